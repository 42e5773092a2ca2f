/**
 * @file fdir_params_doc.cpp
 * @brief The FDIR parameter table as Markdown rows.
 */
#include "tools/common/mission/fdir_params_doc.hpp"

#include "trn/tasks/fdir_params.hpp"

#include <sstream>

namespace tools {

std::string fdir_params_markdown() {
  trn::tasks::ImageConfig defaults{};
  trn::tasks::wire_image(defaults, trn::tasks::kTile64Deployment);
  std::ostringstream o;
  for (const trn::tasks::FdirParam& p : trn::tasks::kFdirParams) {
    const bool field = p.get != nullptr;
    o << "| `" << p.name << "` | " << (field ? p.get(defaults) : p.value) << " | ";
    if (field) {
      o << p.min << ".." << p.max;
    } else {
      o << "constant";
    }
    o << " | " << p.unit << " | " << p.meaning << " |\n";
  }
  return o.str();
}

}  // namespace tools
