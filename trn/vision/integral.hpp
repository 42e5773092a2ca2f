/**
 * @file integral.hpp
 * @brief Integral images of pixel values and of their squares, for O(1) window sums.
 *
 * For an image I of w x h, the tables hold (w + 1) x (h + 1) entries with a
 * zero first row and column: S(x, y) = sum of I over columns < x and rows < y.
 * Any rectangle's sum then takes four lookups.
 *
 * Overflow: a sum of values is at most 255 * w * h. With at most
 * kIntegralMaxPixels = 2^24 pixels (4096 x 4096) that is 255 * 2^24 < 2^32, so
 * the value table is uint32 (static_assert below). A sum of squares reaches
 * 65025 * 2^24 ~ 1.1e12 > 2^32, so the square table is uint64 (bound 2^64 is far).
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "trn/vision/image.hpp"
#include "trn/vision/status.hpp"

#include <cstddef>
#include <cstdint>

namespace trn::vision {

/** Largest image (pixel count) an integral image may cover. */
inline constexpr std::int64_t kIntegralMaxPixels = std::int64_t{4096} * 4096;
static_assert(255ULL * static_cast<std::uint64_t>(kIntegralMaxPixels) <= 0xFFFFFFFFULL,
              "value sums must fit uint32");
static_assert(65025ULL * static_cast<std::uint64_t>(kIntegralMaxPixels) < (1ULL << 63U),
              "square sums must fit uint64 with margin");

/** Read-only access to a built integral image (tables of (width+1) x (height+1)). */
struct IntegralRef {
  const std::uint32_t* sum = nullptr;
  const std::uint64_t* sum_sq = nullptr;
  std::int32_t width = 0;   ///< width of the image it was built from, px
  std::int32_t height = 0;  ///< height of the image it was built from, px

  /** Sum of pixel values over the w x h rectangle at (x, y). Pre: rectangle inside the image. */
  std::uint32_t rect_sum(std::int32_t x, std::int32_t y, std::int32_t w, std::int32_t h) const noexcept {
    const std::int64_t s = width + 1;
    const std::int64_t top = static_cast<std::int64_t>(y) * s;
    const std::int64_t bot = static_cast<std::int64_t>(y + h) * s;
    // Unsigned wrap-around cancels exactly: the true result is in range.
    return sum[bot + x + w] - sum[bot + x] - sum[top + x + w] + sum[top + x];
  }

  /** Sum of squared pixel values over the w x h rectangle at (x, y). Pre: rectangle inside. */
  std::uint64_t rect_sum_sq(std::int32_t x, std::int32_t y, std::int32_t w, std::int32_t h) const noexcept {
    const std::int64_t s = width + 1;
    const std::int64_t top = static_cast<std::int64_t>(y) * s;
    const std::int64_t bot = static_cast<std::int64_t>(y + h) * s;
    return sum_sq[bot + x + w] - sum_sq[bot + x] - sum_sq[top + x + w] + sum_sq[top + x];
  }
};

/**
 * Builds the integral tables of @p image into caller buffers.
 * @param sum, sum_sq buffers of at least @p capacity entries each
 * @param capacity entries available in each buffer; needs (w + 1) * (h + 1)
 * @param work incremented by the adds and memory words of the pass
 * @return kBadInput for an invalid view or null buffers, kTooLarge when the
 *         image exceeds capacity or kIntegralMaxPixels; @p out is set only on kOk.
 */
Status build_integral(ConstImageU8 image, std::uint32_t* sum, std::uint64_t* sum_sq, std::int64_t capacity,
                      IntegralRef& out, bsp::Work& work) noexcept;

/** Integral tables sized for images up to MaxW x MaxH; place large ones in static or carved memory. */
template <std::int32_t MaxW, std::int32_t MaxH>
class FixedIntegral {
  static_assert(static_cast<std::int64_t>(MaxW) * MaxH <= kIntegralMaxPixels, "beyond the overflow proof");

 public:
  static constexpr std::int64_t kEntries = static_cast<std::int64_t>(MaxW + 1) * (MaxH + 1);

  /** Builds over @p image; see build_integral(). */
  Status build(ConstImageU8 image, bsp::Work& work) noexcept {
    return build_integral(image, sum_, sum_sq_, kEntries, ref_, work);
  }

  /** The tables of the last successful build. */
  const IntegralRef& ref() const noexcept { return ref_; }

 private:
  std::uint32_t sum_[static_cast<std::size_t>(kEntries)]{};
  std::uint64_t sum_sq_[static_cast<std::size_t>(kEntries)]{};
  IntegralRef ref_{};
};

}  // namespace trn::vision
