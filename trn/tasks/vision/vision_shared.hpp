/**
 * @file vision_shared.hpp
 * @brief What the vision coordinator and the vision tiles share: the landmark table and the
 *        relit coarse layer in DDR, the bands of the relight, the frame's pixels by offset.
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "kernel/kernel.hpp"
#include "trn/vision/coarse.hpp"
#include "trn/vision/correlator.hpp"
#include "trn/vision/frame.hpp"
#include "trn/vision/landmarks.hpp"

#include <cstddef>
#include <cstdint>

namespace trn::tasks {

/** Name of the shared DDR carve holding the landmark table. */
inline constexpr const char* kLandmarkCarveName = "landmarks";
/** Name of the shared DDR carve holding the coarse layer relit to the descent sun. */
inline constexpr const char* kRelitCarveName = "coarse_relit";
/** DDR carve name of the coordinator's coarse-stage workspace. */
inline constexpr const char* kCoarseWsCarveName = "coarse_ws";
/** DDR carve of the coordinator's plan scratch (vision::PlanScratch: each frame's predictions, kept between its two passes). */
inline constexpr const char* kPlanScratchCarveName = "plan_scratch";
/** DDR carve of the coarse stage's band slots (CoarseBandSlots: one per tile). */
inline constexpr const char* kCoarseBandCarveName = "coarse_bands";
/** Rows of the coarse surface a band slot holds. */
inline constexpr std::int32_t kCoarseBandMaxRows = 16;
/** The template height a slot's integral image is sized for (the coordinator's coarse template). */
inline constexpr std::int32_t kCoarseBandTemplatePx = 64;
/** Integral-image entries of a slot: kCoarseBandMaxRows rows of offsets over a kCoarseMaxPx wide window. */
inline constexpr std::int64_t kCoarseBandEntries =
    std::int64_t{vision::kCoarseMaxPx + 1} * (kCoarseBandMaxRows + kCoarseBandTemplatePx);
/** Surface values of a slot. */
inline constexpr std::int64_t kCoarseBandValues = std::int64_t{vision::kCoarseMaxPx} * kCoarseBandMaxRows;

/**
 * Where a tile computes a band of the coarse stage's surface (vision::correlate_band())
 * and leaves it for the coordinator: the band window's integral image, the band's rows
 * and flags (~250 KiB; in DDR, as a vision tile's own RAM has no room for it).
 */
struct CoarseBandSlot {
  std::uint32_t sum[static_cast<std::size_t>(kCoarseBandEntries)];
  std::uint64_t sum_sq[static_cast<std::size_t>(kCoarseBandEntries)];
  float surface[static_cast<std::size_t>(kCoarseBandValues)];
  std::uint8_t flags[static_cast<std::size_t>(kCoarseBandValues)];

  vision::BandBuffers buffers() noexcept {
    return vision::BandBuffers{sum, sum_sq, kCoarseBandEntries, surface, flags, kCoarseBandValues};
  }
};

/** Bands of the coarse surface at most in a frame: one per vision tile, more when a slot cannot hold a tile's share. */
inline constexpr std::uint32_t kMaxCoarseBands = 64;
/** The slot of a band the coordinator computes itself (no tile writes there). */
inline constexpr std::uint32_t kCoordinatorBandSlot = kMaxCoarseBands;

/**
 * The slots, by band (band j of a frame is computed in slot j, by the one tile
 * it is dealt to: a tile given two bands never overwrites the first before
 * the coordinator has copied it), and the coordinator's own.
 */
struct CoarseBandSlots {
  CoarseBandSlot slot[kMaxCoarseBands + 1U];
};

/** Band slot @p index (0 .. kCoordinatorBandSlot), or nullptr before the coordinator carved them or out of range. [task] */
CoarseBandSlot* coarse_band_slot(std::uint32_t index) noexcept;

/** The most rows of @p prep's surface one slot holds (0: not even one). */
std::int32_t coarse_band_rows_max(const vision::CoarsePrepared& prep) noexcept;

/** Ticks a unit, a result or a batch part may wait for the network before it is counted as failed. */
inline constexpr std::uint32_t kVisionSendTicks = 20;

/** The shared landmark table, or nullptr before the coordinator selected it. [task|host] */
const vision::LandmarkTable* landmark_table_find() noexcept;

/**
 * A checked correlation that found a wrong surface, as an event of this tile
 * (kCorrelationCorrected, or kCorrelationFailed when still wrong): subject the
 * landmark (kCoarseLandmark for the coarse stage), cause the check that failed
 * first, a the frame, b the recomputations. Nothing when the checks all passed
 * at once. [task]
 */
void report_correlation_checks(bool failed, std::uint32_t recomputes, vision::CorrelationCheck first,
                               std::uint16_t landmark, std::uint32_t frame) noexcept;

/** @p bytes of DDR at @p offset, or nullptr when they are not all inside DDR. */
const std::uint8_t* ddr_at(std::uint64_t offset, std::uint64_t bytes) noexcept;

/** The DDR carve named @p what, or nullptr. */
const std::uint8_t* ddr_find(const char* what) noexcept;
/** ddr_find(), and the block's size into @p bytes (0 when not found). */
const std::uint8_t* ddr_find_sized(const char* what, std::size_t& bytes) noexcept;

/**
 * The DDR carve named @p what if one of @p bytes exists (a restarted task
 * takes back what it carved before; the bytes are as left), else a new zeroed
 * carve. nullptr when the region is full or a carve of that name has another
 * size. [task]
 */
std::uint8_t* ddr_carve_named(const char* what, std::size_t bytes, std::size_t align) noexcept;

/** Rows [@p row0, @p row0 + @p rows) of band @p i of @p n over @p height rows. */
void band_rows(std::int32_t height, std::uint32_t i, std::uint32_t n, std::int32_t& row0, std::int32_t& rows) noexcept;

/**
 * Rows relit between two check-ins of the task: about 40 M TILE64 cycles
 * (57 ms), whatever the band's size (a band of the coarse layer shared by 5
 * tiles instead of 40 is 8 times larger, and in one piece it overran the
 * task's 500-tick check-in: healthy tiles were reset).
 */
inline constexpr std::int32_t kRelightStepRows = 16;

/**
 * Relights rows [row0, row0 + rows) of @p map into the same rows of @p relit,
 * charging the work, kRelightStepRows at a time with a check-in of the
 * calling task after each step.
 */
bool relight_band(const vision::MapView& map, const double sun_m[3], vision::ImageU8 relit, std::int32_t row0,
                  std::int32_t rows) noexcept;

}  // namespace trn::tasks
