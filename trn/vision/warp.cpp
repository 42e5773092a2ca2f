/**
 * @file warp.cpp
 * @brief Bilinear affine and homography resampling (see warp.hpp).
 */
#include "trn/vision/warp.hpp"

#include <cmath>

namespace trn::vision {

bool invert_affine(const Affine2& m, Affine2& inv) noexcept {
  const double det = m.a[0] * m.a[4] - m.a[1] * m.a[3];
  if (!(std::fabs(det) > 1e-12)) {
    return false;
  }
  const double id = 1.0 / det;
  inv.a[0] = m.a[4] * id;
  inv.a[1] = -m.a[1] * id;
  inv.a[3] = -m.a[3] * id;
  inv.a[4] = m.a[0] * id;
  inv.a[2] = -(inv.a[0] * m.a[2] + inv.a[1] * m.a[5]);
  inv.a[5] = -(inv.a[3] * m.a[2] + inv.a[4] * m.a[5]);
  return true;
}

Status warp_affine(ConstImageU8 src, const Affine2& dst_to_src, ImageU8 dst, std::uint8_t fill,
                   std::int32_t& outside_px, bsp::Work& work) noexcept {
  outside_px = 0;
  if (!src.valid() || !dst.valid()) {
    return Status::kBadInput;
  }
  const double* a = dst_to_src.a;
  for (std::int32_t y = 0; y < dst.height; ++y) {
    std::uint8_t* out = dst.row(y);
    for (std::int32_t x = 0; x < dst.width; ++x) {
      const double xs = a[0] * x + a[1] * y + a[2];
      const double ys = a[3] * x + a[4] * y + a[5];
      if (!sample_bilinear(src, xs, ys, out[x])) {
        out[x] = fill;
        ++outside_px;
      }
    }
  }
  const auto px = static_cast<std::uint64_t>(dst.width) * static_cast<std::uint64_t>(dst.height);
  work.flops += px * 18U;  // transform 8, bilinear 10
  work.int_ops += px * 8U;
  work.mem_words += px * 5U / 4U + 1U;
  return Status::kOk;
}

Status warp_homography(ConstImageU8 src, const Homography& dst_to_src, ImageU8 dst, std::uint8_t fill,
                       std::int32_t& outside_px, bsp::Work& work) noexcept {
  outside_px = 0;
  if (!src.valid() || !dst.valid()) {
    return Status::kBadInput;
  }
  const double* h = dst_to_src.h;
  for (std::int32_t y = 0; y < dst.height; ++y) {
    std::uint8_t* out = dst.row(y);
    for (std::int32_t x = 0; x < dst.width; ++x) {
      const double w = h[6] * x + h[7] * y + h[8];
      const bool in_front = w > 1e-12;
      const double xs = in_front ? (h[0] * x + h[1] * y + h[2]) / w : -1.0;
      const double ys = in_front ? (h[3] * x + h[4] * y + h[5]) / w : -1.0;
      if (!sample_bilinear(src, xs, ys, out[x])) {
        out[x] = fill;
        ++outside_px;
      }
    }
  }
  const auto px = static_cast<std::uint64_t>(dst.width) * static_cast<std::uint64_t>(dst.height);
  work.flops += px * 22U;
  work.fdivs += px * 2U;
  work.int_ops += px * 8U;
  work.mem_words += px * 5U / 4U + 1U;
  return Status::kOk;
}

}  // namespace trn::vision
