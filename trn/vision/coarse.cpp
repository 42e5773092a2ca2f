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

Status coarse_match(ConstImageU8 map_region, ConstImageU8 image, const CoarseParams& p, CoarseWorkspace& ws,
                    CoarseResult& out, bsp::Work& work) noexcept {
  out = CoarseResult{};
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
  const std::int32_t tx0 = (small.width - p.template_px) / 2;
  const std::int32_t ty0 = (small.height - p.template_px) / 2;
  const ConstImageU8 tmpl = small.sub(tx0, ty0, p.template_px, p.template_px);
  if (!tmpl.valid()) {
    return Status::kBadInput;
  }
  CorrelatorBuffers buf = ws.corr.buffers();
  buf.transform = ws.transform.buffers();
  st = correlate(tmpl, ws.map_small.cview(), p.quality, buf, out.match, work, CorrelationTaps{}, p.method);
  if (st != Status::kOk) {
    return st;
  }
  // Image coarse pixel i sits at map coarse pixel i + offset, and a coarse offset is
  // `factor` full-resolution pixels because both grids start at their own pixel 0.
  out.x_px = (out.match.x_px - tx0) * p.factor;
  out.y_px = (out.match.y_px - ty0) * p.factor;
  return Status::kOk;
}

}  // namespace trn::vision
