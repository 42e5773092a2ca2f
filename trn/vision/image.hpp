/**
 * @file image.hpp
 * @brief Non-owning image views over caller buffers, and fixed-capacity owned images.
 *
 * Every vision algorithm works on views: a pointer to the first pixel, a width,
 * a height and a row stride (in elements, >= width). Views never own memory, so
 * the same code runs over a static buffer, a carved region or a sub-rectangle
 * of a bigger image. FixedImage<T, MaxW, MaxH> owns a buffer sized at compile
 * time and hands out views of its current (smaller or equal) size.
 * Pixel (x, y) is column x, row y; rows are contiguous.
 */
#pragma once

#include <cstddef>
#include <cstdint>

namespace trn::vision {

template <typename T>
struct ImageView {
  T* data = nullptr;        ///< first pixel (row 0, column 0)
  std::int32_t width = 0;   ///< columns, px
  std::int32_t height = 0;  ///< rows, px
  std::int32_t stride = 0;  ///< elements from one row to the next, >= width

  /** True when the view has pixels and a consistent layout. */
  constexpr bool valid() const noexcept {
    return data != nullptr && width > 0 && height > 0 && stride >= width;
  }

  /** Pointer to row @p y. Pre: 0 <= y < height. */
  constexpr T* row(std::int32_t y) const noexcept {
    return data + static_cast<std::int64_t>(y) * stride;
  }

  /** Pixel (x, y). Pre: inside the view. */
  constexpr T& at(std::int32_t x, std::int32_t y) const noexcept { return row(y)[x]; }

  /** True when (x, y) is inside the view. */
  constexpr bool contains(std::int32_t x, std::int32_t y) const noexcept {
    return x >= 0 && y >= 0 && x < width && y < height;
  }

  /**
   * The w x h rectangle whose top-left pixel is (x, y).
   * @return the sub-view, or an invalid (empty) view when the rectangle is not inside.
   */
  constexpr ImageView sub(std::int32_t x, std::int32_t y, std::int32_t w, std::int32_t h) const noexcept {
    if (!valid() || x < 0 || y < 0 || w <= 0 || h <= 0 || w > width - x || h > height - y) {
      return ImageView{};
    }
    return ImageView{row(y) + x, w, h, stride};
  }

  /** Read-only view of the same pixels. */
  constexpr ImageView<const T> as_const() const noexcept {
    return ImageView<const T>{data, width, height, stride};
  }
};

using ImageU8 = ImageView<std::uint8_t>;
using ConstImageU8 = ImageView<const std::uint8_t>;
using ImageI32 = ImageView<std::int32_t>;
using ConstImageI32 = ImageView<const std::int32_t>;
using ImageF32 = ImageView<float>;
using ConstImageF32 = ImageView<const float>;

/**
 * An image that owns a MaxW x MaxH buffer and uses its top-left width x height part.
 * Large instances belong in static storage or carved memory, never on a stack.
 */
template <typename T, std::int32_t MaxW, std::int32_t MaxH>
class FixedImage {
  static_assert(MaxW > 0 && MaxH > 0, "capacity must be positive");
  static_assert(static_cast<std::int64_t>(MaxW) * MaxH <= (std::int64_t{1} << 28), "capacity out of range");

 public:
  static constexpr std::int32_t kMaxWidth = MaxW;
  static constexpr std::int32_t kMaxHeight = MaxH;

  /**
   * Sets the used size; the pixels keep whatever they held.
   * @return false (size unchanged) when w or h is not in 1..capacity.
   */
  constexpr bool resize(std::int32_t w, std::int32_t h) noexcept {
    if (w <= 0 || h <= 0 || w > MaxW || h > MaxH) {
      return false;
    }
    width_ = w;
    height_ = h;
    return true;
  }

  constexpr std::int32_t width() const noexcept { return width_; }
  constexpr std::int32_t height() const noexcept { return height_; }

  /** Mutable view of the used part (stride MaxW); invalid before the first resize. */
  constexpr ImageView<T> view() noexcept { return ImageView<T>{width_ > 0 ? data_ : nullptr, width_, height_, MaxW}; }

  /** Read-only view of the used part. */
  constexpr ImageView<const T> cview() const noexcept {
    return ImageView<const T>{width_ > 0 ? data_ : nullptr, width_, height_, MaxW};
  }

 private:
  T data_[static_cast<std::size_t>(MaxW) * static_cast<std::size_t>(MaxH)]{};
  std::int32_t width_ = 0;
  std::int32_t height_ = 0;
};

}  // namespace trn::vision
