/**
 * @file correlator.cpp
 * @brief One template over one window, with the surface and its peak checked (see correlator.hpp).
 */
#include "trn/vision/correlator.hpp"

#include "fdir/abft.hpp"

#include <bit>

namespace trn::vision {

static_assert(kCorrelationMaxRecompute == fdir::kAbftMaxRecompute, "one recomputation rule for checked results");

namespace {

/** One correlation's inputs and outputs, for its computations and checks. */
struct SurfaceJob {
  ConstImageU8 tmpl;
  ConstImageU8 window;
  const TemplateStats& stats;
  const CorrelatorBuffers& buf;
  const CorrelationTaps& taps;
  CorrelationMethod method;
  ImageF32 surface;
  ImageU8 flags;
};

/** The surface of @p j by its method, each dot product published and summed into @p check. */
Status surface_of(const SurfaceJob& j, const IntegralRef& integral, NccCheck& check, std::int32_t& flat_windows,
                  bsp::Work& work) noexcept {
  if (j.method == CorrelationMethod::kSpatial) {
    return ncc_surface(j.tmpl, j.stats, j.window, integral, j.surface, j.flags, flat_windows, work, &check);
  }
  ImageView<const std::uint32_t> dots;
  const Status st = transform_dots(j.tmpl, j.window, j.buf.transform, dots, work);
  if (st != Status::kOk) {
    return st;
  }
  return ncc_surface_from_dots(j.stats, integral, dots, j.surface, j.flags, flat_windows, work, &check);
}

/** Whether @p method can run on @p buf for @p window: kOk, or why not. */
Status method_fits(CorrelationMethod method, const CorrelatorBuffers& buf, ConstImageU8 window) noexcept {
  if (method == CorrelationMethod::kSpatial) {
    return Status::kOk;
  }
  if (method != CorrelationMethod::kTransform || buf.transform.window_plane == nullptr ||
      buf.transform.template_plane == nullptr || buf.transform.scaled == nullptr) {
    return Status::kBadInput;
  }
  const bool fits = window.width <= buf.transform.max_side && window.height <= buf.transform.max_side &&
                    window.width <= kNttMaxSide && window.height <= kNttMaxSide;
  return fits ? Status::kOk : Status::kTooLarge;
}

/**
 * Builds the window's integral image and the surface (publishing each dot
 * product, then the surface), and holds the sum of the dot products against
 * the integral image's checksum; @p bad says kDotSum when they differ.
 */
Status compute_surface(const SurfaceJob& j, IntegralRef& integral, NccCheck& check, std::int32_t& flat_windows,
                       CorrelationCheck& bad, bsp::Work& work) noexcept {
  Status st = build_integral(j.window, j.buf.sum, j.buf.sum_sq, j.buf.integral_entries, integral, work);
  if (st != Status::kOk) {
    return st;
  }
  check.publish = j.taps.publish;
  check.dot_channel = j.taps.dot_channel;
  st = surface_of(j, integral, check, flat_windows, work);
  if (st != Status::kOk) {
    return st;
  }
  if (j.taps.publish != nullptr) {
    const auto values = static_cast<std::size_t>(j.surface.width) * static_cast<std::size_t>(j.surface.height);
    (void)j.taps.publish(j.taps.surface_channel, j.surface.data, values * sizeof(float));
  }
  const std::int64_t ref = ncc_dot_checksum(j.tmpl, integral, j.surface.width, j.surface.height, work);
  work.int_ops += 1U;
  bad = ref == check.dot_sum ? CorrelationCheck::kNone : CorrelationCheck::kDotSum;
  return Status::kOk;
}

/**
 * After the peak search: the surface's digest again, and every existing value
 * of the peak's 3 x 3 neighbourhood (what the refinement reads) computed alone
 * and compared bit for bit.
 */
CorrelationCheck verify_peak(const SurfaceJob& j, const IntegralRef& integral, const NccCheck& check,
                             const Peak& p, bsp::Work& work) noexcept {
  const ConstImageF32 s = j.surface.as_const();
  if (surface_digest(s, work) != check.surface_sum) {
    return CorrelationCheck::kSurface;
  }
  for (std::int32_t dy = -1; dy <= 1; ++dy) {
    for (std::int32_t dx = -1; dx <= 1; ++dx) {
      const std::int32_t x = p.ix + dx;
      const std::int32_t y = p.iy + dy;
      if (!s.contains(x, y)) {
        continue;
      }
      const float again = ncc_score_at(j.tmpl, j.stats, j.window, integral, x, y, work);
      if (std::bit_cast<std::uint32_t>(again) != std::bit_cast<std::uint32_t>(s.at(x, y))) {
        return CorrelationCheck::kPeakScore;
      }
    }
  }
  return CorrelationCheck::kNone;
}

/** The surface and its peak, computed and checked, recomputed while wrong (bounded); fills @p out. */
Status checked_surface(const SurfaceJob& j, const QualityParams& q, MatchResult& out, bsp::Work& work) noexcept {
  IntegralRef integral;
  NccCheck check;
  for (std::uint32_t attempt = 0U; attempt <= kCorrelationMaxRecompute; ++attempt) {
    out.recomputes = attempt;
    CorrelationCheck bad = CorrelationCheck::kNone;
    const Status st = compute_surface(j, integral, check, out.flat_windows, bad, work);
    if (st != Status::kOk) {
      return st;
    }
    if (bad == CorrelationCheck::kNone) {
      out.peak = find_peak(j.surface.as_const(), q, work);
      bad = verify_peak(j, integral, check, out.peak, work);
    }
    out.check_failed = bad != CorrelationCheck::kNone;
    if (!out.check_failed) {
      break;
    }
    if (out.first_check == CorrelationCheck::kNone) {
      out.first_check = bad;
    }
  }
  return Status::kOk;
}

}  // namespace

Status correlate(ConstImageU8 tmpl, ConstImageU8 window, const QualityParams& q, const CorrelatorBuffers& buf,
                 MatchResult& out, bsp::Work& work, const CorrelationTaps& taps, CorrelationMethod method) noexcept {
  out = MatchResult{};
  if (!tmpl.valid() || !window.valid() || tmpl.width > window.width || tmpl.height > window.height ||
      buf.sum == nullptr || buf.surface == nullptr || buf.flags == nullptr) {
    return Status::kBadInput;
  }
  if (window.width > buf.max_window_px || window.height > buf.max_window_px) {
    return Status::kTooLarge;
  }
  const Status fit = method_fits(method, buf, window);
  if (fit != Status::kOk) {
    return fit;
  }
  TemplateStats stats;
  const Status st = template_stats(tmpl, stats, work);
  if (st != Status::kOk) {
    return st;
  }
  if (stats.flat) {
    out.peak.reason = Reject::kFlatTemplate;
    return Status::kOk;
  }
  const std::int32_t sw = window.width - tmpl.width + 1;
  const std::int32_t sh = window.height - tmpl.height + 1;
  const SurfaceJob job{tmpl,   window, stats, buf, taps, method, ImageF32{buf.surface, sw, sh, sw},
                       ImageU8{buf.flags, sw, sh, sw}};
  const Status cs = checked_surface(job, q, out, work);
  if (cs != Status::kOk) {
    return cs;
  }
  out.surface = job.surface.as_const();
  if (out.check_failed) {
    out.peak.reason = Reject::kCheckFailed;  // nothing of a surface still wrong is used
  } else if (out.flat_windows == sw * sh) {
    out.peak.reason = Reject::kFlatWindow;
  }
  out.x_px = out.peak.x_px;
  out.y_px = out.peak.y_px;
  return Status::kOk;
}

}  // namespace trn::vision
