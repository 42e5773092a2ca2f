/**
 * @file fine.cpp
 * @brief Fine-stage landmark match (see fine.hpp).
 */
#include "trn/vision/fine.hpp"

namespace trn::vision {

Status fine_match(ConstImageU8 tmpl, ConstImageU8 window, const QualityParams& q, FineWorkspace& ws,
                  MatchResult& out, bsp::Work& work) noexcept {
  out = MatchResult{};
  if (tmpl.width > kFineMaxTemplatePx || tmpl.height > kFineMaxTemplatePx) {
    return Status::kTooLarge;
  }
  return correlate(tmpl, window, q, ws.buffers(), out, work);
}

}  // namespace trn::vision
