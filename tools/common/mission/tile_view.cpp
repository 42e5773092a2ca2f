/**
 * @file tile_view.cpp
 * @brief Terminal rendering of the tile grid into a fixed buffer (no allocation: --view redraws under the sealed heap).
 */
#include "tools/common/mission/tile_view.hpp"

#include <algorithm>
#include <cctype>
#include <cstdarg>
#include <cstdio>

namespace tools {
namespace {

struct RoleDef {
  const char* name;
  const char* code;
  const char* label;
  std::uint32_t rgb;  ///< plot fill colour
};

constexpr std::array<RoleDef, 11> kRoles = {{
    {"trn_supervisor", "TS", "TRN supervisor", 0x8C564BU},
    {"vision_coordinator", "VC", "vision coordinator", 0x9467BDU},
    {"filter_supervisor", "FS", "filter supervisor", 0xE377C2U},
    {"vision_supervisor", "VS", "vision supervisor", 0xBCBD22U},
    {"filter_replica", "FR", "filter replica (TMR)", 0x6BAED6U},
    {"io", "IO", "I/O (IMU, camera)", 0xFF7F0EU},
    {"filter", "FI", "filter", 0x1F77B4U},
    {"voter", "VO", "filter voter", 0x17BECFU},
    {"vision", "VI", "vision", 0x2CA02CU},
    {"spare", "SP", "spare", 0xC7C7C7U},
    {"unused", "--", "unused", 0xF0F0F0U},
}};
constexpr std::uint32_t kUnknownRoleRgb = 0x7F7F7FU;

struct HealthDef {
  const char* name;
  char mark;
  const char* ansi;  ///< SGR parameters
};

constexpr std::array<HealthDef, 5> kHealth = {{
    {"ok", '.', "32"},
    {"suspect", '?', "33"},
    {"failed", 'X', "1;31"},
    {"recovered", '+', "36"},
    {"off", '-', "2"},
}};
constexpr const char* kUnknownHealthAnsi = "35";

struct PowerDef {
  const char* name;
  char mark;
};

constexpr std::array<PowerDef, 4> kPower = {{
    {"active", '*'},
    {"idle", '~'},
    {"booting", '^'},
    {"off", '_'},
}};

const RoleDef* find_role(std::string_view role) noexcept {
  const auto* it = std::find_if(kRoles.begin(), kRoles.end(), [role](const RoleDef& r) { return role == r.name; });
  return it == kRoles.end() ? nullptr : &*it;
}

const HealthDef* find_health(std::string_view health) noexcept {
  const auto* it =
      std::find_if(kHealth.begin(), kHealth.end(), [health](const HealthDef& h) { return health == h.name; });
  return it == kHealth.end() ? nullptr : &*it;
}

/** Appends to a fixed buffer; once a write does not fit, nothing more is written. */
class Out {
 public:
  explicit Out(std::span<char> buf) noexcept : buf_(buf) {}

  void put(const char* fmt, ...) noexcept __attribute__((format(printf, 2, 3))) {
    if (full_ || buf_.empty()) {
      return;
    }
    std::va_list ap;
    va_start(ap, fmt);
    const std::size_t room = buf_.size() - used_;
    const int n = std::vsnprintf(buf_.data() + used_, room, fmt, ap);
    va_end(ap);
    if (n < 0 || static_cast<std::size_t>(n) >= room) {
      full_ = true;
      buf_[used_] = '\0';
      return;
    }
    used_ += static_cast<std::size_t>(n);
  }

  /** Marks a line end: the text is cut back to here if a later write overflows. */
  void line_end() noexcept {
    put("\n");
    if (!full_) {
      last_line_ = used_;
    }
  }

  std::size_t finish() noexcept {
    if (buf_.empty()) {
      return 0U;
    }
    if (full_) {
      used_ = last_line_;
    }
    buf_[used_] = '\0';
    return used_;
  }

 private:
  std::span<char> buf_;
  std::size_t used_ = 0U;
  std::size_t last_line_ = 0U;
  bool full_ = false;
};

constexpr std::size_t kLegendWidth = 76U;

/** Legend entries in one or more lines of at most kLegendWidth columns. */
class Legend {
 public:
  Legend(Out& out, const char* title) noexcept : out_(out), col_(std::char_traits<char>::length(title)) {
    out_.put("%s", title);
  }
  void entry(const char* code, std::string_view label) noexcept {
    const std::size_t w = 2U + std::char_traits<char>::length(code) + 1U + label.size();
    if (col_ + w > kLegendWidth && col_ > 7U) {
      out_.line_end();
      out_.put("       ");
      col_ = 7U;
    }
    out_.put("  %s %.*s", code, static_cast<int>(label.size()), label.data());
    col_ += w;
  }
  void end() noexcept { out_.line_end(); }

 private:
  Out& out_;
  std::size_t col_;
};

void role_legend(std::span<const TileInfo> tiles, Out& out) noexcept {
  Legend lg(out, "roles: ");
  for (const RoleDef& r : kRoles) {
    if (std::any_of(tiles.begin(), tiles.end(), [&r](const TileInfo& t) { return t.role == r.name; })) {
      lg.entry(r.code, r.label);
    }
  }
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const std::string_view role = tiles[i].role;
    const bool first = std::none_of(tiles.begin(), tiles.begin() + static_cast<std::ptrdiff_t>(i),
                                    [role](const TileInfo& t) { return t.role == role; });
    if (first && find_role(role) == nullptr) {
      const std::array<char, 3> code = tile_role_code(role);
      lg.entry(code.data(), role.empty() ? std::string_view("(no role)") : role);
    }
  }
  lg.end();
}

void health_legend(bool ansi, Out& out) noexcept {
  Legend lg(out, "health:");
  for (const HealthDef& h : kHealth) {
    const std::array<char, 2> mark = {h.mark, '\0'};
    if (ansi) {
      out.put("  \x1b[%sm%s\x1b[0m %s", h.ansi, mark.data(), h.name);
    } else {
      lg.entry(mark.data(), h.name);
    }
  }
  lg.end();
}

void power_legend(std::span<const TileInfo> tiles, Out& out) noexcept {
  if (std::all_of(tiles.begin(), tiles.end(), [](const TileInfo& t) { return t.power.empty(); })) {
    return;  // no power state known: no marks, no legend
  }
  Legend lg(out, "power: ");
  for (const PowerDef& p : kPower) {
    const std::array<char, 2> mark = {p.mark, '\0'};
    lg.entry(mark.data(), p.name);
  }
  lg.end();
}

void grid(std::uint32_t cols, std::uint32_t rows, std::span<const TileInfo> tiles, bool ansi, Out& out) noexcept {
  out.put("tile");
  for (std::uint32_t x = 0; x < cols; ++x) {
    out.put(" %3u", x);
  }
  out.line_end();
  for (std::uint32_t y = 0; y < rows; ++y) {
    out.put("%4u", y * cols);
    for (std::uint32_t x = 0; x < cols; ++x) {
      const std::size_t id = static_cast<std::size_t>(y) * cols + x;
      if (id >= tiles.size()) {
        out.put("    ");
        continue;
      }
      const TileInfo& t = tiles[id];
      const std::array<char, 3> code = tile_role_code(t.role);
      const char mark = tile_health_mark(t.health);
      const char power = tile_power_mark(t.power);
      if (ansi) {
        const HealthDef* h = find_health(t.health);
        out.put(" %c\x1b[%sm%s%c\x1b[0m", power, h != nullptr ? h->ansi : kUnknownHealthAnsi, code.data(), mark);
      } else {
        out.put(" %c%s%c", power, code.data(), mark);
      }
    }
    out.line_end();
  }
}

}  // namespace

std::array<char, 3> tile_role_code(std::string_view role) noexcept {
  const RoleDef* r = find_role(role);
  if (r != nullptr) {
    return {r->code[0], r->code[1], '\0'};
  }
  std::array<char, 3> code = {'?', '?', '\0'};
  for (std::size_t i = 0; i < 2U && i < role.size(); ++i) {
    const auto c = static_cast<unsigned char>(role[i]);
    code[i] = std::isprint(c) != 0 ? static_cast<char>(std::toupper(c)) : '?';
  }
  return code;
}

char tile_power_mark(std::string_view power) noexcept {
  if (power.empty()) {
    return ' ';
  }
  const auto* it = std::find_if(kPower.begin(), kPower.end(), [power](const PowerDef& p) { return power == p.name; });
  return it == kPower.end() ? '!' : it->mark;
}

std::uint32_t tile_role_rgb(std::string_view role) noexcept {
  const RoleDef* r = find_role(role);
  return r != nullptr ? r->rgb : kUnknownRoleRgb;
}

std::uint32_t tile_health_code(std::string_view health) noexcept {
  const HealthDef* h = find_health(health);
  return h != nullptr ? static_cast<std::uint32_t>(h - kHealth.data()) : static_cast<std::uint32_t>(kHealth.size());
}

char tile_health_mark(std::string_view health) noexcept {
  const HealthDef* h = find_health(health);
  return h != nullptr ? h->mark : '!';
}

std::size_t tile_grid_bytes_bound(std::uint32_t cols, std::uint32_t rows) noexcept {
  // A coloured cell is " *\x1b[1;31mVIX\x1b[0m" (19 bytes); the legends fit in 1 KiB
  // with the known roles, plus one entry per tile for unknown roles.
  const std::size_t tiles = static_cast<std::size_t>(cols) * rows;
  return 8U + 4U * cols + rows * (6U + 20U * cols) + 1024U + 48U * tiles;
}

std::size_t render_tile_grid_to(std::uint32_t cols, std::uint32_t rows, std::span<const TileInfo> tiles,
                                bool ansi_colors, std::span<char> out) noexcept {
  Out o(out);
  grid(cols, rows, tiles, ansi_colors, o);
  const std::size_t shown = std::min(tiles.size(), static_cast<std::size_t>(cols) * rows);
  role_legend(tiles.first(shown), o);
  health_legend(ansi_colors, o);
  power_legend(tiles.first(shown), o);
  return o.finish();
}

std::string render_tile_grid(std::uint32_t cols, std::uint32_t rows, const std::vector<TileInfo>& tiles,
                             bool ansi_colors) {
  std::string s(tile_grid_bytes_bound(cols, rows), '\0');
  const std::size_t n = render_tile_grid_to(cols, rows, tiles, ansi_colors, s);
  s.resize(n);
  return s;
}

}  // namespace tools
