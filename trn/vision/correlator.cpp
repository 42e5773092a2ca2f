/**
 * @file correlator.cpp
 * @brief One template over one window (see correlator.hpp).
 */
#include "trn/vision/correlator.hpp"

namespace trn::vision {

Status correlate(ConstImageU8 tmpl, ConstImageU8 window, const QualityParams& q, const CorrelatorBuffers& buf,
                 MatchResult& out, bsp::Work& work) noexcept {
  out = MatchResult{};
  if (!tmpl.valid() || !window.valid() || tmpl.width > window.width || tmpl.height > window.height ||
      buf.sum == nullptr || buf.surface == nullptr || buf.flags == nullptr) {
    return Status::kBadInput;
  }
  if (window.width > buf.max_window_px || window.height > buf.max_window_px) {
    return Status::kTooLarge;
  }
  TemplateStats stats;
  Status st = template_stats(tmpl, stats, work);
  if (st != Status::kOk) {
    return st;
  }
  if (stats.flat) {
    out.peak.reason = Reject::kFlatTemplate;
    return Status::kOk;
  }
  IntegralRef integral;
  st = build_integral(window, buf.sum, buf.sum_sq, buf.integral_entries, integral, work);
  if (st != Status::kOk) {
    return st;
  }
  const std::int32_t sw = window.width - tmpl.width + 1;
  const std::int32_t sh = window.height - tmpl.height + 1;
  const ImageF32 surface{buf.surface, sw, sh, sw};
  const ImageU8 flags{buf.flags, sw, sh, sw};
  st = ncc_surface(tmpl, stats, window, integral, surface, flags, out.flat_windows, work);
  if (st != Status::kOk) {
    return st;
  }
  out.surface = surface.as_const();
  out.peak = find_peak(out.surface, q, work);
  if (out.flat_windows == sw * sh) {
    out.peak.reason = Reject::kFlatWindow;
  }
  out.x_px = out.peak.x_px;
  out.y_px = out.peak.y_px;
  return Status::kOk;
}

}  // namespace trn::vision
