/**
 * @file tile_view.hpp
 * @brief The tile grid in the terminal: a power mark, a short role code and a health mark per tile, and a legend.
 *
 * Used by the image's --view (redrawn in place during the run, with the heap
 * sealed: render_tile_grid_to() writes into a caller's buffer and allocates
 * nothing) and by the end-of-run summary (render_tile_grid()).
 */
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace tools {

/**
 * What the outputs show of one tile. Role and health are short names (15
 * characters or fewer stay in the string's own storage, so updating them in
 * place during the run allocates nothing).
 */
struct TileInfo {
  /** "trn_supervisor", "vision_coordinator", "filter_supervisor", "io", "filter", "voter", "vision", "spare",
   *  "unused"; another name shows as its first two letters. */
  std::string role = "unused";
  /** "ok", "suspect", "failed", "recovered", "off"; another name shows as '!'. */
  std::string health = "ok";
  std::uint32_t faults_injected = 0U;
  std::uint32_t faults_detected = 0U;
  std::uint32_t faults_recovered = 0U;
  std::uint32_t resets = 0U;
  std::uint32_t deadline_misses = 0U;
  /** "off", "booting", "idle", "active" (bsp::power_state_name of the metered state); "" not known: no mark. */
  std::string power;
  double energy_j = 0.0;  ///< the tile's energy since the board started (bsp::tile_energy)
};

/** Two-letter code of a role, NUL-terminated ("VI" for vision); an unknown role gives its first two letters, upper case. */
std::array<char, 3> tile_role_code(std::string_view role) noexcept;

/** Mark of a health: '.' ok, '?' suspect, 'X' failed, '+' recovered, '-' off, '!' anything else. */
char tile_health_mark(std::string_view health) noexcept;

/** Mark of a power state: '*' active, '~' idle, '^' booting, '_' off, ' ' not known (""), '!' anything else. */
char tile_power_mark(std::string_view power) noexcept;

/** Fill colour of a role in the tile-map plot, 0xRRGGBB (grey for an unknown role). */
std::uint32_t tile_role_rgb(std::string_view role) noexcept;

/** 0 ok, 1 suspect, 2 failed, 3 recovered, 4 off, 5 anything else (the tile-map plot's column health_code). */
std::uint32_t tile_health_code(std::string_view health) noexcept;

/** Bytes render_tile_grid_to() may need for a cols x rows grid (colours and legend included). */
std::size_t tile_grid_bytes_bound(std::uint32_t cols, std::uint32_t rows) noexcept;

/**
 * Writes the grid (tile i at row i / cols, column i % cols; a tile missing from
 * @p tiles shows as blank; each cell is the power mark, the role code and the
 * health mark), then the legend of the roles present, of the health marks and,
 * if any tile's power state is known, of the power marks, into @p out,
 * NUL-terminated. Every line ends with '\n'.
 * @p ansi_colors colours each cell by health (green ok, yellow suspect, red
 * failed, cyan recovered, dim off). Allocates nothing.
 * @return the bytes written (without the NUL); the text is cut at a line end
 *         when @p out is smaller than tile_grid_bytes_bound().
 */
std::size_t render_tile_grid_to(std::uint32_t cols, std::uint32_t rows, std::span<const TileInfo> tiles,
                                bool ansi_colors, std::span<char> out) noexcept;

/** The same text as a string. */
std::string render_tile_grid(std::uint32_t cols, std::uint32_t rows, const std::vector<TileInfo>& tiles,
                             bool ansi_colors);

}  // namespace tools
