/**
 * @file transform_dots.cpp
 * @brief All dot products of a template over a window by an exact 2-D transform (see transform_dots.hpp).
 */
#include "trn/vision/transform_dots.hpp"

namespace trn::vision {

namespace detail {
namespace {

/** Smallest k with 2^k >= n, for 1 <= n <= kNttMaxSide. */
std::int32_t ceil_log2(std::int32_t n) noexcept {
  std::int32_t k = 0;
  while (k < kNttMaxLog2 && (std::int32_t{1} << k) < n) {
    ++k;
  }
  return k;
}

/** The plane sizes for a window. */
struct PlaneSize {
  std::int32_t log2_w = 0;
  std::int32_t log2_h = 0;
};

PlaneSize plane_size(std::int32_t ww, std::int32_t wh) noexcept { return PlaneSize{ceil_log2(ww), ceil_log2(wh)}; }

/** Window bytes into the top-left of @p a, every other entry zero. */
void load_window(ConstImageU8 window, NttPlane a) noexcept {
  const std::int32_t n = a.width();
  const std::int32_t m = a.height();
  for (std::int32_t y = 0; y < m; ++y) {
    std::uint32_t* row = a.data + static_cast<std::int64_t>(y) * n;
    std::int32_t x = 0;
    if (y < window.height) {
      const std::uint8_t* src = window.row(y);
      for (; x < window.width; ++x) {
        row[x] = src[x];
      }
    }
    for (; x < n; ++x) {
      row[x] = 0U;
    }
  }
}

/** scaled[v] = v c mod p for v = 0..255, by modular additions. */
void build_scaled(std::uint32_t c, std::uint32_t* scaled) noexcept {
  std::uint32_t v = 0U;
  for (std::int32_t k = 0; k < 256; ++k) {
    scaled[k] = v;
    const std::uint32_t s = v + c;  // both below p < 2^31
    v = s >= kNttModulus ? s - kNttModulus : s;
  }
}

/** The template flipped along both axes, each pixel through @p scaled, into the top-left of @p b. */
void load_template(ConstImageU8 tmpl, const std::uint32_t* scaled, NttPlane b) noexcept {
  const std::int32_t n = b.width();
  const std::int32_t m = b.height();
  for (std::int32_t v = 0; v < m; ++v) {
    std::uint32_t* row = b.data + static_cast<std::int64_t>(v) * n;
    std::int32_t u = 0;
    if (v < tmpl.height) {
      const std::uint8_t* src = tmpl.row(tmpl.height - 1 - v);
      for (; u < tmpl.width; ++u) {
        row[u] = scaled[src[tmpl.width - 1 - u]];
      }
    }
    for (; u < n; ++u) {
      row[u] = 0U;
    }
  }
}

/** Work of the two loads and the scale table: a store per plane word, a load per byte and per lookup. */
bsp::Work load_work(std::int32_t tw, std::int32_t th, std::int32_t ww, std::int32_t wh, PlaneSize ps) noexcept {
  const std::uint64_t plane = std::uint64_t{1} << static_cast<std::uint32_t>(ps.log2_w + ps.log2_h);
  const auto win = static_cast<std::uint64_t>(ww) * static_cast<std::uint64_t>(wh);
  const auto tpx = static_cast<std::uint64_t>(tw) * static_cast<std::uint64_t>(th);
  bsp::Work w;
  constexpr std::uint64_t kTable = 256U;                        // entries of the scale table
  w.int_ops = 2U * plane + 3U * kTable;                         // loop and address per word; table additions
  w.mem_words = 2U * plane + win / 4U + tpx / 4U + tpx + kTable;  // stores; bytes; lookups; table stores
  return w;
}

}  // namespace
}  // namespace detail

bsp::Work transform_dots_work(std::int32_t tw, std::int32_t th, std::int32_t ww, std::int32_t wh) noexcept {
  const detail::PlaneSize ps = detail::plane_size(ww, wh);
  return detail::load_work(tw, th, ww, wh, ps) + ntt_forward_work(ps.log2_w, ps.log2_h, wh) +
         ntt_forward_work(ps.log2_w, ps.log2_h, th) + ntt_multiply_work(ps.log2_w, ps.log2_h) +
         ntt_inverse_work(ps.log2_w, ps.log2_h, wh - th + 1);
}

Status transform_dots(ConstImageU8 tmpl, ConstImageU8 window, const TransformBuffers& buf,
                      ImageView<const std::uint32_t>& dots, bsp::Work& work) noexcept {
  dots = ImageView<const std::uint32_t>{};
  if (!tmpl.valid() || !window.valid() || tmpl.width > window.width || tmpl.height > window.height ||
      buf.window_plane == nullptr || buf.template_plane == nullptr || buf.scaled == nullptr) {
    return Status::kBadInput;
  }
  if (window.width > buf.max_side || window.height > buf.max_side || window.width > kNttMaxSide ||
      window.height > kNttMaxSide ||
      static_cast<std::int64_t>(tmpl.width) * tmpl.height > kNccMaxTemplatePixels) {
    return Status::kTooLarge;
  }
  const detail::PlaneSize ps = detail::plane_size(window.width, window.height);
  const NttPlane a{buf.window_plane, ps.log2_w, ps.log2_h};
  const NttPlane b{buf.template_plane, ps.log2_w, ps.log2_h};
  const std::int32_t sh = window.height - tmpl.height + 1;
  detail::load_window(window, a);
  detail::build_scaled(ntt_convolution_scale(ps.log2_w, ps.log2_h), buf.scaled);
  detail::load_template(tmpl, buf.scaled, b);
  work += detail::load_work(tmpl.width, tmpl.height, window.width, window.height, ps);
  // Every call below was given a valid plane and rows inside it; a failure would be a broken invariant.
  Status st = ntt_forward(a, window.height, work);
  if (st == Status::kOk) {
    st = ntt_forward(b, tmpl.height, work);
  }
  if (st == Status::kOk) {
    st = ntt_multiply(a, b, work);
  }
  if (st == Status::kOk) {
    st = ntt_inverse(a, tmpl.height - 1, sh, work);
  }
  if (st != Status::kOk) {
    return st;
  }
  const std::int32_t n = a.width();
  dots = ImageView<const std::uint32_t>{a.data + static_cast<std::int64_t>(tmpl.height - 1) * n + (tmpl.width - 1),
                                        window.width - tmpl.width + 1, sh, n};
  return Status::kOk;
}

}  // namespace trn::vision
