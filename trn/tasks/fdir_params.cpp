/**
 * @file fdir_params.cpp
 * @brief The FDIR parameter table's range check.
 */
#include "trn/tasks/fdir_params.hpp"

namespace trn::tasks {

const FdirParam* fdir_param_out_of_range(const ImageConfig& cfg) noexcept {
  for (const FdirParam& p : kFdirParams) {
    if (p.get == nullptr) {
      continue;
    }
    const std::uint32_t v = p.get(cfg);
    if (v < p.min || v > p.max) {
      return &p;
    }
  }
  return nullptr;
}

}  // namespace trn::tasks
