/**
 * @file ntt.cpp
 * @brief Radix-2 number-theoretic transforms modulo 15 * 2^27 + 1 (see ntt.hpp).
 */
#include "trn/vision/ntt.hpp"

#include <cstddef>

namespace trn::vision {

namespace detail {
namespace {

constexpr std::uint32_t kP = kNttModulus;
constexpr std::uint32_t kGenerator = 31U;  ///< generates Z_p^* (checked below on its 2-power part)

/** a b mod p by 64-bit division: for the compile-time tables only. */
constexpr std::uint32_t mul_mod_slow(std::uint32_t a, std::uint32_t b) noexcept {
  return static_cast<std::uint32_t>(static_cast<std::uint64_t>(a) * b % kP);
}

/** b^e mod p, square and multiply over e's 32 bits. */
constexpr std::uint32_t pow_mod(std::uint32_t b, std::uint32_t e) noexcept {
  std::uint32_t r = 1U;
  for (std::uint32_t bit = 0U; bit < 32U; ++bit) {
    if (((e >> bit) & 1U) != 0U) {
      r = mul_mod_slow(r, b);
    }
    b = mul_mod_slow(b, b);
  }
  return r;
}

/** Twiddles and their Shoup companions: entry h + j (h a power of two, j < h) is w_2h^j (or w_2h^-j). */
struct Twiddles {
  std::uint32_t w[kNttMaxSide]{};
  std::uint32_t wq[kNttMaxSide]{};  ///< floor(w 2^32 / p)
};

constexpr Twiddles make_twiddles(bool inverse) noexcept {
  Twiddles t{};
  for (std::uint32_t h = 1U; h < static_cast<std::uint32_t>(kNttMaxSide); h *= 2U) {
    std::uint32_t root = pow_mod(kGenerator, (kP - 1U) / (2U * h));
    if (inverse) {
      root = pow_mod(root, kP - 2U);  // Fermat: root^(p-2) = 1 / root
    }
    std::uint32_t v = 1U;
    for (std::uint32_t j = 0U; j < h; ++j) {
      t.w[h + j] = v;
      t.wq[h + j] = static_cast<std::uint32_t>((static_cast<std::uint64_t>(v) << 32U) / kP);
      v = mul_mod_slow(v, root);
    }
  }
  return t;
}

constexpr Twiddles kForwardTw = make_twiddles(false);
constexpr Twiddles kInverseTw = make_twiddles(true);

// 31 is a quadratic non-residue, so w_L = 31^((p-1)/L) has order exactly L: w_L^(L/2) = -1.
static_assert(pow_mod(kGenerator, (kP - 1U) / 2U) == kP - 1U, "31 must be a non-residue mod p");
static_assert(pow_mod(kForwardTw.w[kNttMaxSide / 2 + 1], static_cast<std::uint32_t>(kNttMaxSide / 2)) == kP - 1U,
              "the longest transform's root must have full order");
static_assert(mul_mod_slow(kForwardTw.w[kNttMaxSide / 2 + 1], kInverseTw.w[kNttMaxSide / 2 + 1]) == 1U,
              "inverse roots");

/** -1/p mod 2^32 by Newton's iteration (each step doubles the correct low bits, from 3). */
constexpr std::uint32_t neg_inverse_of_p() noexcept {
  std::uint32_t inv = kP;
  for (int k = 0; k < 5; ++k) {
    inv *= 2U - kP * inv;
  }
  return 0U - inv;
}
constexpr std::uint32_t kPNegInv = neg_inverse_of_p();
static_assert(kP * kPNegInv == 0xFFFFFFFFU, "-1/p mod 2^32");
static_assert(kPNegInv == (1U << 31U) - (1U << 27U) - 1U, "the shift form counted for Montgomery's m");

/** 2^32 / 2^s mod p for s = 0 .. 2 kNttMaxLog2 (ntt_convolution_scale()), built at compile time. */
struct ConvolutionScale {
  std::uint32_t c[2 * kNttMaxLog2 + 1]{};
};

constexpr ConvolutionScale make_convolution_scale() noexcept {
  ConvolutionScale t{};
  const auto r_mod_p = static_cast<std::uint32_t>((std::uint64_t{1} << 32U) % kP);
  for (std::uint32_t s = 0U; s <= 2U * static_cast<std::uint32_t>(kNttMaxLog2); ++s) {
    // 1 / 2^s = p - (p - 1) / 2^s: 2^s divides p - 1 (s <= 16 < 27) and 2^s ((p - 1) / 2^s) = -1.
    t.c[s] = mul_mod_slow(r_mod_p, kP - ((kP - 1U) >> s));
  }
  return t;
}
constexpr ConvolutionScale kConvolutionScale = make_convolution_scale();
static_assert(mul_mod_slow(kConvolutionScale.c[16], 1U << 16U) == static_cast<std::uint32_t>((1ULL << 32U) % kP),
              "c 2^s = 2^32 mod p");

/** a w mod p by Shoup's method. Any 32-bit a; w in [0, p), wq = floor(w 2^32 / p). */
inline std::uint32_t mul_shoup(std::uint32_t a, std::uint32_t w, std::uint32_t wq) noexcept {
  const auto q = static_cast<std::uint32_t>((static_cast<std::uint64_t>(a) * wq) >> 32U);
  // q p mod 2^32 by p's form, as counted: (q << 31) - (q << 27) + q. The true a w - q p lies in
  // [0, 2p), so the wraps mod 2^32 cancel.
  const std::uint32_t r = a * w - ((q << 31U) - (q << 27U) + q);
  return r >= kP ? r - kP : r;
}

/** Gentleman-Sande butterfly: (a, b) <- (a + b, (a - b) w). */
inline void butterfly_dif(std::uint32_t& a, std::uint32_t& b, std::uint32_t w, std::uint32_t wq) noexcept {
  const std::uint32_t x = a;
  const std::uint32_t y = b;
  const std::uint32_t s = x + y;  // < 2p < 2^32
  a = s >= kP ? s - kP : s;
  b = mul_shoup(x - y + kP, w, wq);  // x - y + p in (0, 2p)
}

/** Cooley-Tukey butterfly: (a, b) <- (a + b w, a - b w). */
inline void butterfly_dit(std::uint32_t& a, std::uint32_t& b, std::uint32_t w, std::uint32_t wq) noexcept {
  const std::uint32_t x = a;
  const std::uint32_t t = mul_shoup(b, w, wq);
  const std::uint32_t s = x + t;
  const std::uint32_t d = x - t + kP;
  a = s >= kP ? s - kP : s;
  b = d >= kP ? d - kP : d;
}

/** Montgomery reduction of t < p 2^32: t / 2^32 mod p, in [0, p). */
inline std::uint32_t redc(std::uint64_t t) noexcept {
  const std::uint32_t m = static_cast<std::uint32_t>(t) * kPNegInv;
  // t + m p < 2^62 + 2^63 and is divisible by 2^32; the quotient is below 2p.
  const auto u = static_cast<std::uint32_t>((t + static_cast<std::uint64_t>(m) * kP) >> 32U);
  return u >= kP ? u - kP : u;
}

/** The butterfly of a forward (DIF) or an inverse (DIT) pass. */
template <bool kInverse>
inline void butterfly(std::uint32_t& a, std::uint32_t& b, std::uint32_t w, std::uint32_t wq) noexcept {
  if constexpr (kInverse) {
    butterfly_dit(a, b, w, wq);
  } else {
    butterfly_dif(a, b, w, wq);
  }
}

/**
 * One butterfly with one twiddle over two row segments. With kWidth > 0 the
 * segments go through local copies of fixed length, which cannot alias each
 * other: the host compiler vectorises that loop.
 */
template <std::int32_t kWidth, bool kInverse>
inline void segment(std::uint32_t* ra, std::uint32_t* rb, std::int32_t n, std::uint32_t w,
                    std::uint32_t wq) noexcept {
  if constexpr (kWidth > 0) {
    std::uint32_t a[static_cast<std::size_t>(kWidth)];
    std::uint32_t b[static_cast<std::size_t>(kWidth)];
    for (std::int32_t c = 0; c < kWidth; ++c) {
      a[c] = ra[c];
      b[c] = rb[c];
    }
    for (std::int32_t c = 0; c < kWidth; ++c) {
      butterfly<kInverse>(a[c], b[c], w, wq);
    }
    for (std::int32_t c = 0; c < kWidth; ++c) {
      ra[c] = a[c];
      rb[c] = b[c];
    }
  } else {
    for (std::int32_t c = 0; c < n; ++c) {
      butterfly<kInverse>(ra[c], rb[c], w, wq);
    }
  }
}

/** One butterfly over two row segments of kWidth, each element with its own twiddle (see segment()). */
template <std::int32_t kWidth, bool kInverse>
inline void segment_twiddled(std::uint32_t* ra, std::uint32_t* rb, const std::uint32_t* w,
                             const std::uint32_t* wq) noexcept {
  std::uint32_t a[static_cast<std::size_t>(kWidth)];
  std::uint32_t b[static_cast<std::size_t>(kWidth)];
  for (std::int32_t c = 0; c < kWidth; ++c) {
    a[c] = ra[c];
    b[c] = rb[c];
  }
  for (std::int32_t c = 0; c < kWidth; ++c) {
    butterfly<kInverse>(a[c], b[c], w[c], wq[c]);
  }
  for (std::int32_t c = 0; c < kWidth; ++c) {
    ra[c] = a[c];
    rb[c] = b[c];
  }
}

/**
 * Transform of one contiguous row of 2^log2_n: forward (natural in, bit-reversed
 * out, stages h = n/2 .. 1) or inverse (bit-reversed in, natural out, unscaled,
 * stages h = 1 .. n/2). Stages with h >= 4 run in segments of fixed width
 * (vectorised on the host), the two shortest one butterfly at a time.
 */
template <bool kInverse>
void row_transform(std::uint32_t* x, std::int32_t log2_n) noexcept {
  const Twiddles& t = kInverse ? kInverseTw : kForwardTw;
  const std::int32_t n = std::int32_t{1} << log2_n;
  for (std::int32_t k = 0; k < log2_n; ++k) {
    const std::int32_t h = kInverse ? (std::int32_t{1} << k) : (n >> (k + 1));
    const std::uint32_t* w = t.w + h;
    const std::uint32_t* wq = t.wq + h;
    for (std::int32_t s = 0; s < n; s += 2 * h) {
      std::uint32_t* a = x + s;
      if (h >= kNttColumnBlock) {
        for (std::int32_t j = 0; j < h; j += kNttColumnBlock) {
          segment_twiddled<kNttColumnBlock, kInverse>(a + j, a + j + h, w + j, wq + j);
        }
      } else if (h == 8) {
        segment_twiddled<8, kInverse>(a, a + h, w, wq);
      } else if (h == 4) {
        segment_twiddled<4, kInverse>(a, a + h, w, wq);
      } else {
        for (std::int32_t j = 0; j < h; ++j) {
          butterfly<kInverse>(a[j], a[j + h], w[j], wq[j]);
        }
      }
    }
  }
}

/**
 * Forward transforms of the columns col0 .. col0 + width - 1 together: each
 * butterfly of the column transform is applied to a whole row segment with one
 * twiddle. kWidth > 0 fixes the segment's width at compile time (the host
 * compiler vectorises it); 0 takes @p width.
 */
template <std::int32_t kWidth>
void columns_forward(std::uint32_t* col0, std::int32_t stride, std::int32_t log2_h, std::int32_t width) noexcept {
  const std::int32_t n = kWidth > 0 ? kWidth : width;
  const std::int32_t rows = std::int32_t{1} << log2_h;
  for (std::int32_t h = rows / 2; h >= 1; h /= 2) {
    for (std::int32_t s = 0; s < rows; s += 2 * h) {
      for (std::int32_t j = 0; j < h; ++j) {
        const std::uint32_t w = kForwardTw.w[h + j];
        const std::uint32_t wq = kForwardTw.wq[h + j];
        std::uint32_t* ra = col0 + static_cast<std::int64_t>(s + j) * stride;
        std::uint32_t* rb = ra + static_cast<std::int64_t>(h) * stride;
        segment<kWidth, false>(ra, rb, n, w, wq);
      }
    }
  }
}

/** Inverse transforms of a block of columns together (see columns_forward()). */
template <std::int32_t kWidth>
void columns_inverse(std::uint32_t* col0, std::int32_t stride, std::int32_t log2_h, std::int32_t width) noexcept {
  const std::int32_t n = kWidth > 0 ? kWidth : width;
  const std::int32_t rows = std::int32_t{1} << log2_h;
  for (std::int32_t h = 1; h < rows; h *= 2) {
    for (std::int32_t s = 0; s < rows; s += 2 * h) {
      for (std::int32_t j = 0; j < h; ++j) {
        const std::uint32_t w = kInverseTw.w[h + j];
        const std::uint32_t wq = kInverseTw.wq[h + j];
        std::uint32_t* ra = col0 + static_cast<std::int64_t>(s + j) * stride;
        std::uint32_t* rb = ra + static_cast<std::int64_t>(h) * stride;
        segment<kWidth, true>(ra, rb, n, w, wq);
      }
    }
  }
}

/** Every column of @p plane, forward or inverse, in blocks of kNttColumnBlock (narrower planes: one block). */
void all_columns(NttPlane plane, bool inverse) noexcept {
  const std::int32_t width = plane.width();
  if (width < kNttColumnBlock) {
    if (inverse) {
      columns_inverse<0>(plane.data, width, plane.log2_h, width);
    } else {
      columns_forward<0>(plane.data, width, plane.log2_h, width);
    }
    return;
  }
  // width is a power of two >= kNttColumnBlock, so the blocks tile it exactly.
  for (std::int32_t c = 0; c < width; c += kNttColumnBlock) {
    if (inverse) {
      columns_inverse<kNttColumnBlock>(plane.data + c, width, plane.log2_h, kNttColumnBlock);
    } else {
      columns_forward<kNttColumnBlock>(plane.data + c, width, plane.log2_h, kNttColumnBlock);
    }
  }
}

// ---- work, as the TILE64 would do it (16 x 16-bit multipliers, two ALUs, one load/store slot)
// High word of a 32 x 32 product: four 16 x 16 partial products, the middle sum and its carries.
constexpr std::uint64_t kMulHiMacs = 4U;
constexpr std::uint64_t kMulHiOps = 6U;
// Low word: the low partial product plus both cross terms accumulated, shifted and added.
constexpr std::uint64_t kMulLoMacs = 3U;
constexpr std::uint64_t kMulLoOps = 2U;
// q p mod 2^32 = (q << 31) - (q << 27) + q: no multiply.
constexpr std::uint64_t kTimesPOps = 4U;
// Shoup: hi32(a w'), lo32(a w), q p, the subtraction, a compare and a conditional subtraction.
constexpr std::uint64_t kShoupMacs = kMulHiMacs + kMulLoMacs;
constexpr std::uint64_t kShoupOps = kMulHiOps + kMulLoOps + kTimesPOps + 3U;
// A butterfly: one Shoup product, a modular sum and a modular difference (3 ops each), one op of
// loop and address arithmetic; two loads and two stores.
constexpr std::uint64_t kButterflyMacs = kShoupMacs;
constexpr std::uint64_t kButterflyOps = kShoupOps + 7U;
constexpr std::uint64_t kButterflyWords = 4U;
constexpr std::uint64_t kTwiddleWords = 2U;  // w and w'
// Montgomery: the full 64-bit product (as the high word plus 2 ops for the low one); m = lo32(t) (-1/p)
// with -1/p = 2^31 - 2^27 - 1 (4 ops); t + m p in two words, m p by shifts (12 ops with carries);
// the conditional subtraction (2) and the loop (1). Two loads, one store.
constexpr std::uint64_t kRedcMacs = kMulHiMacs;
constexpr std::uint64_t kRedcOps = kMulHiOps + 2U + 4U + 12U + 2U + 1U;
constexpr std::uint64_t kRedcWords = 3U;
static_assert(kButterflyMacs == 7U && kButterflyOps == 22U, "ntt.hpp states these figures");

/** Work of @p rows row transforms of length 2^log2_w: every butterfly loads its own twiddle pair. */
bsp::Work rows_work(std::int32_t log2_w, std::int32_t rows) noexcept {
  const auto bfly = static_cast<std::uint64_t>(rows) * (std::uint64_t{1} << static_cast<std::uint32_t>(log2_w)) / 2U *
                    static_cast<std::uint64_t>(log2_w);
  bsp::Work w;
  w.int_macs = bfly * kButterflyMacs;
  w.int_ops = bfly * kButterflyOps;
  w.mem_words = bfly * (kButterflyWords + kTwiddleWords);
  return w;
}

/** Work of every column transform: one twiddle pair per row pair and column block. */
bsp::Work columns_work(std::int32_t log2_w, std::int32_t log2_h) noexcept {
  const std::uint64_t width = std::uint64_t{1} << static_cast<std::uint32_t>(log2_w);
  const std::uint64_t pairs = (std::uint64_t{1} << static_cast<std::uint32_t>(log2_h)) / 2U *
                              static_cast<std::uint64_t>(log2_h);  // row pairs over all stages
  const std::uint64_t block = static_cast<std::uint64_t>(kNttColumnBlock);
  const std::uint64_t blocks = (width + block - 1U) / block;
  bsp::Work w;
  w.int_macs = width * pairs * kButterflyMacs;
  w.int_ops = width * pairs * kButterflyOps;
  w.mem_words = width * pairs * kButterflyWords + blocks * pairs * kTwiddleWords;
  return w;
}

}  // namespace
}  // namespace detail

bsp::Work ntt_forward_work(std::int32_t log2_w, std::int32_t log2_h, std::int32_t rows_in) noexcept {
  return detail::rows_work(log2_w, rows_in) + detail::columns_work(log2_w, log2_h);
}

bsp::Work ntt_inverse_work(std::int32_t log2_w, std::int32_t log2_h, std::int32_t rows) noexcept {
  return detail::columns_work(log2_w, log2_h) + detail::rows_work(log2_w, rows);
}

bsp::Work ntt_multiply_work(std::int32_t log2_w, std::int32_t log2_h) noexcept {
  const std::uint64_t n = std::uint64_t{1} << static_cast<std::uint32_t>(log2_w + log2_h);
  bsp::Work w;
  w.int_macs = n * detail::kRedcMacs;
  w.int_ops = n * detail::kRedcOps;
  w.mem_words = n * detail::kRedcWords;
  return w;
}

Status ntt_forward(NttPlane plane, std::int32_t rows_in, bsp::Work& work) noexcept {
  if (!plane.valid() || rows_in < 0 || rows_in > plane.height()) {
    return Status::kBadInput;
  }
  const std::int32_t width = plane.width();
  for (std::int32_t y = 0; y < rows_in; ++y) {
    detail::row_transform<false>(plane.data + static_cast<std::int64_t>(y) * width, plane.log2_w);
  }
  detail::all_columns(plane, false);
  work += ntt_forward_work(plane.log2_w, plane.log2_h, rows_in);
  return Status::kOk;
}

Status ntt_inverse(NttPlane plane, std::int32_t row0, std::int32_t rows, bsp::Work& work) noexcept {
  if (!plane.valid() || row0 < 0 || rows < 0 || rows > plane.height() - row0) {
    return Status::kBadInput;
  }
  detail::all_columns(plane, true);
  const std::int32_t width = plane.width();
  for (std::int32_t y = row0; y < row0 + rows; ++y) {
    detail::row_transform<true>(plane.data + static_cast<std::int64_t>(y) * width, plane.log2_w);
  }
  work += ntt_inverse_work(plane.log2_w, plane.log2_h, rows);
  return Status::kOk;
}

Status ntt_multiply(NttPlane acc, NttPlane other, bsp::Work& work) noexcept {
  if (!acc.valid() || !other.valid() || acc.log2_w != other.log2_w || acc.log2_h != other.log2_h) {
    return Status::kBadInput;
  }
  const std::int64_t n = static_cast<std::int64_t>(acc.width()) * acc.height();
  std::uint32_t* a = acc.data;
  const std::uint32_t* b = other.data;
  for (std::int64_t i = 0; i < n; ++i) {
    a[i] = detail::redc(static_cast<std::uint64_t>(a[i]) * b[i]);  // < p^2 < p 2^32
  }
  work += ntt_multiply_work(acc.log2_w, acc.log2_h);
  return Status::kOk;
}

std::uint32_t ntt_convolution_scale(std::int32_t log2_w, std::int32_t log2_h) noexcept {
  if (log2_w < 0 || log2_w > kNttMaxLog2 || log2_h < 0 || log2_h > kNttMaxLog2) {
    return 0U;
  }
  return detail::kConvolutionScale.c[static_cast<std::uint32_t>(log2_w + log2_h)];
}

}  // namespace trn::vision
