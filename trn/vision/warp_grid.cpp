/**
 * @file warp_grid.cpp
 * @brief Grid homography warp: exact nodes, fixed-point cells, integer bilinear sampling (see warp_grid.hpp).
 */
#include "trn/vision/warp_grid.hpp"

#include <cmath>

namespace trn::vision {

namespace detail {

GridShape grid_shape(std::int32_t grid_px, std::int32_t width, std::int32_t height) noexcept {
  GridShape s;
  if (width <= 0 || height <= 0) {
    return s;
  }
  for (std::int32_t g = kGridWarpMinPx, shift = 2; g <= kGridWarpMaxPx; g *= 2, ++shift) {
    if (g == grid_px) {
      s.shift = shift;
    }
  }
  static_assert(kGridWarpMinPx == 4, "the loop above starts at shift 2");
  if (s.shift == 0) {
    return s;
  }
  s.nodes = (width - 1) / grid_px + 2;
  s.status = s.nodes <= kGridWarpMaxNodes ? Status::kOk : Status::kTooLarge;
  return s;
}

void grid_node_row(const Homography& h, const GridShape& shape, std::int32_t node_y, GridNodeRow& row,
                   bsp::Work& work) noexcept {
  const double* m = h.h;
  const double scale = static_cast<double>(std::int32_t{1} << kGridFracBits);
  const double y = node_y;
  for (std::int32_t k = 0; k < shape.nodes; ++k) {
    const double x = static_cast<double>(k) * static_cast<double>(std::int32_t{1} << shape.shift);
    const double w = m[6] * x + m[7] * y + m[8];
    row.x[k] = kGridNoNode;
    row.y[k] = 0;
    if (!(w > 1e-12)) {
      continue;  // behind the camera: the cells around it are outside
    }
    // The same expressions as warp_homography(), so a node is the exact warp's coordinate.
    const double xs = (m[0] * x + m[1] * y + m[2]) / w;
    const double ys = (m[3] * x + m[4] * y + m[5]) / w;
    if (!(std::fabs(xs) < kGridMaxCoordPx && std::fabs(ys) < kGridMaxCoordPx)) {
      continue;
    }
    row.x[k] = static_cast<std::int32_t>(std::lround(xs * scale));
    row.y[k] = static_cast<std::int32_t>(std::lround(ys * scale));
  }
  const auto n = static_cast<std::uint64_t>(shape.nodes);
  work.flops += n * 22U;  // three rows of H (12), two range checks, two scalings and roundings (8), x (2)
  work.fdivs += n * 2U;
  work.mem_words += n * 2U;
}

}  // namespace detail

namespace {

/** Integer bilinear sampling of one destination pixel from its Q16 source coordinate. */
class BilinearSink {
 public:
  BilinearSink(ConstImageU8 src, ImageU8 dst, std::uint8_t fill) noexcept
      : src_(src),
        dst_(dst),
        fill_(fill),
        x_max_(static_cast<std::int32_t>((src.width - 1) << kGridWeightBits)),
        y_max_(static_cast<std::int32_t>((src.height - 1) << kGridWeightBits)) {}

  void operator()(std::int32_t x, std::int32_t y, std::int32_t xq, std::int32_t yq, bool usable) noexcept {
    constexpr std::int32_t kDrop = kGridFracBits - kGridWeightBits;
    constexpr std::int32_t kMask = (std::int32_t{1} << kGridWeightBits) - 1;
    constexpr std::int32_t kRound = std::int32_t{1} << (2 * kGridWeightBits - 1);
    std::uint8_t& out = dst_.row(y)[x];
    // The coordinate rounded to 2^-kGridWeightBits px; the exact warp's rule on it: the last
    // row/column is inside only at a zero weight, which then needs no right/lower neighbour.
    const std::int32_t qx = (xq + (std::int32_t{1} << (kDrop - 1))) >> kDrop;
    const std::int32_t qy = (yq + (std::int32_t{1} << (kDrop - 1))) >> kDrop;
    if (!usable || qx < 0 || qy < 0 || qx > x_max_ || qy > y_max_) {
      out = fill_;
      ++outside_;
      return;
    }
    const std::int32_t fx = qx & kMask;
    const std::int32_t fy = qy & kMask;
    const std::uint8_t* p = src_.row(qy >> kGridWeightBits) + (qx >> kGridWeightBits);
    const std::int32_t dx = fx != 0 ? 1 : 0;
    const std::int32_t dy = fy != 0 ? src_.stride : 0;
    const std::int32_t p00 = p[0];
    const std::int32_t p01 = p[dx];
    const std::int32_t p10 = p[dy];
    const std::int32_t p11 = p[dy + dx];
    // top, bot < 2^18; v < 2^28: no overflow. v >= 0, so rounding half up is lround's rule.
    const std::int32_t top = (p00 << kGridWeightBits) + fx * (p01 - p00);
    const std::int32_t bot = (p10 << kGridWeightBits) + fx * (p11 - p10);
    const std::int32_t v = (top << kGridWeightBits) + fy * (bot - top);
    out = static_cast<std::uint8_t>((v + kRound) >> (2 * kGridWeightBits));
  }

  [[nodiscard]] std::int32_t outside() const noexcept { return outside_; }

 private:
  ConstImageU8 src_;
  ImageU8 dst_;
  std::uint8_t fill_;
  std::int32_t x_max_;
  std::int32_t y_max_;
  std::int32_t outside_ = 0;
};

}  // namespace

Status warp_homography_grid(ConstImageU8 src, const Homography& dst_to_src, std::int32_t grid_px, ImageU8 dst,
                            std::uint8_t fill, std::int32_t& outside_px, bsp::Work& work) noexcept {
  outside_px = 0;
  if (!src.valid() || !dst.valid() || static_cast<double>(src.width) > kGridMaxCoordPx ||
      static_cast<double>(src.height) > kGridMaxCoordPx) {
    return Status::kBadInput;
  }
  const detail::GridShape shape = detail::grid_shape(grid_px, dst.width, dst.height);
  if (shape.status != Status::kOk) {
    return shape.status;
  }
  BilinearSink sink(src, dst, fill);
  detail::walk_grid(dst_to_src, shape, dst.width, dst.height, sink, work);
  outside_px = sink.outside();
  const auto px = static_cast<std::uint64_t>(dst.width) * static_cast<std::uint64_t>(dst.height);
  // Per pixel, every pixel charged the inside path: rounding 4, bounds 4, split 4, neighbour
  // offsets 3, address 1, top 3, bottom 3, value 5; the row address and three weights as MACs;
  // four source bytes loaded and one stored, each a memory access.
  work.int_ops += px * 27U;
  work.int_macs += px * 4U;
  work.mem_words += px * 5U;
  return Status::kOk;
}

}  // namespace trn::vision
