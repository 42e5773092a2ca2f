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

/** Records one computation's checks (@p bad) in the outcome; @return whether it passed. */
bool attempt_passed(CorrelationCheck bad, bool& check_failed, CorrelationCheck& first_check) noexcept {
  check_failed = bad != CorrelationCheck::kNone;
  if (check_failed && first_check == CorrelationCheck::kNone) {
    first_check = bad;
  }
  return !check_failed;
}

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
    return ncc_surface(j.tmpl, j.stats, j.window, integral, j.surface, j.flags, flat_windows, work, &check, j.buf.wide);
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
    if (attempt_passed(bad, out.check_failed, out.first_check)) {
      break;
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

namespace {

/** Whether @p tmpl fits @p window and is not flat: kOk with its statistics in @p stats. */
Status band_template(ConstImageU8 tmpl, ConstImageU8 window, TemplateStats& stats, bsp::Work& work) noexcept {
  if (!tmpl.valid() || !window.valid() || tmpl.width > window.width || tmpl.height > window.height) {
    return Status::kBadInput;
  }
  const Status st = template_stats(tmpl, stats, work);
  if (st != Status::kOk) {
    return st;
  }
  return stats.flat ? Status::kBadInput : Status::kOk;
}

/**
 * Every existing score of the 3 x 3 neighbourhood of @p p computed again alone,
 * over the window of that neighbourhood only (its integral in @p scratch), and
 * compared bit for bit with @p surface.
 */
Status neighbourhood_check(ConstImageU8 tmpl, const TemplateStats& stats, ConstImageU8 window, ConstImageF32 surface,
                           const Peak& p, const CorrelatorBuffers& scratch, CorrelationCheck& bad,
                           bsp::Work& work) noexcept {
  bad = CorrelationCheck::kNone;
  const std::int32_t x0 = p.ix - 1 < 0 ? 0 : p.ix - 1;
  const std::int32_t y0 = p.iy - 1 < 0 ? 0 : p.iy - 1;
  const std::int32_t x1 = p.ix + 1 >= surface.width ? surface.width - 1 : p.ix + 1;
  const std::int32_t y1 = p.iy + 1 >= surface.height ? surface.height - 1 : p.iy + 1;
  if (x1 < x0 || y1 < y0) {
    return Status::kOk;  // no peak on the surface: nothing the refinement reads
  }
  const ConstImageU8 sub = window.sub(x0, y0, x1 - x0 + tmpl.width, y1 - y0 + tmpl.height);
  IntegralRef integral;
  const Status st = build_integral(sub, scratch.sum, scratch.sum_sq, scratch.integral_entries, integral, work);
  if (st != Status::kOk) {
    return st;
  }
  for (std::int32_t y = y0; y <= y1; ++y) {
    for (std::int32_t x = x0; x <= x1; ++x) {
      const float again = ncc_score_at(tmpl, stats, sub, integral, x - x0, y - y0, work);
      if (std::bit_cast<std::uint32_t>(again) != std::bit_cast<std::uint32_t>(surface.at(x, y))) {
        bad = CorrelationCheck::kPeakScore;
        return Status::kOk;
      }
    }
  }
  return Status::kOk;
}

}  // namespace

Status correlate_band(ConstImageU8 tmpl, ConstImageU8 window, std::int32_t row0, std::int32_t rows,
                      const BandBuffers& buf, BandResult& out, bsp::Work& work, const CorrelationTaps& taps) noexcept {
  out = BandResult{};
  if (buf.sum == nullptr || buf.sum_sq == nullptr || buf.surface == nullptr || buf.flags == nullptr) {
    return Status::kBadInput;
  }
  TemplateStats stats;
  Status st = band_template(tmpl, window, stats, work);
  if (st != Status::kOk) {
    return st;
  }
  const std::int32_t sw = window.width - tmpl.width + 1;
  const std::int32_t sh = window.height - tmpl.height + 1;
  if (row0 < 0 || rows < 1 || row0 > sh - rows) {
    return Status::kBadInput;
  }
  if (static_cast<std::int64_t>(sw) * rows > buf.surface_values) {
    return Status::kTooLarge;
  }
  const ConstImageU8 band_window = window.sub(0, row0, window.width, rows + tmpl.height - 1);
  const ImageF32 surface{buf.surface, sw, rows, sw};
  const ImageU8 flags{buf.flags, sw, rows, sw};
  out.width = sw;
  out.rows = rows;
  for (std::uint32_t attempt = 0U; attempt <= kCorrelationMaxRecompute; ++attempt) {
    out.recomputes = attempt;
    IntegralRef integral;
    st = build_integral(band_window, buf.sum, buf.sum_sq, buf.integral_entries, integral, work);
    if (st != Status::kOk) {
      return st;
    }
    NccCheck check;
    check.publish = taps.publish;
    check.dot_channel = taps.dot_channel;
    st = ncc_surface(tmpl, stats, band_window, integral, surface, flags, out.flat_windows, work, &check);
    if (st != Status::kOk) {
      return st;
    }
    if (taps.publish != nullptr) {
      (void)taps.publish(taps.surface_channel, surface.data, static_cast<std::size_t>(sw) * static_cast<std::size_t>(rows) * sizeof(float));
    }
    const std::int64_t ref = ncc_dot_checksum(tmpl, integral, sw, rows, work);
    work.int_ops += 1U;
    CorrelationCheck bad = CorrelationCheck::kNone;
    if (ref != check.dot_sum) {
      bad = CorrelationCheck::kDotSum;
    } else if (surface_digest(surface.as_const(), work) != check.surface_sum) {
      bad = CorrelationCheck::kSurface;
    }
    out.digest = check.surface_sum;
    if (attempt_passed(bad, out.check_failed, out.first_check)) {
      break;
    }
  }
  return Status::kOk;
}

Status correlate_gathered(ConstImageU8 tmpl, ConstImageU8 window, const QualityParams& q, ConstImageF32 surface,
                          std::uint64_t digest, std::int32_t flat_windows, std::uint32_t recomputes,
                          const CorrelatorBuffers& scratch, MatchResult& out, bsp::Work& work) noexcept {
  out = MatchResult{};
  TemplateStats stats;
  const Status st = band_template(tmpl, window, stats, work);
  if (st != Status::kOk) {
    return st;
  }
  const std::int32_t sw = window.width - tmpl.width + 1;
  const std::int32_t sh = window.height - tmpl.height + 1;
  if (!surface.valid() || surface.width != sw || surface.height != sh || scratch.sum == nullptr ||
      scratch.sum_sq == nullptr) {
    return Status::kBadInput;
  }
  out.flat_windows = flat_windows;
  out.recomputes = recomputes;
  out.surface = surface;
  CorrelationCheck bad = surface_digest(surface, work) != digest ? CorrelationCheck::kSurface : CorrelationCheck::kNone;
  if (bad == CorrelationCheck::kNone) {
    out.peak = find_peak(surface, q, work);
    const Status nst = neighbourhood_check(tmpl, stats, window, surface, out.peak, scratch, bad, work);
    if (nst != Status::kOk) {
      return nst;
    }
  }
  out.check_failed = bad != CorrelationCheck::kNone;
  out.first_check = bad;
  if (out.check_failed) {
    out.peak.reason = Reject::kCheckFailed;
  } else if (out.flat_windows == sw * sh) {
    out.peak.reason = Reject::kFlatWindow;
  }
  out.x_px = out.peak.x_px;
  out.y_px = out.peak.y_px;
  return Status::kOk;
}

}  // namespace trn::vision
