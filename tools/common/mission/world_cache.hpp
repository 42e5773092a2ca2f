/**
 * @file world_cache.hpp
 * @brief A folder of built world products (terrain grid, reference-map product, the ground's
 *        landmark table) kept between runs.
 *
 * Building the terrain and rendering the map product cost seconds per run;
 * a campaign of thousands of runs of one scenario builds them once. Each file
 * is named by a key over every parameter that builds it (and the format), so
 * a changed scenario never reads another's world; files are written under a
 * temporary name and renamed into place, so runs in parallel never read a torn
 * one. A file that does not fit (size, magic, key) is ignored and built again.
 * The key also names the image's build (its file's size and time): an image
 * rebuilt with other world code never reads a world an older build wrote, and
 * writing a terrain removes the older builds' files from the folder.
 * The products read back are the bytes the build wrote: a run with the cache
 * flies to the same trace hash as one without.
 *
 * Host code: allocation and exceptions are fine here.
 */
#pragma once

#include "bsp_tile64/api/map_product.hpp"
#include "bsp_tile64/world/refmap.hpp"
#include "bsp_tile64/world/terrain.hpp"
#include "trn/vision/landmarks.hpp"

#include <cstdint>
#include <functional>
#include <string>

namespace tools {

class WorldCache {
 public:
  /** A cache in folder @p dir (created when first written); an empty @p dir is no cache. */
  explicit WorldCache(std::string dir = {}) : dir_(std::move(dir)) {}

  [[nodiscard]] bool enabled() const { return !dir_.empty(); }

  /** The terrain of @p cfg: restored from the cache, or built and then kept. False if it cannot be built. */
  bool terrain(const bsp::world::TerrainConfig& cfg, std::string& error);

  /** The map product of @p map over terrain @p cfg, carved into DDR: restored, or built and kept. */
  const bsp::MapProductHeader* map(const bsp::world::TerrainConfig& cfg, const bsp::world::MapConfig& map,
                                   bsp::world::WorldError& err);

  /**
   * The ground's landmark table of the map @p map over terrain @p cfg selected with @p params: read
   * into @p table, or made by @p select (which fills @p table, false on failure) and then kept. The
   * table read back is the bytes @p select wrote. False when @p select fails.
   */
  bool landmarks(const bsp::world::TerrainConfig& cfg, const bsp::world::MapConfig& map,
                 const trn::vision::SelectParams& params, trn::vision::LandmarkTable& table,
                 const std::function<bool(trn::vision::LandmarkTable&)>& select);

  /** Products read from the folder / built and written to it since this object was made. */
  [[nodiscard]] std::uint32_t hits() const { return hits_; }
  [[nodiscard]] std::uint32_t misses() const { return misses_; }

  /** The key of the terrain of @p cfg (hex), as in the file names. */
  static std::string terrain_key(const bsp::world::TerrainConfig& cfg);
  /** The key of the map product of @p map over the terrain of @p cfg. */
  static std::string map_key(const bsp::world::TerrainConfig& cfg, const bsp::world::MapConfig& map);

 private:
  std::string dir_;
  std::uint32_t hits_ = 0U;
  std::uint32_t misses_ = 0U;
};

}  // namespace tools
