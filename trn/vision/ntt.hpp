/**
 * @file ntt.hpp
 * @brief Exact integer 2-D number-theoretic transform (radix 2, modulo 15 * 2^27 + 1) over caller buffers.
 *
 * The field. p = 2013265921 = 15 * 2^27 + 1 is prime, below 2^31, and 31
 * generates its multiplicative group, so Z_p holds roots of unity of every
 * order 2^k, k <= 27: a length-2^k discrete Fourier transform exists in Z_p and
 * the convolution theorem holds there exactly, with no rounding. A cyclic
 * convolution computed through the transform equals the integer one whenever
 * every true result lies in [0, p) (transform_dots.hpp uses this).
 *
 * A plane is a row-major array of 2^log2_w x 2^log2_h residues in [0, p)
 * with stride 2^log2_w. Forward: per row, then per column, decimation in
 * frequency (natural order in, bit-reversed order out), roots w_L = 31^((p-1)/L).
 * Inverse: per column, then per row, decimation in time (bit-reversed in,
 * natural out) with the inverse roots, unscaled: it returns 2^(log2_w + log2_h)
 * times the inverse transform. The spectrum stays in bit-reversed order, which
 * a pointwise product does not mind. The column pass works on blocks of
 * kNttColumnBlock neighbouring columns at once (one twiddle for the whole row
 * segment, contiguous memory, a block stays in cache through all its stages),
 * the row pass on one row at a time. Butterflies run over fixed-width segments
 * copied to locals, so the host compiler vectorises them at -O2; the TILE64
 * count below is of the same butterflies done in place.
 *
 * Arithmetic, all in 32-bit words, every value kept in [0, p):
 * - twiddle products by Shoup's method: with w' = floor(w 2^32 / p) precomputed,
 *   q = hi32(a w'), r = a w - q p (mod 2^32) lies in [0, 2p), one conditional
 *   subtraction; a may be any 32-bit value. The tables are built at compile time.
 * - pointwise products by Montgomery's reduction (R = 2^32): REDC(a b) = a b / R.
 *   ntt_convolution_scale() gives the factor that, applied to one operand's
 *   samples, makes multiply-then-inverse return the exact cyclic convolution.
 *
 * Work counted for the TILE64 (bsp::Work; see ntt.cpp for each figure): the
 * chip multiplies 16 x 16 bits, so a 32 x 32 product is several multiplies,
 * and p's form makes q p shifts and adds: a butterfly is 7 MACs, 22 integer
 * ops and 4 data words, plus 2 twiddle words where the twiddle changes (every
 * butterfly of a row pass, once per row pair and column block in the column pass).
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "trn/vision/status.hpp"

#include <cstdint>

namespace trn::vision {

inline constexpr std::uint32_t kNttModulus = 2013265921U;  ///< 15 * 2^27 + 1, prime
inline constexpr std::int32_t kNttMaxLog2 = 8;             ///< longest transform per axis: 2^8 = 256 samples
inline constexpr std::int32_t kNttMaxSide = std::int32_t{1} << kNttMaxLog2;
inline constexpr std::int32_t kNttColumnBlock = 16;        ///< columns transformed together (one 64-byte line)
static_assert(kNttModulus < (1U << 31U), "sums of two residues must fit 32 bits");
static_assert(((kNttModulus - 1U) >> 27U) == 15U && ((kNttModulus - 1U) & ((1U << 27U) - 1U)) == 0U,
              "p - 1 = 15 * 2^27: the shift-and-add forms of q p in ntt.cpp depend on it");
static_assert(kNttMaxLog2 <= 27, "roots of unity exist up to order 2^27");

/** A plane of 2^log2_w x 2^log2_h residues, row-major, stride 2^log2_w. */
struct NttPlane {
  std::uint32_t* data = nullptr;
  std::int32_t log2_w = 0;
  std::int32_t log2_h = 0;

  constexpr std::int32_t width() const noexcept { return std::int32_t{1} << log2_w; }
  constexpr std::int32_t height() const noexcept { return std::int32_t{1} << log2_h; }
  constexpr bool valid() const noexcept {
    return data != nullptr && log2_w >= 0 && log2_w <= kNttMaxLog2 && log2_h >= 0 && log2_h <= kNttMaxLog2;
  }
};

/**
 * Forward 2-D transform in place. Pre: every entry in [0, p); rows at and
 * below @p rows_in are zero (their row transforms are skipped: zero stays zero).
 * Post: the spectrum, bit-reversed along both axes, every entry in [0, p).
 * @return kBadInput for an invalid plane or rows_in outside 0..height.
 */
Status ntt_forward(NttPlane plane, std::int32_t rows_in, bsp::Work& work) noexcept;

/**
 * Inverse 2-D transform in place, unscaled. Pre: a spectrum as ntt_forward()
 * leaves it. Post: rows row0 .. row0 + rows - 1 hold 2^(log2_w + log2_h) times
 * the inverse transform in natural order, in [0, p); the other rows hold the
 * column pass's intermediates (their row transforms are skipped).
 * @return kBadInput for an invalid plane or a row range outside the plane.
 */
Status ntt_inverse(NttPlane plane, std::int32_t row0, std::int32_t rows, bsp::Work& work) noexcept;

/**
 * Pointwise Montgomery product: acc[i] = acc[i] * other[i] / 2^32 (mod p).
 * Pre: both planes of the same size, entries in [0, p). Post: entries in [0, p).
 * @return kBadInput for invalid or differently sized planes.
 */
Status ntt_multiply(NttPlane acc, NttPlane other, bsp::Work& work) noexcept;

/**
 * The factor c = 2^32 / 2^(log2_w + log2_h) (mod p): samples of one operand
 * multiplied by c (mod p) before its forward transform make ntt_multiply()
 * then ntt_inverse() return the exact cyclic convolution (mod p).
 * @return the factor, or 0 when a size is outside 0..kNttMaxLog2.
 */
std::uint32_t ntt_convolution_scale(std::int32_t log2_w, std::int32_t log2_h) noexcept;

/** Work of ntt_forward() on a 2^log2_w x 2^log2_h plane with @p rows_in non-zero rows. */
bsp::Work ntt_forward_work(std::int32_t log2_w, std::int32_t log2_h, std::int32_t rows_in) noexcept;
/** Work of ntt_inverse() with @p rows rows transformed back. */
bsp::Work ntt_inverse_work(std::int32_t log2_w, std::int32_t log2_h, std::int32_t rows) noexcept;
/** Work of ntt_multiply(). */
bsp::Work ntt_multiply_work(std::int32_t log2_w, std::int32_t log2_h) noexcept;

}  // namespace trn::vision
