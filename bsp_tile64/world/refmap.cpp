/**
 * @file refmap.cpp
 * @brief Orthoimage and elevation layers of the reference map, rendered from the terrain into DDR.
 */
#include "bsp_tile64/world/refmap.hpp"

#include "bsp_tile64/api/memory.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstddef>
#include <cstdint>

namespace bsp::world {
namespace {

constexpr double kElevationScaleM = 0.1;
constexpr std::uint64_t kAlign = 64;

std::uint64_t align_up(std::uint64_t v) noexcept { return (v + kAlign - 1U) & ~(kAlign - 1U); }

/** Lays out layer @p l of @p mpp over @p extent_m starting at byte @p offset; returns the end offset. */
std::uint64_t layout_layer(MapLayerHeader& h, double mpp, double extent_m, double dn, std::uint64_t offset) noexcept {
  const auto n = static_cast<std::uint32_t>(std::floor(extent_m / mpp));
  h.width_px = n;
  h.height_px = n;
  h.m_per_px = mpp;
  h.origin_x_m = -0.5 * static_cast<double>(n - 1U) * mpp;
  h.origin_y_m = 0.5 * static_cast<double>(n - 1U) * mpp;
  h.elevation_scale_m = kElevationScaleM;
  h.dn_per_radiance = dn;
  const std::uint64_t cells = std::uint64_t{n} * n;
  h.image_offset = align_up(offset);
  h.elevation_offset = align_up(h.image_offset + cells);
  return h.elevation_offset + cells * sizeof(std::int16_t);
}

/** Fills one layer: footprint means of radiance (map sun) and height over s x s sub-samples. */
void fill_layer(MapProductHeader* p, std::uint32_t l, const double sun[3]) noexcept {
  const MapLayerHeader& h = p->layers[l];
  const double terrain_mpp = terrain_config().m_per_px;
  const auto s = static_cast<std::uint32_t>(std::clamp(std::round(h.m_per_px / terrain_mpp), 2.0, 4.0));
  const double step = h.m_per_px / static_cast<double>(s);
  const double inv = 1.0 / static_cast<double>(s * s);
  std::uint8_t* img = reinterpret_cast<std::uint8_t*>(p) + h.image_offset;  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): product bytes
  auto* elev = reinterpret_cast<std::int16_t*>(img - h.image_offset + h.elevation_offset);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): product bytes
  for (std::uint32_t row = 0; row < h.height_px; ++row) {
    for (std::uint32_t col = 0; col < h.width_px; ++col) {
      const double x0 = h.origin_x_m + static_cast<double>(col) * h.m_per_px - 0.5 * h.m_per_px + 0.5 * step;
      const double y0 = h.origin_y_m - static_cast<double>(row) * h.m_per_px - 0.5 * h.m_per_px + 0.5 * step;
      double rad = 0.0;
      double z = 0.0;
      for (std::uint32_t j = 0; j < s; ++j) {
        for (std::uint32_t i = 0; i < s; ++i) {
          const double x = x0 + static_cast<double>(i) * step;
          const double y = y0 + static_cast<double>(j) * step;
          rad += terrain_radiance(x, y, sun);
          z += terrain_height_m(x, y);
        }
      }
      const std::size_t k = std::size_t{row} * h.width_px + col;
      img[k] = static_cast<std::uint8_t>(std::clamp(rad * inv * h.dn_per_radiance + 0.5, 0.0, 255.0));
      elev[k] = static_cast<std::int16_t>(std::clamp(std::round(z * inv / kElevationScaleM), -32767.0, 32767.0));
    }
  }
}

/** The product's place in DDR, @p bytes long (nullptr and kNoMemory in @p e when DDR is full). */
MapProductHeader* carve_product(std::uint64_t bytes, WorldError& e) noexcept {
  const Carve c = carve(Region{Region::kDdr}, bytes, kAlign, kMapProductCarveName);
  e = c.error == MemError::kOk ? WorldError::kOk : WorldError::kNoMemory;
  return reinterpret_cast<MapProductHeader*>(c.ptr);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): product bytes
}

}  // namespace

const MapProductHeader* refmap_build(const MapConfig& cfg, WorldError* err) noexcept {
  WorldError e = WorldError::kOk;
  const double terrain_side_m = 2.0 * terrain_half_extent_m();
  const double extent = cfg.extent_m > 0.0 ? cfg.extent_m : terrain_side_m;
  if (!terrain_ready()) {
    e = WorldError::kNotBuilt;
  } else if (cfg.fine_m_per_px < 1.0 || cfg.fine_m_per_px > 100.0 || cfg.coarse_m_per_px < cfg.fine_m_per_px ||
             cfg.coarse_m_per_px > 200.0 || extent > terrain_side_m || extent < 4.0 * cfg.coarse_m_per_px ||
             cfg.dn_per_radiance < 1.0 || cfg.dn_per_radiance > 10000.0) {
    e = WorldError::kBadConfig;
  }
  MapProductHeader hdr{};
  if (e == WorldError::kOk) {
    hdr.magic = kMapProductMagic;
    hdr.version = kMapProductVersion;
    hdr.layer_count = kMapLayers;
    hdr.sun_azimuth_deg = cfg.sun.azimuth_deg;
    hdr.sun_elevation_deg = cfg.sun.elevation_deg;
    std::uint64_t end = layout_layer(hdr.layers[kMapLayerFine], cfg.fine_m_per_px, extent, cfg.dn_per_radiance,
                                     sizeof(MapProductHeader));
    end = layout_layer(hdr.layers[kMapLayerCoarse], cfg.coarse_m_per_px, extent, cfg.dn_per_radiance, end);
    hdr.total_bytes = end;
  }
  MapProductHeader* p = e == WorldError::kOk ? carve_product(hdr.total_bytes, e) : nullptr;
  if (e == WorldError::kOk) {
    *p = hdr;
    double sun[3];
    sun_vector(cfg.sun, sun);
    fill_layer(p, kMapLayerFine, sun);
    fill_layer(p, kMapLayerCoarse, sun);
  }
  if (err != nullptr) {
    *err = e;
  }
  return e == WorldError::kOk ? p : nullptr;
}

const MapProductHeader* refmap_restore(std::span<const std::byte> bytes, WorldError* err) noexcept {
  WorldError e = WorldError::kOk;
  MapProductHeader hdr{};
  if (bytes.size() < sizeof(MapProductHeader)) {
    e = WorldError::kBadConfig;
  } else {
    std::memcpy(&hdr, bytes.data(), sizeof hdr);
    if (hdr.magic != kMapProductMagic || hdr.version != kMapProductVersion || hdr.layer_count != kMapLayers ||
        hdr.total_bytes != bytes.size()) {
      e = WorldError::kBadConfig;
    }
  }
  MapProductHeader* p = e == WorldError::kOk ? carve_product(hdr.total_bytes, e) : nullptr;
  if (e == WorldError::kOk) {
    std::memcpy(p, bytes.data(), bytes.size());
  }
  if (err != nullptr) {
    *err = e;
  }
  return e == WorldError::kOk ? p : nullptr;
}

}  // namespace bsp::world
