/**
 * @file tile_view_test.cpp
 * @brief The terminal tile grid: layout, role codes, health and power marks, legend, colours, and no allocation when redrawn.
 */
#include "tools/common/mission/tile_view.hpp"

#include "tests/support/heap_probe.hpp"

#include <gtest/gtest.h>

#include <array>
#include <sstream>
#include <string>
#include <vector>

namespace {

std::vector<tools::TileInfo> default_tiles() {
  std::vector<tools::TileInfo> t(64U);
  t[0].role = "trn_supervisor";
  t[1].role = "vision_coordinator";
  t[2].role = "filter_supervisor";
  t[9].role = "io";
  t[18].role = "filter";
  for (std::size_t i = 24; i < 64U; ++i) {
    t[i].role = "vision";
  }
  t[44].health = "failed";
  t[25].health = "suspect";
  t[24].health = "recovered";
  t[60].role = "spare";
  t[61].role = "spare";
  t[61].health = "off";
  return t;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string l; std::getline(ss, l);) {
    out.push_back(l);
  }
  return out;
}

TEST(TileView, RoleCodesAndHealthMarks) {
  EXPECT_EQ(std::string(tools::tile_role_code("vision").data()), "VI");
  EXPECT_EQ(std::string(tools::tile_role_code("io").data()), "IO");
  EXPECT_EQ(std::string(tools::tile_role_code("trn_supervisor").data()), "TS");
  EXPECT_EQ(std::string(tools::tile_role_code("telemetry").data()), "TE") << "unknown role: its first letters";
  EXPECT_EQ(std::string(tools::tile_role_code("x").data()), "X?");
  EXPECT_EQ(tools::tile_health_mark("ok"), '.');
  EXPECT_EQ(tools::tile_health_mark("failed"), 'X');
  EXPECT_EQ(tools::tile_health_mark("suspect"), '?');
  EXPECT_EQ(tools::tile_health_mark("recovered"), '+');
  EXPECT_EQ(tools::tile_health_mark("off"), '-');
  EXPECT_EQ(tools::tile_health_mark("melted"), '!');
  EXPECT_EQ(tools::tile_health_code("failed"), 2U);
  EXPECT_EQ(tools::tile_health_code("melted"), 5U);
  EXPECT_NE(tools::tile_role_rgb("vision"), tools::tile_role_rgb("filter"));
}

TEST(TileView, EightByEightGridWithLegend) {
  const std::string s = tools::render_tile_grid(8U, 8U, default_tiles(), false);
  const std::vector<std::string> lines = lines_of(s);
  ASSERT_GE(lines.size(), 11U) << s;
  EXPECT_EQ(lines[0], "tile   0   1   2   3   4   5   6   7");
  EXPECT_EQ(lines[1], "   0  TS.  VC.  FS.  --.  --.  --.  --.  --.");
  EXPECT_EQ(lines[2], "   8  --.  IO.  --.  --.  --.  --.  --.  --.");
  EXPECT_EQ(lines[3], "  16  --.  --.  FI.  --.  --.  --.  --.  --.");
  EXPECT_EQ(lines[4], "  24  VI+  VI?  VI.  VI.  VI.  VI.  VI.  VI.");
  EXPECT_EQ(lines[6], "  40  VI.  VI.  VI.  VI.  VIX  VI.  VI.  VI.");
  EXPECT_EQ(lines[8], "  56  VI.  VI.  VI.  VI.  SP.  SP-  VI.  VI.");
  EXPECT_EQ(s.back(), '\n');
  EXPECT_NE(s.find("roles:   TS TRN supervisor  VC vision coordinator  FS filter supervisor"), std::string::npos)
      << s;
  EXPECT_EQ(lines[10], "         IO I/O (IMU, camera)  FI filter  VI vision  SP spare  -- unused") << "wrapped under the first";
  EXPECT_NE(s.find("SP spare"), std::string::npos) << s;
  EXPECT_EQ(s.find("VO filter voter"), std::string::npos) << "only the roles present are in the legend\n" << s;
  EXPECT_NE(s.find("health:  . ok  ? suspect  X failed  + recovered  - off"), std::string::npos) << s;
  EXPECT_EQ(s.find('\x1b'), std::string::npos) << "no escape codes without colours";
  for (const std::string& l : lines) {
    EXPECT_LE(l.size(), 80U) << l;
  }
}

TEST(TileView, PowerMarksPrecedeTheRoleCodeWithTheirLegend) {
  EXPECT_EQ(tools::tile_power_mark("active"), '*');
  EXPECT_EQ(tools::tile_power_mark("idle"), '~');
  EXPECT_EQ(tools::tile_power_mark("booting"), '^');
  EXPECT_EQ(tools::tile_power_mark("off"), '_');
  EXPECT_EQ(tools::tile_power_mark(""), ' ');
  EXPECT_EQ(tools::tile_power_mark("hibernating"), '!');
  std::vector<tools::TileInfo> t = default_tiles();
  for (tools::TileInfo& i : t) {
    i.power = "idle";
  }
  t[0].power = "active";
  t[2].power = "off";
  t[9].power = "booting";
  const std::string s = tools::render_tile_grid(8U, 8U, t, false);
  const std::vector<std::string> lines = lines_of(s);
  ASSERT_GE(lines.size(), 12U) << s;
  EXPECT_EQ(lines[1], "   0 *TS. ~VC. _FS. ~--. ~--. ~--. ~--. ~--.");
  EXPECT_EQ(lines[2], "   8 ~--. ^IO. ~--. ~--. ~--. ~--. ~--. ~--.");
  EXPECT_NE(s.find("power:   * active  ~ idle  ^ booting  _ off"), std::string::npos) << s;
  EXPECT_EQ(tools::render_tile_grid(8U, 8U, default_tiles(), false).find("power:"), std::string::npos)
      << "no power state known: no power legend";
  const std::string c = tools::render_tile_grid(8U, 8U, t, true);
  EXPECT_NE(c.find(" *\x1b[32mTS.\x1b[0m"), std::string::npos) << "the mark stays outside the health colour";
  EXPECT_EQ(lines_of(c).size(), lines.size());
}

TEST(TileView, ColoursFollowHealth) {
  const std::string s = tools::render_tile_grid(8U, 8U, default_tiles(), true);
  EXPECT_NE(s.find("\x1b[1;31mVIX\x1b[0m"), std::string::npos) << "a failed tile is red";
  EXPECT_NE(s.find("\x1b[33mVI?\x1b[0m"), std::string::npos) << "a suspect tile is yellow";
  EXPECT_NE(s.find("\x1b[32mTS.\x1b[0m"), std::string::npos) << "a healthy tile is green";
  EXPECT_NE(s.find("\x1b[2mSP-\x1b[0m"), std::string::npos) << "an off tile is dim";
  EXPECT_EQ(lines_of(s).size(), lines_of(tools::render_tile_grid(8U, 8U, default_tiles(), false)).size())
      << "same number of lines: the image redraws in place";
}

TEST(TileView, MissingTilesAndUnknownRolesStillRender) {
  std::vector<tools::TileInfo> t(10U);
  t[3].role = "telemetry";
  t[3].health = "melted";
  const std::string s = tools::render_tile_grid(4U, 4U, t, false);
  const std::vector<std::string> lines = lines_of(s);
  EXPECT_EQ(lines[1], "   0  --.  --.  --.  TE!");
  EXPECT_EQ(lines[3], "   8  --.  --.        ") << "tiles 10..15 are not known: blank";
  EXPECT_NE(s.find("TE telemetry"), std::string::npos) << s;
}

TEST(TileView, RedrawIntoABufferAllocatesNothing) {
  const std::vector<tools::TileInfo> tiles = default_tiles();
  std::vector<char> buf(tools::tile_grid_bytes_bound(8U, 8U));
  std::size_t n = 0U;
  const std::uint64_t allocs = test_support::count_allocs(
      [&] { n = tools::render_tile_grid_to(8U, 8U, tiles, true, std::span<char>(buf)); });
  EXPECT_EQ(allocs, 0U);
  EXPECT_EQ(std::string(buf.data(), n), tools::render_tile_grid(8U, 8U, tiles, true));
  EXPECT_EQ(buf[n], '\0');
}

TEST(TileView, ASmallBufferIsCutAtALineEnd) {
  const std::vector<tools::TileInfo> tiles = default_tiles();
  std::array<char, 100> buf{};
  const std::size_t n = tools::render_tile_grid_to(8U, 8U, tiles, false, buf);
  ASSERT_GT(n, 0U);
  ASSERT_LT(n, buf.size());
  EXPECT_EQ(buf[n], '\0');
  EXPECT_EQ(buf[n - 1U], '\n');
  EXPECT_EQ(std::string(buf.data(), n), tools::render_tile_grid(8U, 8U, tiles, false).substr(0, n));
  EXPECT_EQ(tools::render_tile_grid_to(8U, 8U, tiles, false, std::span<char>()), 0U);
}

}  // namespace
