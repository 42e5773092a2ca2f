/**
 * @file coarse.cpp
 * @brief Coarse-stage search on decimated data (see coarse.hpp).
 */
#include "trn/vision/coarse.hpp"

namespace trn::vision {

namespace detail {
namespace {

/** Decimates @p in into @p dst after sizing it; kTooLarge when it does not fit. */
template <std::int32_t W, std::int32_t H>
Status decimate_into(ConstImageU8 in, std::int32_t factor, FixedImage<std::uint8_t, W, H>& dst,
                     bsp::Work& work) noexcept {
  if (!dst.resize(in.width / factor, in.height / factor)) {
    return (in.width / factor > W || in.height / factor > H) ? Status::kTooLarge : Status::kBadInput;
  }
  return downsample_box(in, factor, dst.view(), work);
}

}  // namespace
}  // namespace detail

Status downsample_box(ConstImageU8 in, std::int32_t factor, ImageU8 out, bsp::Work& work) noexcept {
  if (!in.valid() || !out.valid() || factor < 1 || factor > kCoarseMaxFactor ||
      out.width != in.width / factor || out.height != in.height / factor) {
    return Status::kBadInput;
  }
  const auto area = static_cast<std::uint32_t>(factor * factor);
  for (std::int32_t y = 0; y < out.height; ++y) {
    std::uint8_t* dst = out.row(y);
    for (std::int32_t x = 0; x < out.width; ++x) {
      std::uint32_t s = 0U;  // <= 255 * 16 * 16: no overflow
      for (std::int32_t j = 0; j < factor; ++j) {
        const std::uint8_t* src = in.row(y * factor + j) + static_cast<std::int64_t>(x) * factor;
        for (std::int32_t i = 0; i < factor; ++i) {
          s += src[i];
        }
      }
      dst[x] = static_cast<std::uint8_t>((s + area / 2U) / area);
    }
  }
  const auto px = static_cast<std::uint64_t>(out.width) * static_cast<std::uint64_t>(out.height);
  work.int_ops += px * (area + 2U);
  work.mem_words += px * (area / 4U + 1U);
  return Status::kOk;
}

Status coarse_prepare(ConstImageU8 map_region, ConstImageU8 image, const CoarseParams& p, CoarseWorkspace& ws,
                      CoarsePrepared& out, bsp::Work& work) noexcept {
  out = CoarsePrepared{};
  if (!map_region.valid() || !image.valid() || p.factor < 1 || p.factor > kCoarseMaxFactor ||
      p.template_px < 2 || p.template_px > kCoarseMaxTemplatePx) {
    return Status::kBadInput;
  }
  Status st = detail::decimate_into(map_region, p.factor, ws.map_small, work);
  if (st != Status::kOk) {
    return st;
  }
  st = detail::decimate_into(image, p.factor, ws.image_small, work);
  if (st != Status::kOk) {
    return st;
  }
  const ConstImageU8 small = ws.image_small.cview();
  out.tx0 = (small.width - p.template_px) / 2;
  out.ty0 = (small.height - p.template_px) / 2;
  out.tmpl = small.sub(out.tx0, out.ty0, p.template_px, p.template_px);
  out.window = ws.map_small.cview();
  if (!out.tmpl.valid() || out.tmpl.width > out.window.width || out.tmpl.height > out.window.height) {
    return Status::kBadInput;
  }
  out.surface_w = out.window.width - out.tmpl.width + 1;
  out.surface_h = out.window.height - out.tmpl.height + 1;
  return Status::kOk;
}

void coarse_result(const CoarsePrepared& prep, const CoarseParams& p, const MatchResult& m, CoarseResult& out) noexcept {
  out = CoarseResult{};
  out.match = m;
  // Image coarse pixel i sits at map coarse pixel i + offset, and a coarse offset is
  // `factor` full-resolution pixels because both grids start at their own pixel 0.
  out.x_px = (m.x_px - prep.tx0) * p.factor;
  out.y_px = (m.y_px - prep.ty0) * p.factor;
}

Status coarse_match(ConstImageU8 map_region, ConstImageU8 image, const CoarseParams& p, CoarseWorkspace& ws,
                    CoarseResult& out, bsp::Work& work) noexcept {
  out = CoarseResult{};
  CoarsePrepared prep;
  Status st = coarse_prepare(map_region, image, p, ws, prep, work);
  if (st != Status::kOk) {
    return st;
  }
  CorrelatorBuffers buf = ws.corr.buffers();
  buf.transform = ws.transform.buffers();
  MatchResult m;
  st = correlate(prep.tmpl, prep.window, p.quality, buf, m, work, CorrelationTaps{}, p.method);
  if (st != Status::kOk) {
    out.match = m;
    return st;
  }
  coarse_result(prep, p, m, out);
  return Status::kOk;
}

}  // namespace trn::vision
