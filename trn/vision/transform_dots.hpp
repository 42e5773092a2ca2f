/**
 * @file transform_dots.hpp
 * @brief Every template-window dot product at once, exactly, through the number-theoretic transform.
 *
 * The dot products D(x, y) = sum_{i,j} T(i, j) W(x + i, y + j) of a tw x th
 * template at every offset of a ww x wh window are a convolution: with T
 * flipped along both axes, F(u, v) = T(tw - 1 - u, th - 1 - v),
 * (W * F)(x + tw - 1, y + th - 1) = D(x, y). Both are zero-padded to N x M,
 * the powers of two at or above ww x wh, and convolved cyclically by the 2-D
 * transform of ntt.hpp. The cyclic wrap reaches only outputs left of column
 * tw - 1 or above row th - 1, which no offset uses (N >= ww, M >= wh).
 *
 * Exact. Each D is an integer in [0, 255^2 n] (n = tw th), and
 * 255^2 kNccMaxTemplatePixels < p (static_assert below): the residue the
 * transform returns is D itself. The dot products, hence the NCC surface, its
 * checksums and the match, are bit for bit those of the spatial path (ncc.hpp).
 *
 * Steps: the window into plane A (bytes to words, zero padding), forward
 * transform; the flipped template into plane B, each pixel v replaced by
 * v c mod p (c = ntt_convolution_scale(); a 256-entry table built by modular
 * additions), forward transform of its th rows; A = A B / 2^32 pointwise;
 * inverse transform of the rows that hold offsets. For a 64 x 64 template over
 * a 256 x 256 window that is 1.31 M butterflies and 65 k Montgomery products
 * (38.3 M TILE64 cycles by the cost model) against 153 M MACs (314.7 M cycles) spatially.
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "trn/vision/image.hpp"
#include "trn/vision/ncc.hpp"
#include "trn/vision/ntt.hpp"
#include "trn/vision/status.hpp"

#include <cstddef>
#include <cstdint>

namespace trn::vision {

static_assert(65025ULL * static_cast<std::uint64_t>(kNccMaxTemplatePixels) < kNttModulus,
              "every dot product must be below p for the transform to return it exactly");

/** Raw buffers of transform_dots() (from a TransformWorkspace). */
struct TransformBuffers {
  std::uint32_t* window_plane = nullptr;    ///< the window's plane; holds the dot products afterwards
  std::uint32_t* template_plane = nullptr;  ///< the flipped, scaled template's plane
  std::uint32_t* scaled = nullptr;          ///< 256 entries: v c mod p
  std::int32_t max_side = 0;                ///< plane side capacity, a power of two
};

/** Buffers for windows up to MaxSide x MaxSide (two planes of MaxSide^2 words: 512 KiB at 256). */
template <std::int32_t MaxSide>
struct TransformWorkspace {
  static_assert(MaxSide >= 1 && MaxSide <= kNttMaxSide && (MaxSide & (MaxSide - 1)) == 0,
                "plane side: a power of two up to kNttMaxSide");
  static constexpr std::size_t kWords = static_cast<std::size_t>(MaxSide) * static_cast<std::size_t>(MaxSide);

  std::uint32_t window_plane[kWords]{};
  std::uint32_t template_plane[kWords]{};
  std::uint32_t scaled[256]{};

  TransformBuffers buffers() noexcept { return TransformBuffers{window_plane, template_plane, scaled, MaxSide}; }
};

/**
 * The dot product of @p tmpl with @p window at every offset.
 * Post (kOk): @p dots is a (ww - tw + 1) x (wh - th + 1) view into
 * buf.window_plane; entry (x, y) is the dot product at offset (x, y), exactly.
 * It stays valid until the buffers are used again.
 * @return kBadInput for invalid views, null buffers or a template larger than
 *         the window; kTooLarge for a window above buf.max_side or kNttMaxSide,
 *         or a template above kNccMaxTemplatePixels (the exactness bound).
 */
Status transform_dots(ConstImageU8 tmpl, ConstImageU8 window, const TransformBuffers& buf,
                      ImageView<const std::uint32_t>& dots, bsp::Work& work) noexcept;

/** Work transform_dots() counts for a @p tw x @p th template over a @p ww x @p wh window. */
bsp::Work transform_dots_work(std::int32_t tw, std::int32_t th, std::int32_t ww, std::int32_t wh) noexcept;

}  // namespace trn::vision
