/**
 * @file terrain.cpp
 * @brief Procedural terrain: fractal value noise, power-law craters, boulders, Lambert shading.
 */
#include "bsp_tile64/world/terrain.hpp"

#include "bsp_tile64/emu/rng.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace bsp::world {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::size_t kCells = std::size_t{kMaxTerrainPx} * kMaxTerrainPx;

// The grid: truth, static so the board never touches the heap.
detail::Cell g_cells[kCells];

TerrainConfig g_cfg;
std::uint32_t g_n = 0;
double g_half_m = 0.0;
double g_centre_px = 0.0;
bool g_built = false;
bool g_shaded = false;

std::size_t cell(std::uint32_t ix, std::uint32_t iy) noexcept { return std::size_t{iy} * g_n + ix; }

/** Integer lattice hash: the world's keys come from bsp::Rng, the mixing is SplitMix64's finaliser. */
double lattice(std::uint64_t key, std::int64_t ix, std::int64_t iy) noexcept {
  std::uint64_t h = key ^ (static_cast<std::uint64_t>(ix) * 0x9E3779B97F4A7C15ULL) ^
                    (static_cast<std::uint64_t>(iy) * 0xC2B2AE3D27D4EB4FULL);
  h = (h ^ (h >> 30U)) * 0xBF58476D1CE4E5B9ULL;
  h = (h ^ (h >> 27U)) * 0x94D049BB133111EBULL;
  h ^= h >> 31U;
  return static_cast<double>(h >> 11U) * 0x1.0p-52 - 1.0;  // [-1, 1)
}

/** Smooth value noise in [-1, 1] at lattice coordinates (x, y). */
double value_noise(std::uint64_t key, double x, double y) noexcept {
  const double fx0 = std::floor(x);
  const double fy0 = std::floor(y);
  const auto ix = static_cast<std::int64_t>(fx0);
  const auto iy = static_cast<std::int64_t>(fy0);
  double fx = x - fx0;
  double fy = y - fy0;
  fx = fx * fx * (3.0 - 2.0 * fx);
  fy = fy * fy * (3.0 - 2.0 * fy);
  const double a = lattice(key, ix, iy);
  const double b = lattice(key, ix + 1, iy);
  const double c = lattice(key, ix, iy + 1);
  const double d = lattice(key, ix + 1, iy + 1);
  return (a + (b - a) * fx) + ((c + (d - c) * fx) - (a + (b - a) * fx)) * fy;
}

bool config_valid(const TerrainConfig& c) noexcept {
  return c.size_px >= 64U && c.size_px <= kMaxTerrainPx && c.m_per_px >= 0.5 && c.m_per_px <= 50.0 &&
         c.relief_m >= 0.0 && c.relief_m <= 1000.0 && c.base_wavelength_m >= 10.0 && c.octaves >= 1U &&
         c.octaves <= 10U && c.crater_density_per_km2 >= 0.0 && c.crater_density_per_km2 <= 1000.0 &&
         c.crater_min_d_m > 0.0 && c.crater_max_d_m >= c.crater_min_d_m && c.crater_sfd_exponent >= 1.0 &&
         c.crater_sfd_exponent <= 4.0 && c.boulder_density_per_km2 >= 0.0 &&
         c.boulder_density_per_km2 <= 1000.0;
}

/** Fractal relief and albedo background: octave keys drawn from the world stream. */
void build_relief(Rng& rng) noexcept {
  constexpr std::uint32_t kMaxOctaves = 10;
  std::uint64_t keys[kMaxOctaves + 2];
  for (std::uint64_t& k : keys) {
    k = rng.next();
  }
  const double mpp = g_cfg.m_per_px;
  for (std::uint32_t iy = 0; iy < g_n; ++iy) {
    const double y = (static_cast<double>(iy) - g_centre_px) * mpp;
    for (std::uint32_t ix = 0; ix < g_n; ++ix) {
      const double x = (static_cast<double>(ix) - g_centre_px) * mpp;
      double h = 0.0;
      double amp = g_cfg.relief_m;
      double inv_wl = 1.0 / g_cfg.base_wavelength_m;
      for (std::uint32_t o = 0; o < g_cfg.octaves; ++o) {
        h += amp * value_noise(keys[o], x * inv_wl, y * inv_wl);
        amp *= 0.5;
        inv_wl *= 2.0;
      }
      // Albedo: dusty plains with broad brighter and darker units.
      const double wl_a = 1.0 / 1500.0;
      const double a = 0.22 + 0.05 * value_noise(keys[kMaxOctaves], x * wl_a, y * wl_a) +
                       0.02 * value_noise(keys[kMaxOctaves + 1], x * wl_a * 8.0, y * wl_a * 8.0);
      g_cells[cell(ix, iy)].height_m = static_cast<float>(h);
      g_cells[cell(ix, iy)].albedo = static_cast<std::uint8_t>(std::lround(std::clamp(a, 0.0, 1.0) * 255.0));
    }
  }
}

struct Crater {
  double x_m;
  double y_m;
  double d_m;
  double freshness;  ///< 1 fresh (deep, bright ejecta) .. 0.3 degraded
};

/** Crater relief and albedo change at normalised radius r (in crater radii). */
void crater_profile(const Crater& c, double r, double* dh_m, double* dalb) noexcept {
  const double depth = 0.2 * c.d_m * c.freshness;
  const double rim = 0.04 * c.d_m * c.freshness;
  if (r < 1.0) {
    *dh_m = rim + depth * (r * r - 1.0);
    *dalb = -0.03 * c.freshness * (1.0 - r * r);
    return;
  }
  // Ejecta blanket: height and brightness fall off outwards, tapered to zero at 2.5 radii.
  const double taper = std::clamp((2.5 - r) / 1.5, 0.0, 1.0);
  *dh_m = rim / (r * r * r) * taper;
  *dalb = 0.10 * c.freshness / (r * r) * taper;
}

void add_albedo(std::size_t k, double da) noexcept {
  const double a = static_cast<double>(g_cells[k].albedo) + da * 255.0;
  g_cells[k].albedo = static_cast<std::uint8_t>(std::lround(std::clamp(a, 0.0, 255.0)));
}

void stamp_crater(const Crater& c) noexcept {
  const double radius_m = 0.5 * c.d_m;
  const double reach_px = 2.5 * radius_m / g_cfg.m_per_px;
  const double cx = c.x_m / g_cfg.m_per_px + g_centre_px;
  const double cy = c.y_m / g_cfg.m_per_px + g_centre_px;
  const double n1 = static_cast<double>(g_n - 1U);
  const auto x0 = static_cast<std::uint32_t>(std::clamp(std::floor(cx - reach_px), 0.0, n1));
  const auto x1 = static_cast<std::uint32_t>(std::clamp(std::ceil(cx + reach_px), 0.0, n1));
  const auto y0 = static_cast<std::uint32_t>(std::clamp(std::floor(cy - reach_px), 0.0, n1));
  const auto y1 = static_cast<std::uint32_t>(std::clamp(std::ceil(cy + reach_px), 0.0, n1));
  for (std::uint32_t iy = y0; iy <= y1; ++iy) {
    for (std::uint32_t ix = x0; ix <= x1; ++ix) {
      const double dx = (static_cast<double>(ix) - cx) * g_cfg.m_per_px;
      const double dy = (static_cast<double>(iy) - cy) * g_cfg.m_per_px;
      const double r = std::sqrt(dx * dx + dy * dy) / radius_m;
      if (r >= 2.5) {
        continue;
      }
      double dh = 0.0;
      double da = 0.0;
      crater_profile(c, r, &dh, &da);
      g_cells[cell(ix, iy)].height_m += static_cast<float>(dh);
      add_albedo(cell(ix, iy), da);
    }
  }
}

/** Craters: diameters from a truncated Pareto (cumulative exponent b), by inverse CDF. */
void build_craters(Rng& rng) noexcept {
  const double side_km = static_cast<double>(g_n) * g_cfg.m_per_px / 1000.0;
  const double expected = g_cfg.crater_density_per_km2 * side_km * side_km;
  constexpr double kMaxCraters = 200000.0;
  const auto count = static_cast<std::uint32_t>(std::min(expected, kMaxCraters));
  for (std::uint32_t i = 0; i < count; ++i) {
    Crater c{};
    c.x_m = rng.uniform(-g_half_m, g_half_m);
    c.y_m = rng.uniform(-g_half_m, g_half_m);
    c.d_m = detail::crater_diameter_m(rng.uniform(), g_cfg);
    c.freshness = rng.uniform(0.3, 1.0);
    stamp_crater(c);
  }
}

/** Boulders: bumps of a few metres with bright tops, a sample or two across. */
void build_boulders(Rng& rng) noexcept {
  const double side_km = static_cast<double>(g_n) * g_cfg.m_per_px / 1000.0;
  constexpr double kMaxBoulders = 1.0e6;
  const auto count =
      static_cast<std::uint32_t>(std::min(g_cfg.boulder_density_per_km2 * side_km * side_km, kMaxBoulders));
  for (std::uint32_t i = 0; i < count; ++i) {
    const auto ix = static_cast<std::uint32_t>(rng.below(g_n - 2U)) + 1U;
    const auto iy = static_cast<std::uint32_t>(rng.below(g_n - 2U)) + 1U;
    const double h = rng.uniform(1.0, 4.0);
    g_cells[cell(ix, iy)].height_m += static_cast<float>(h);
    add_albedo(cell(ix, iy), 0.08);
    for (const std::size_t k : {cell(ix - 1U, iy), cell(ix + 1U, iy), cell(ix, iy - 1U), cell(ix, iy + 1U)}) {
      g_cells[k].height_m += static_cast<float>(0.4 * h);
    }
  }
}

/** Continuous grid coordinates of a map point. */
void to_grid(double x_m, double y_m, double* gx, double* gy) noexcept {
  *gx = x_m / g_cfg.m_per_px + g_centre_px;
  *gy = y_m / g_cfg.m_per_px + g_centre_px;
}

/** Bilinear sample of the member @p field of the cells, clamped to the edge. */
template <class T>
double bilinear(T detail::Cell::*field, double gx, double gy, double scale) noexcept {
  const double n1 = static_cast<double>(g_n - 1U);
  gx = std::clamp(gx, 0.0, n1);
  gy = std::clamp(gy, 0.0, n1);
  const auto ix = std::min(static_cast<std::uint32_t>(gx), g_n - 2U);
  const auto iy = std::min(static_cast<std::uint32_t>(gy), g_n - 2U);
  const double fx = gx - static_cast<double>(ix);
  const double fy = gy - static_cast<double>(iy);
  const detail::Cell* p = g_cells + cell(ix, iy);
  const double a = static_cast<double>(p[0].*field);
  const double b = static_cast<double>(p[1].*field);
  const double c = static_cast<double>(p[g_n].*field);
  const double d = static_cast<double>(p[g_n + 1U].*field);
  return scale * ((a + (b - a) * fx) + ((c + (d - c) * fx) - (a + (b - a) * fx)) * fy);
}

}  // namespace

void sun_vector(const SunAngle& sun, double out[3]) noexcept {
  const double az = sun.azimuth_deg * kPi / 180.0;
  const double el = sun.elevation_deg * kPi / 180.0;
  out[0] = std::sin(az) * std::cos(el);
  out[1] = std::cos(az) * std::cos(el);
  out[2] = std::sin(el);
}

namespace {

/** The grid's size and scale from @p cfg (valid); the shade is stale. */
void set_grid(const TerrainConfig& cfg) noexcept {
  g_cfg = cfg;
  g_n = cfg.size_px;
  g_centre_px = 0.5 * static_cast<double>(g_n - 1U);
  g_half_m = g_centre_px * cfg.m_per_px;
  g_shaded = false;
}

}  // namespace

WorldError terrain_build(const TerrainConfig& cfg) noexcept {
  if (!config_valid(cfg)) {
    return WorldError::kBadConfig;
  }
  set_grid(cfg);
  Rng rng(cfg.seed, StreamId::kWorld, 0);
  build_relief(rng);
  Rng crater_rng(cfg.seed, StreamId::kWorld, 1);
  build_craters(crater_rng);
  Rng boulder_rng(cfg.seed, StreamId::kWorld, 2);
  build_boulders(boulder_rng);
  g_built = true;
  return WorldError::kOk;
}

std::span<const detail::Cell> terrain_cells() noexcept {
  return g_built ? std::span<const detail::Cell>(g_cells, std::size_t{g_n} * g_n) : std::span<const detail::Cell>{};
}

WorldError terrain_restore(const TerrainConfig& cfg, std::span<const detail::Cell> cells) noexcept {
  if (!config_valid(cfg) || cells.size() != std::size_t{cfg.size_px} * cfg.size_px) {
    return WorldError::kBadConfig;
  }
  set_grid(cfg);
  std::copy(cells.begin(), cells.end(), g_cells);
  g_built = true;
  return WorldError::kOk;
}

bool terrain_ready() noexcept { return g_built; }

const TerrainConfig& terrain_config() noexcept { return g_cfg; }

double terrain_half_extent_m() noexcept { return g_half_m; }

double terrain_height_m(double x_m, double y_m) noexcept {
  double gx = 0.0;
  double gy = 0.0;
  to_grid(x_m, y_m, &gx, &gy);
  return bilinear(&detail::Cell::height_m, gx, gy, 1.0);
}

double terrain_albedo(double x_m, double y_m) noexcept {
  double gx = 0.0;
  double gy = 0.0;
  to_grid(x_m, y_m, &gx, &gy);
  return bilinear(&detail::Cell::albedo, gx, gy, 1.0 / 255.0);
}

double terrain_radiance(double x_m, double y_m, const double sun_dir[3]) noexcept {
  const double s = g_cfg.m_per_px;
  const double dhdx = (terrain_height_m(x_m + s, y_m) - terrain_height_m(x_m - s, y_m)) / (2.0 * s);
  const double dhdy = (terrain_height_m(x_m, y_m + s) - terrain_height_m(x_m, y_m - s)) / (2.0 * s);
  // Normal (-dh/dx, -dh/dy, 1) normalised.
  const double cos_i = (-dhdx * sun_dir[0] - dhdy * sun_dir[1] + sun_dir[2]) /
                       std::sqrt(dhdx * dhdx + dhdy * dhdy + 1.0);
  return terrain_albedo(x_m, y_m) * std::max(cos_i, 0.0);
}

WorldError terrain_shade(const SunAngle& sun) noexcept {
  if (!g_built) {
    return WorldError::kNotBuilt;
  }
  double s[3];
  sun_vector(sun, s);
  const double inv2 = 1.0 / (2.0 * g_cfg.m_per_px);
  for (std::uint32_t iy = 0; iy < g_n; ++iy) {
    const std::uint32_t ym = iy > 0U ? iy - 1U : iy;
    const std::uint32_t yp = iy + 1U < g_n ? iy + 1U : iy;
    for (std::uint32_t ix = 0; ix < g_n; ++ix) {
      const std::uint32_t xm = ix > 0U ? ix - 1U : ix;
      const std::uint32_t xp = ix + 1U < g_n ? ix + 1U : ix;
      const double dhdx = static_cast<double>(g_cells[cell(xp, iy)].height_m - g_cells[cell(xm, iy)].height_m) * inv2;
      const double dhdy = static_cast<double>(g_cells[cell(ix, yp)].height_m - g_cells[cell(ix, ym)].height_m) * inv2;
      const double cos_i = (-dhdx * s[0] - dhdy * s[1] + s[2]) / std::sqrt(dhdx * dhdx + dhdy * dhdy + 1.0);
      const double rad = static_cast<double>(g_cells[cell(ix, iy)].albedo) / 255.0 * std::max(cos_i, 0.0);
      g_cells[cell(ix, iy)].shade = static_cast<std::uint16_t>(std::lround(std::min(rad, 1.0) * 65535.0));
    }
  }
  g_shaded = true;
  return WorldError::kOk;
}

bool terrain_shaded() noexcept { return g_shaded; }

double terrain_shaded_radiance(double x_m, double y_m) noexcept {
  if (std::fabs(x_m) > g_half_m || std::fabs(y_m) > g_half_m) {
    return 0.0;
  }
  double gx = 0.0;
  double gy = 0.0;
  to_grid(x_m, y_m, &gx, &gy);
  return bilinear(&detail::Cell::shade, gx, gy, 1.0 / 65535.0);
}

WorldError terrain_paint_target(double x_m, double y_m, double radius_m, double radiance) noexcept {
  if (!g_shaded) {
    return WorldError::kNotBuilt;
  }
  double gx = 0.0;
  double gy = 0.0;
  to_grid(x_m, y_m, &gx, &gy);
  const double r_px = radius_m / g_cfg.m_per_px;
  const double n1 = static_cast<double>(g_n - 1U);
  const auto x0 = static_cast<std::uint32_t>(std::clamp(std::floor(gx - r_px), 0.0, n1));
  const auto x1 = static_cast<std::uint32_t>(std::clamp(std::ceil(gx + r_px), 0.0, n1));
  const auto y0 = static_cast<std::uint32_t>(std::clamp(std::floor(gy - r_px), 0.0, n1));
  const auto y1 = static_cast<std::uint32_t>(std::clamp(std::ceil(gy + r_px), 0.0, n1));
  const auto value = static_cast<std::uint16_t>(std::lround(std::clamp(radiance, 0.0, 1.0) * 65535.0));
  for (std::uint32_t iy = y0; iy <= y1; ++iy) {
    for (std::uint32_t ix = x0; ix <= x1; ++ix) {
      const double dx = static_cast<double>(ix) - gx;
      const double dy = static_cast<double>(iy) - gy;
      if (dx * dx + dy * dy <= r_px * r_px) {
        g_cells[cell(ix, iy)].shade = value;
      }
    }
  }
  return WorldError::kOk;
}

namespace detail {
double crater_diameter_m(double u, const TerrainConfig& cfg) noexcept {
  // Truncated Pareto: P(D > d) = ((d/Dmin)^-b - r) / (1 - r), r = (Dmin/Dmax)^b.
  const double b = cfg.crater_sfd_exponent;
  const double ratio = std::pow(cfg.crater_min_d_m / cfg.crater_max_d_m, b);
  return cfg.crater_min_d_m * std::pow(1.0 - u * (1.0 - ratio), -1.0 / b);
}
const Cell* cell_data() noexcept { return g_cells; }
}  // namespace detail

}  // namespace bsp::world
