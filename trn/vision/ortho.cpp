/**
 * @file ortho.cpp
 * @brief Orthorectifying resampling onto a terrain-following map grid (see ortho.hpp).
 */
#include "trn/vision/ortho.hpp"

namespace trn::vision {

namespace {

/** Mean of the sub x sub samples of destination pixel (x, y) lifted by dz; false when one is missing. */
bool sample_pixel(ConstImageU8 src, const Homography& hm, const double g[3], double x, double y, double dz,
                  std::int32_t sub, std::uint8_t& value) noexcept {
  const double* h = hm.h;
  const double step = 1.0 / sub;
  const double first = 0.5 * step - 0.5;
  std::uint32_t sum = 0U;
  for (std::int32_t j = 0; j < sub; ++j) {
    const double ys = y + first + j * step;
    for (std::int32_t i = 0; i < sub; ++i) {
      const double xs = x + first + i * step;
      const double w = h[6] * xs + h[7] * ys + h[8] + dz * g[2];
      if (!(w > 1e-9)) {
        return false;
      }
      const double iw = 1.0 / w;
      const double u = (h[0] * xs + h[1] * ys + h[2] + dz * g[0]) * iw;
      const double v = (h[3] * xs + h[4] * ys + h[5] + dz * g[1]) * iw;
      std::uint8_t s = 0U;
      if (!sample_bilinear(src, u, v, s)) {
        return false;
      }
      sum += s;
    }
  }
  const auto n = static_cast<std::uint32_t>(sub * sub);
  value = static_cast<std::uint8_t>((sum + n / 2U) / n);
  return true;
}

}  // namespace

Status warp_terrain(ConstImageU8 src, const Homography& h, const double g[3], const GridHeights& heights,
                    std::int32_t sub, ImageU8 dst, std::uint8_t fill, std::int32_t& outside_px,
                    bsp::Work& work) noexcept {
  outside_px = 0;
  if (!src.valid() || !dst.valid() || g == nullptr || heights.first == nullptr || heights.stride < dst.width ||
      sub < 1 || sub > kMaxSubsamples) {
    return Status::kBadInput;
  }
  for (std::int32_t y = 0; y < dst.height; ++y) {
    const std::int16_t* hz = heights.first + static_cast<std::int64_t>(y) * heights.stride;
    std::uint8_t* out = dst.row(y);
    for (std::int32_t x = 0; x < dst.width; ++x) {
      const double dz = hz[x] * heights.scale_m - heights.plane_z_m;
      if (!sample_pixel(src, h, g, x, y, dz, sub, out[x])) {
        out[x] = fill;
        ++outside_px;
      }
    }
  }
  const auto px = static_cast<std::uint64_t>(dst.width) * static_cast<std::uint64_t>(dst.height);
  const auto samples = px * static_cast<std::uint64_t>(sub * sub);
  work.flops += px * 2U + samples * 28U;  // lift 6 + transform 12 + bilinear 10 per sample
  work.fdivs += samples;
  work.int_ops += px * 4U + samples * 9U;
  work.mem_words += px / 2U + samples * 5U / 4U + 1U;
  return Status::kOk;
}

}  // namespace trn::vision
