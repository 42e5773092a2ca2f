/**
 * @file correlator.hpp
 * @brief One template over one search window: statistics, integral, NCC surface, peak and checks.
 *
 * The fine and coarse stages both reduce to this; they differ only in sizes
 * and in what they do before (downsampling) and after (scaling the offset).
 * Buffers come from a CorrelatorWorkspace whose capacity is a template parameter.
 *
 * Checked correlation (docs/FDIR.md, "Checked correlation"). A surface is
 * computed with the sum of its dot products, which must equal the checksum
 * the window's integral image gives (ncc.hpp): exact integers, tolerance zero,
 * so one wrong dot product anywhere fails it. After the peak search the
 * surface's digest (the sum of its values' bits as written) is taken again,
 * and the peak's score and its 3 x 3 neighbours (every value the sub-pixel
 * refinement reads) are computed again one by one (ncc_score_at: the same
 * operations in the same order, so equal bit for bit; tolerance zero again).
 * Any mismatch computes the integral and the surface again, at most
 * kCorrelationMaxRecompute times; still wrong, the match is rejected with
 * Reject::kCheckFailed, so nothing wrong is sent. A recomputed match is bit
 * for bit the clean one.
 *
 * Two ways to the dot products (CorrelationMethod), one set of checks. kSpatial
 * computes each dot product alone (ncc_surface); kTransform computes them all
 * at once by the exact integer transform (transform_dots.hpp) and scores them by
 * the same code (ncc_surface_from_dots). Both give the same integers, so the
 * same surface, checksums and match, bit for bit. On either path each dot
 * product is published on the dot channel before its use and summed, so a
 * corruption injected there is caught the same way. What the checks cover on
 * the transform path: the dot-product sum checks the whole transform end to end
 * (loads, both forward transforms, the pointwise product, the inverse); one
 * wrong dot product always fails it. A fault inside the transform spreads over
 * many dot products (a wrong spectrum value shifts every output by a multiple
 * of its root's powers, mod p) and fails it unless their integer errors sum to
 * exactly zero, which is not excluded by construction but needs thousands of
 * residues to cancel. The peak's neighbourhood is computed again by the spatial
 * dot products, a different algorithm, so the values a match is made of are
 * checked independently of the transform.
 */
#pragma once

#include "bsp_tile64/api/port.hpp"
#include "bsp_tile64/api/work.hpp"
#include "trn/vision/image.hpp"
#include "trn/vision/integral.hpp"
#include "trn/vision/ncc.hpp"
#include "trn/vision/peak.hpp"
#include "trn/vision/transform_dots.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace trn::vision {

/** bsp::publish_filter channel of a correlation surface after it is computed, before the peak search. */
inline constexpr std::uint32_t kCorrelationSurfaceChannel = 9;
/** bsp::publish_filter channel of each dot product of a surface, before it is used. */
inline constexpr std::uint32_t kCorrelationDotChannel = 10;
/** Recomputations of a surface found wrong before the match is rejected (as fdir::kAbftMaxRecompute). */
inline constexpr std::uint32_t kCorrelationMaxRecompute = 2U;

/** How a surface's dot products are computed (the same integers either way; see the file comment). */
enum class CorrelationMethod : std::uint8_t {
  kSpatial = 0,    ///< each dot product alone: n integer MACs per offset
  kTransform = 1,  ///< all at once by the exact 2-D transform; needs CorrelatorBuffers::transform
};

/** The check that found a correlation wrong (the events' cause). */
enum class CorrelationCheck : std::uint8_t {
  kNone = 0,
  kDotSum = 1,     ///< the sum of the dot products differs from the integral image's checksum
  kSurface = 2,    ///< the surface's digest changed between its computation and the peak search's end
  kPeakScore = 3,  ///< a score of the peak's 3 x 3 neighbourhood computed again differs from the surface's
};

/** Where a correlation publishes (silent corruptions are injected there); the flight code takes the defaults. */
struct CorrelationTaps {
  PublishFn publish = &bsp::publish_filter;  ///< nullptr: nothing published
  std::uint32_t dot_channel = kCorrelationDotChannel;
  std::uint32_t surface_channel = kCorrelationSurfaceChannel;
};

/** Raw buffers the correlator writes into (from a CorrelatorWorkspace). */
struct CorrelatorBuffers {
  std::uint32_t* sum = nullptr;
  std::uint64_t* sum_sq = nullptr;
  std::int64_t integral_entries = 0;  ///< capacity of sum and sum_sq
  float* surface = nullptr;
  std::uint8_t* flags = nullptr;
  std::int32_t max_window_px = 0;     ///< window (and surface) side capacity
  TransformBuffers transform{};       ///< planes of CorrelationMethod::kTransform (none: spatial only)
  NccWideBuffer wide{};               ///< ncc_surface()'s 16-bit copies (none: dot products from the bytes)
};

/**
 * Buffers for windows up to MaxWindow x MaxWindow pixels; with @p Wide, room
 * for ncc_surface()'s 16-bit copies too (templates up to kNccWideMaxTemplatePx
 * wide: the fine stage's), about 2 * MaxWindow^2 bytes more.
 */
template <std::int32_t MaxWindow, bool Wide = false>
struct CorrelatorWorkspace {
  static_assert(MaxWindow > 0 && MaxWindow <= 4096, "window capacity out of range");
  static constexpr std::int64_t kEntries = static_cast<std::int64_t>(MaxWindow + 1) * (MaxWindow + 1);
  static constexpr std::int64_t kPixels = static_cast<std::int64_t>(MaxWindow) * MaxWindow;
  static constexpr std::int64_t kWideEntries = Wide ? ncc_wide_entries(MaxWindow) : 0;

  std::uint32_t sum[static_cast<std::size_t>(kEntries)]{};
  std::uint64_t sum_sq[static_cast<std::size_t>(kEntries)]{};
  float surface[static_cast<std::size_t>(kPixels)]{};
  std::uint8_t flags[static_cast<std::size_t>(kPixels)]{};
  std::array<std::int16_t, static_cast<std::size_t>(kWideEntries)> wide{};

  CorrelatorBuffers buffers() noexcept {
    return CorrelatorBuffers{sum,      sum_sq, kEntries, surface, flags, MaxWindow, TransformBuffers{},
                             NccWideBuffer{Wide ? wide.data() : nullptr, kWideEntries}};
  }
};

/** Outcome of one template match. */
struct MatchResult {
  Peak peak;                    ///< surface peak, its sub-pixel position and the reject reason
  double x_px = 0.0;            ///< template top-left in window pixels (sub-pixel), valid when accepted
  double y_px = 0.0;
  std::int32_t flat_windows = 0;  ///< window positions skipped as flat
  ConstImageF32 surface{};      ///< the correlation surface (inside the workspace)
  std::uint32_t recomputes = 0U;  ///< surfaces computed again after a failed check
  bool check_failed = false;    ///< still wrong after kCorrelationMaxRecompute: rejected (kCheckFailed)
  CorrelationCheck first_check = CorrelationCheck::kNone;  ///< what found the first computation wrong

  constexpr bool accepted() const noexcept { return peak.accepted(); }
  constexpr Reject reason() const noexcept { return peak.reason; }
};

/**
 * Correlates @p tmpl over every position of @p window, checks the surface and
 * its peak (see the file comment) and applies the quality checks.
 * @param taps where the dot products and the surface are published
 * @param method how the dot products are computed; the result does not depend on it
 * @return kBadInput for invalid views, a template larger than the window or
 *         kTransform without transform buffers; kTooLarge when the window
 *         exceeds the buffers (the transform's too). A flat template or
 *         all-flat window is not an error: the result says kFlatTemplate / kFlatWindow;
 *         a surface still wrong after its recomputations says kCheckFailed.
 */
Status correlate(ConstImageU8 tmpl, ConstImageU8 window, const QualityParams& q, const CorrelatorBuffers& buf,
                 MatchResult& out, bsp::Work& work, const CorrelationTaps& taps = CorrelationTaps{},
                 CorrelationMethod method = CorrelationMethod::kSpatial) noexcept;

/**
 * A correlation in bands (one surface computed by several tiles, each some of
 * its rows, gathered by one): correlate_band() computes and checks rows
 * [row0, row0 + rows) of the surface correlate() gives @p tmpl over @p window,
 * correlate_gathered() searches the assembled surface. A score depends only on
 * the template, the window's pixels under it and their sums, and box sums are
 * differences of the integral image, so a band's values are the whole
 * surface's bit for bit (tests/trn/vision/checked_correlation_test.cpp), and
 * so is the match.
 *
 * Checks. A band is checked where it is computed, as correlate() checks a
 * surface: its dot products' sum against the checksum of the band window's
 * integral image, and its digest taken again after it is published; a band
 * still wrong after kCorrelationMaxRecompute is reported failed
 * (BandResult::check_failed), never used. The gatherer holds the assembled
 * surface's digest to the sum of the bands' (a value changed on its way
 * fails it) and computes the peak's 3 x 3 scores again alone.
 */

/** Buffers of one band (integral of the band's window, its rows of surface and flags). */
struct BandBuffers {
  std::uint32_t* sum = nullptr;
  std::uint64_t* sum_sq = nullptr;
  std::int64_t integral_entries = 0;  ///< capacity of sum and sum_sq
  float* surface = nullptr;           ///< the band's rows, packed (stride = surface width)
  std::uint8_t* flags = nullptr;
  std::int64_t surface_values = 0;    ///< capacity of surface and flags
};

/** What a band's computation says to its gatherer. */
struct BandResult {
  std::int32_t width = 0;         ///< surface width (offsets per row)
  std::int32_t rows = 0;          ///< rows computed
  std::int32_t flat_windows = 0;  ///< flat windows among them
  std::uint64_t digest = 0U;      ///< surface_digest() of the band as computed
  std::uint32_t recomputes = 0U;  ///< band computed again after a failed check
  bool check_failed = false;      ///< still wrong after kCorrelationMaxRecompute: not to be used
  CorrelationCheck first_check = CorrelationCheck::kNone;
};

/**
 * Rows [@p row0, @p row0 + @p rows) of the surface of @p tmpl over @p window,
 * computed spatially and checked (see above), into @p buf (row r of the band at
 * buf.surface + r * width).
 * @return kBadInput for invalid views, a template larger than the window, a flat
 *         template, missing buffers or rows outside the surface; kTooLarge when
 *         the band exceeds the buffers.
 */
Status correlate_band(ConstImageU8 tmpl, ConstImageU8 window, std::int32_t row0, std::int32_t rows,
                      const BandBuffers& buf, BandResult& out, bsp::Work& work,
                      const CorrelationTaps& taps = CorrelationTaps{}) noexcept;

/**
 * The match of @p surface, assembled from bands of @p tmpl over @p window:
 * its digest against @p digest (the sum of the bands'), the peak search, the
 * peak's 3 x 3 neighbourhood computed again alone (integral of the
 * neighbourhood's window into @p scratch) and the quality checks. A failed
 * check rejects the match (Reject::kCheckFailed; first_check says which).
 * @p flat_windows and @p recomputes are the bands' sums.
 * @return kBadInput for invalid views, a flat template or a surface of the wrong
 *         size; kTooLarge when the neighbourhood's window exceeds @p scratch.
 */
Status correlate_gathered(ConstImageU8 tmpl, ConstImageU8 window, const QualityParams& q, ConstImageF32 surface,
                          std::uint64_t digest, std::int32_t flat_windows, std::uint32_t recomputes,
                          const CorrelatorBuffers& scratch, MatchResult& out, bsp::Work& work) noexcept;

}  // namespace trn::vision
