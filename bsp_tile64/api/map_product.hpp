/**
 * @file map_product.hpp
 * @brief The reference-map product in shared DDR (interface control: what flight code reads).
 *
 * Built at init by the board (bsp_tile64/world/refmap.*) the way an orbital
 * product is made: orthoimages under another sun than the descent, with an
 * elevation layer. Flight code finds it with map_product_find() and reads it
 * through this header only; it never sees the world's truth.
 *
 * Layout: one DDR carve named kMapProductCarveName, starting with a
 * MapProductHeader; layer arrays follow at the offsets the header gives (bytes
 * from the start of the header, 64-byte aligned). Each layer is
 * width x height pixels, row-major, row 0 at the north edge:
 *   pixel (col, row) is centred at x = origin_x_m + col * m_per_px (east),
 *                                   y = origin_y_m - row * m_per_px (north),
 *   image: uint8 DN (radiance under the map sun, dn_per_radiance DN for radiance 1),
 *   elevation: int16, height above the datum = value * elevation_scale_m.
 * Each pixel's 3D position in the map frame (frames.hpp) is therefore
 * (x, y, elevation) with map_pixel_position().
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"

#include <cstdint>
#include <cstring>

namespace bsp {

inline constexpr std::uint32_t kMapProductMagic = 0x4D415031U;  // "MAP1"
inline constexpr std::uint32_t kMapProductVersion = 1;
inline constexpr const char* kMapProductCarveName = "map_product";
inline constexpr std::uint32_t kMapLayers = 2;
inline constexpr std::uint32_t kMapLayerFine = 0;    ///< 6 m/px nominal
inline constexpr std::uint32_t kMapLayerCoarse = 1;  ///< 12 m/px nominal

struct MapLayerHeader {
  std::uint32_t width_px;
  std::uint32_t height_px;
  double m_per_px;
  double origin_x_m;          ///< map-frame x of the centre of pixel (0, 0)
  double origin_y_m;          ///< map-frame y of the centre of pixel (0, 0)
  double elevation_scale_m;   ///< metres per elevation count (0.1: decimetres)
  double dn_per_radiance;     ///< image DN for Lambert radiance 1.0
  std::uint64_t image_offset;      ///< bytes from the product start to the uint8 image
  std::uint64_t elevation_offset;  ///< bytes from the product start to the int16 elevation
};

struct MapProductHeader {
  std::uint32_t magic;
  std::uint32_t version;
  std::uint32_t layer_count;
  std::uint32_t reserved;
  double sun_azimuth_deg;     ///< sun of the orbital images (clockwise from north)
  double sun_elevation_deg;
  std::uint64_t total_bytes;  ///< header and all layers
  MapLayerHeader layers[kMapLayers];
};

/** The image of layer @p l of product @p p. */
inline const std::uint8_t* map_image(const MapProductHeader* p, std::uint32_t l) noexcept {
  return reinterpret_cast<const std::uint8_t*>(p) + p->layers[l].image_offset;  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): product bytes
}

/** The elevation of layer @p l of product @p p. */
inline const std::int16_t* map_elevation(const MapProductHeader* p, std::uint32_t l) noexcept {
  return reinterpret_cast<const std::int16_t*>(  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): product bytes
      reinterpret_cast<const std::uint8_t*>(p) + p->layers[l].elevation_offset);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): product bytes
}

/** Map-frame position (x, y, z metres) of pixel (@p col, @p row) of layer @p l. Pre: inside the layer. */
inline void map_pixel_position(const MapProductHeader* p, std::uint32_t l, std::uint32_t col, std::uint32_t row,
                               double out_m[3]) noexcept {
  const MapLayerHeader& h = p->layers[l];
  out_m[0] = h.origin_x_m + static_cast<double>(col) * h.m_per_px;
  out_m[1] = h.origin_y_m - static_cast<double>(row) * h.m_per_px;
  out_m[2] = static_cast<double>(map_elevation(p, l)[static_cast<std::uint64_t>(row) * h.width_px + col]) *
             h.elevation_scale_m;
}

/** Finds the product among the DDR carves; nullptr if absent or its magic/version is wrong. */
inline const MapProductHeader* map_product_find() noexcept {
  const Region ddr{Region::kDdr};
  for (const CarveRecord& r : region_carves(ddr)) {
    if (r.what != nullptr && std::strcmp(r.what, kMapProductCarveName) == 0) {
      const auto* p = reinterpret_cast<const MapProductHeader*>(  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): product bytes
          region_span(ddr).data() + r.offset);
      return (p->magic == kMapProductMagic && p->version == kMapProductVersion) ? p : nullptr;
    }
  }
  return nullptr;
}

}  // namespace bsp
