/**
 * @file correlator.hpp
 * @brief One template over one search window: statistics, integral, NCC surface, peak and checks.
 *
 * The fine and coarse stages both reduce to this; they differ only in sizes
 * and in what they do before (downsampling) and after (scaling the offset).
 * Buffers come from a CorrelatorWorkspace whose capacity is a template parameter.
 */
#pragma once

#include "bsp_tile64/work.hpp"
#include "trn/vision/image.hpp"
#include "trn/vision/integral.hpp"
#include "trn/vision/ncc.hpp"
#include "trn/vision/peak.hpp"

#include <cstddef>
#include <cstdint>

namespace trn::vision {

/** Raw buffers the correlator writes into (from a CorrelatorWorkspace). */
struct CorrelatorBuffers {
  std::uint32_t* sum = nullptr;
  std::uint64_t* sum_sq = nullptr;
  std::int64_t integral_entries = 0;  ///< capacity of sum and sum_sq
  float* surface = nullptr;
  std::uint8_t* flags = nullptr;
  std::int32_t max_window_px = 0;     ///< window (and surface) side capacity
};

/** Buffers for windows up to MaxWindow x MaxWindow pixels. */
template <std::int32_t MaxWindow>
struct CorrelatorWorkspace {
  static_assert(MaxWindow > 0 && MaxWindow <= 4096, "window capacity out of range");
  static constexpr std::int64_t kEntries = static_cast<std::int64_t>(MaxWindow + 1) * (MaxWindow + 1);
  static constexpr std::int64_t kPixels = static_cast<std::int64_t>(MaxWindow) * MaxWindow;

  std::uint32_t sum[static_cast<std::size_t>(kEntries)]{};
  std::uint64_t sum_sq[static_cast<std::size_t>(kEntries)]{};
  float surface[static_cast<std::size_t>(kPixels)]{};
  std::uint8_t flags[static_cast<std::size_t>(kPixels)]{};

  CorrelatorBuffers buffers() noexcept { return CorrelatorBuffers{sum, sum_sq, kEntries, surface, flags, MaxWindow}; }
};

/** Outcome of one template match. */
struct MatchResult {
  Peak peak;                    ///< surface peak, its sub-pixel position and the reject reason
  double x_px = 0.0;            ///< template top-left in window pixels (sub-pixel), valid when accepted
  double y_px = 0.0;
  std::int32_t flat_windows = 0;  ///< window positions skipped as flat
  ConstImageF32 surface{};      ///< the correlation surface (inside the workspace)

  constexpr bool accepted() const noexcept { return peak.accepted(); }
  constexpr Reject reason() const noexcept { return peak.reason; }
};

/**
 * Correlates @p tmpl over every position of @p window and applies the checks.
 * @return kBadInput for invalid views or a template larger than the window,
 *         kTooLarge when the window exceeds the buffers. A flat template or
 *         all-flat window is not an error: the result says kFlatTemplate / kFlatWindow.
 */
Status correlate(ConstImageU8 tmpl, ConstImageU8 window, const QualityParams& q, const CorrelatorBuffers& buf,
                 MatchResult& out, bsp::Work& work) noexcept;

}  // namespace trn::vision
