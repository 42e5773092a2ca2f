/**
 * @file refmap.hpp
 * @brief Builds the reference-map product (devices/map_product.hpp) from the terrain, as an orbital product.
 *
 * Each map pixel is the mean Lambert radiance over a sub-sample grid of its
 * footprint, under the map sun (another azimuth and elevation than the
 * descent), and the mean height over the same footprint in decimetres. The
 * product is carved once in shared DDR under kMapProductCarveName.
 */
#pragma once

#include "bsp_tile64/api/map_product.hpp"
#include "bsp_tile64/world/terrain.hpp"

#include <cstddef>
#include <span>

namespace bsp::world {

struct MapConfig {
  double fine_m_per_px = 6.0;     ///< 1..100
  double coarse_m_per_px = 12.0;  ///< fine..200
  double extent_m = 0.0;          ///< side of the mapped square centred on the origin; 0: whole terrain
  SunAngle sun{250.0, 50.0};      ///< orbital imaging sun
  double dn_per_radiance = 600.0; ///< image DN for radiance 1.0, 1..10000
};

/**
 * Builds the product into DDR (needs terrain_build()).
 * @param[out] err kOk, kNotBuilt, kBadConfig (extent larger than the terrain, bad resolution), kNoMemory.
 * @return the product, or nullptr on error.
 */
const MapProductHeader* refmap_build(const MapConfig& cfg, WorldError* err) noexcept;

/**
 * Carves the product into DDR from @p bytes kept from an earlier
 * refmap_build() (a world cache), instead of rendering it again.
 * @param[out] err kOk; kBadConfig if @p bytes is not a whole product (magic,
 * version, layer count, total size); kNoMemory.
 * @return the product, or nullptr on error. [host]
 */
const MapProductHeader* refmap_restore(std::span<const std::byte> bytes, WorldError* err) noexcept;

}  // namespace bsp::world
