/**
 * @file landmark_product.hpp
 * @brief The landmark table made on the ground with the reference map, as the coordinator reads it from DDR.
 *
 * The selection (vision::select_landmarks(), ~0.9 s of the coordinator's tile
 * on the default map) depends on the map alone, so the ground runs it when it
 * makes the map and sends the table with it: a DDR block named
 * kLandmarkProductCarveName, a LandmarkProductHeader followed by `count`
 * vision::Landmark records (map positions filled). The coordinator takes the
 * table only if the header is intact (its own CRC-32C), it was selected with
 * the coordinator's settings on a layer of the same size and geometry, every
 * landmark lies in that layer, the dense set starts within the table, and the records' CRC-32C matches; otherwise it
 * reports why (landmark_product_refused) and selects the landmarks itself.
 *
 * Flight code (the check and the copy): static memory, no exceptions.
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "trn/vision/landmarks.hpp"

#include <cstddef>
#include <cstdint>
#include <span>

namespace trn::tasks {

/** Name of the ground's landmark table in DDR. */
inline constexpr const char* kLandmarkProductCarveName = "landmark_product";
inline constexpr std::uint32_t kLandmarkProductMagic = 0x504B4D4CU;  // "LMKP" little-endian
inline constexpr std::uint32_t kLandmarkProductVersion = 2U;  // 2: the dense set (first_tight, the dense cells in the settings)

/** The block's first bytes (no padding: every field is written). */
struct LandmarkProductHeader {
  std::uint32_t magic = kLandmarkProductMagic;
  std::uint32_t version = kLandmarkProductVersion;
  std::uint32_t count = 0U;           ///< landmark records after the header
  std::int32_t layer_width = 0;       ///< the map layer it was selected on, pixels
  std::int32_t layer_height = 0;
  std::uint32_t first_tight = 0U;     ///< records from this one on are the dense set (LandmarkTable::first_tight)
  vision::MapGeometry geo{};          ///< ... and its geometry
  vision::SelectParams params{};      ///< the selection's settings
  std::uint32_t items_crc = 0U;       ///< CRC-32C of the records
  std::uint32_t header_crc = 0U;      ///< CRC-32C of the header's bytes before this field
};
static_assert(sizeof(LandmarkProductHeader) == 96U, "the header has no padding");
static_assert(sizeof(vision::Landmark) == 40U, "a record has no padding");

/** Bytes of a product of @p count landmarks. */
constexpr std::size_t landmark_product_bytes(std::uint32_t count) noexcept {
  return sizeof(LandmarkProductHeader) + static_cast<std::size_t>(count) * sizeof(vision::Landmark);
}

/** Why a product was not taken (landmark_product_refused's cause). */
enum class ProductCheck : std::uint32_t {
  kOk = 0,
  kTooShort = 1,      ///< the block cannot hold the header, or the records it announces
  kBadHeader = 2,     ///< magic, version or the header's CRC
  kOtherSettings = 3, ///< selected with other settings than the coordinator's
  kOtherMap = 4,      ///< selected on a layer of another size or geometry
  kBadRecords = 5,    ///< the records' CRC, a count above the table, a dense set past it, or a landmark outside the layer
};

/** What the ground needs to say about the layer it selected on. */
struct ProductLayer {
  std::int32_t width = 0;
  std::int32_t height = 0;
  vision::MapGeometry geo{};
};

/**
 * Writes @p table (selected with @p params on @p layer) as a product into
 * @p out. False if @p out is shorter than landmark_product_bytes(count).
 */
bool landmark_product_write(const vision::LandmarkTable& table, const vision::SelectParams& params,
                            const ProductLayer& layer, std::span<std::uint8_t> out) noexcept;

/**
 * Checks the product in @p bytes against the coordinator's @p params and
 * @p layer and, if it passes, copies its records into @p table (count set,
 * scratch cleared). @p table is untouched unless kOk. Charges the CRCs and
 * the copy to @p work.
 */
ProductCheck landmark_product_load(std::span<const std::uint8_t> bytes, const vision::SelectParams& params,
                                   const ProductLayer& layer, vision::LandmarkTable& table, bsp::Work& work) noexcept;

}  // namespace trn::tasks
