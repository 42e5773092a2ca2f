/**
 * @file terrain.hpp
 * @brief The planetary surface (truth): height map, albedo and pre-shaded radiance from a seed.
 *
 * A square grid of size_px x size_px samples, m_per_px apart, centred on the
 * map-frame origin (frames.hpp): sample (ix, iy) sits at
 * x = (ix - (n-1)/2) * m_per_px (east), y = (iy - (n-1)/2) * m_per_px (north).
 * Heights are metres above the datum. Relief is fractal value noise (several
 * octaves), then craters drawn from a power-law size-frequency distribution
 * (cumulative N(>D) ~ D^-b: many small, few large; bowl, raised rim, bright
 * ejecta), then boulders. All storage is static (.bss) at the capacity
 * kMaxTerrainPx; the size in use is a runtime parameter within it.
 *
 * Only the board (world, devices) may include this header: it is the truth.
 */
#pragma once

#include <cstdint>
#include <span>

namespace bsp::world {

/** Static capacity of the grid, samples per side. */
inline constexpr std::uint32_t kMaxTerrainPx = 4096;

enum class WorldError : std::uint8_t {
  kOk,
  kBadConfig,    ///< a parameter out of its documented range
  kNotBuilt,     ///< terrain queried or shaded before terrain_build()
  kNoMemory,     ///< a DDR carve failed
  kOutOfRange,   ///< a query outside its valid domain
};

struct TerrainConfig {
  std::uint64_t seed = 1;              ///< world seed (stream StreamId::kWorld)
  std::uint32_t size_px = 4096;        ///< samples per side, 64..kMaxTerrainPx
  double m_per_px = 4.0;               ///< sample spacing, metres, 0.5..50
  double relief_m = 60.0;              ///< amplitude of the largest noise octave, metres, 0..1000
  double base_wavelength_m = 3000.0;   ///< wavelength of the largest octave, metres
  std::uint32_t octaves = 7;           ///< noise octaves, 1..10 (each halves wavelength and amplitude)
  double crater_density_per_km2 = 25;  ///< craters of diameter >= crater_min_d_m per km^2, 0..1000
  double crater_min_d_m = 20.0;        ///< smallest crater diameter drawn, metres
  double crater_max_d_m = 1500.0;      ///< largest crater diameter drawn, metres
  double crater_sfd_exponent = 2.0;    ///< b in N(>D) ~ D^-b, 1..4
  double boulder_density_per_km2 = 60; ///< boulders per km^2, 0..1000
};

/** Sun direction: azimuth clockwise from north (deg), elevation above the horizon (deg). */
struct SunAngle {
  double azimuth_deg = 0.0;
  double elevation_deg = 45.0;
};

/** Unit vector towards the sun in the map frame (x east, y north, z up). */
void sun_vector(const SunAngle& sun, double out[3]) noexcept;

/**
 * Builds the terrain into the static grid from @p cfg (deterministic in cfg).
 * @return kBadConfig (grid untouched) if a parameter is out of range.
 * Invalidates the shaded image (terrain_shade() must be called again).
 */
WorldError terrain_build(const TerrainConfig& cfg) noexcept;

/** True once terrain_build() succeeded. */
bool terrain_ready() noexcept;

/** The configuration of the built terrain. */
const TerrainConfig& terrain_config() noexcept;

/** Half the side of the grid, metres: the terrain spans [-h, h]^2. */
double terrain_half_extent_m() noexcept;

/** Height above the datum at (x, y), metres, bilinear; clamped to the edge outside the grid. */
double terrain_height_m(double x_m, double y_m) noexcept;

/** Albedo at (x, y), 0..1, bilinear; clamped to the edge outside the grid. */
double terrain_albedo(double x_m, double y_m) noexcept;

/**
 * Lambert radiance (albedo * cos incidence, 0..1) at (x, y) under @p sun_dir
 * (unit, map frame), with the normal from central differences of the heights
 * at the grid spacing. Used to render products under any sun.
 */
double terrain_radiance(double x_m, double y_m, const double sun_dir[3]) noexcept;

/**
 * Pre-shades the whole grid under @p sun into the static radiance image
 * (uint16, 0..65535 for radiance 0..1) that the camera samples.
 * @return kNotBuilt before terrain_build().
 */
WorldError terrain_shade(const SunAngle& sun) noexcept;

/** True once terrain_shade() succeeded for the current terrain. */
bool terrain_shaded() noexcept;

/** Pre-shaded radiance at (x, y), 0..1, bilinear; 0 outside the grid. */
double terrain_shaded_radiance(double x_m, double y_m) noexcept;

/**
 * Paints a uniform disc of @p radiance (0..1) and @p radius_m around (x, y)
 * into the pre-shaded image: a calibration target whose position is known
 * exactly, for geometry checks of the renderer. Undone by terrain_shade().
 * @return kNotBuilt unless the terrain is shaded.
 */
WorldError terrain_paint_target(double x_m, double y_m, double radius_m, double radiance) noexcept;

namespace detail {
/** Crater diameter for the uniform draw @p u in [0, 1): inverse CDF of the truncated power law of @p cfg. */
double crater_diameter_m(double u, const TerrainConfig& cfg) noexcept;
/**
 * One grid sample. Height and shade share a cache line, so the renderer's
 * shade lookup after its last height lookup hits the cache.
 */
struct Cell {
  float height_m;       ///< above the datum
  std::uint16_t shade;  ///< pre-shaded radiance, 65535 = 1.0
  std::uint8_t albedo;  ///< 255 = 1.0
  std::uint8_t reserved;
};
static_assert(sizeof(Cell) == 8, "cells pack into 8 bytes");
/** Raw view for the renderer's inner loop (row-major, iy rows). */
const Cell* cell_data() noexcept;
}  // namespace detail

/** The built grid, size_px^2 cells row-major (empty before terrain_build()): what a world cache keeps. [host] */
std::span<const detail::Cell> terrain_cells() noexcept;

/**
 * Takes a grid kept from an earlier terrain_build(@p cfg) instead of building
 * it again (the same cells, bit for bit, as the build gives). The shade is
 * computed again by terrain_shade().
 * @return kBadConfig (grid untouched) if @p cfg is out of range or @p cells is
 * not size_px^2 cells.
 */
WorldError terrain_restore(const TerrainConfig& cfg, std::span<const detail::Cell> cells) noexcept;

}  // namespace bsp::world
