/**
 * @file integral.cpp
 * @brief Integral images of values and squares (see integral.hpp for the overflow bound).
 */
#include "trn/vision/integral.hpp"

namespace trn::vision {

Status build_integral(ConstImageU8 image, std::uint32_t* sum, std::uint64_t* sum_sq, std::int64_t capacity,
                      IntegralRef& out, bsp::Work& work) noexcept {
  if (!image.valid() || sum == nullptr || sum_sq == nullptr) {
    return Status::kBadInput;
  }
  const std::int64_t w = image.width;
  const std::int64_t h = image.height;
  if (w * h > kIntegralMaxPixels || (w + 1) * (h + 1) > capacity) {
    return Status::kTooLarge;
  }
  const std::int64_t s = w + 1;
  for (std::int64_t x = 0; x < s; ++x) {
    sum[x] = 0U;
    sum_sq[x] = 0U;
  }
  for (std::int64_t y = 0; y < h; ++y) {
    const std::uint8_t* src = image.row(static_cast<std::int32_t>(y));
    std::uint32_t* s_prev = sum + y * s;
    std::uint32_t* s_cur = s_prev + s;
    std::uint64_t* q_prev = sum_sq + y * s;
    std::uint64_t* q_cur = q_prev + s;
    s_cur[0] = 0U;
    q_cur[0] = 0U;
    std::uint32_t row_sum = 0U;
    std::uint64_t row_sq = 0U;
    for (std::int64_t x = 0; x < w; ++x) {
      const std::uint32_t v = src[x];
      row_sum += v;
      row_sq += static_cast<std::uint64_t>(v * v);
      s_cur[x + 1] = s_prev[x + 1] + row_sum;
      q_cur[x + 1] = q_prev[x + 1] + row_sq;
    }
  }
  const auto px = static_cast<std::uint64_t>(w * h);
  work.int_ops += 4U * px;    // two running sums, two column adds
  work.int_macs += px;        // the square
  work.mem_words += px / 4U + 6U * px;  // bytes in; u32 read+write, u64 read+write (2 words each)
  out = IntegralRef{sum, sum_sq, image.width, image.height};
  return Status::kOk;
}

}  // namespace trn::vision
