/**
 * @file main.cpp
 * @brief world_view: dumps a camera frame at time t and a region of the reference map as PGM (and PNG).
 *
 * Builds the world of a scenario (or the built-in default), renders the
 * camera frame of the truth pose at --time, and cuts a window of the fine or
 * coarse map layer. PGM is always written; a PNG beside it when a converter
 * (pnmtopng or ImageMagick's convert) is on the PATH. Bad arguments or a bad
 * scenario: a message on stderr and exit status 2.
 */
#include "bsp_tile64/emu/devices/camera.hpp"
#include "bsp_tile64/api/map_product.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/world/refmap.hpp"
#include "tools/common/mission/scenario.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <string>
#include <vector>

namespace {

constexpr int kUsageError = 2;

bool write_pgm(const std::string& path, const std::uint8_t* px, std::uint32_t w, std::uint32_t h) {
  std::ofstream out(path, std::ios::binary);
  out << "P5\n" << w << " " << h << "\n255\n";
  out.write(reinterpret_cast<const char*>(px), static_cast<std::streamsize>(std::size_t{w} * h));  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): bytes to a stream
  return static_cast<bool>(out);
}

/** Converts a PGM to PNG beside it if a converter exists; returns the PNG path or "". */
std::string to_png(const std::string& pgm) {
  std::string png = pgm.size() > 4 && pgm.substr(pgm.size() - 4) == ".pgm" ? pgm.substr(0, pgm.size() - 4) + ".png"
                                                                                   : pgm + ".png";
  if (std::system("command -v pnmtopng >/dev/null 2>&1") == 0) {
    if (std::system(("pnmtopng '" + pgm + "' > '" + png + "' 2>/dev/null").c_str()) == 0) {
      return png;
    }
  }
  if (std::system("command -v convert >/dev/null 2>&1") == 0) {
    if (std::system(("convert '" + pgm + "' '" + png + "' 2>/dev/null").c_str()) == 0) {
      return png;
    }
  }
  return "";
}

void report(const std::string& what, const std::string& pgm) {
  const std::string png = to_png(pgm);
  std::printf("world_view: %s -> %s%s%s\n", what.c_str(), pgm.c_str(), png.empty() ? "" : ", ",
              png.c_str());
}

struct Options {
  std::string scenario;
  double time_s = 0.0;
  std::string frame_path = "world_view_frame.pgm";
  std::string map_path;
  std::string layer = "fine";
  double map_x_m = 0.0;
  double map_y_m = 0.0;
  std::uint32_t map_size_px = 512;
};

int dump_map(const Options& o, const tools::Scenario& sc) {
  bsp::world::WorldError err = bsp::world::WorldError::kOk;
  const bsp::MapProductHeader* p = bsp::world::refmap_build(sc.map, &err);
  if (p == nullptr) {
    std::fprintf(stderr, "world_view: map product failed (error %d)\n", static_cast<int>(err));
    return 1;
  }
  const std::uint32_t l = o.layer == "coarse" ? bsp::kMapLayerCoarse : bsp::kMapLayerFine;
  const bsp::MapLayerHeader& h = p->layers[l];
  const double c0 = std::round((o.map_x_m - h.origin_x_m) / h.m_per_px) - o.map_size_px / 2.0;
  const double r0 = std::round((h.origin_y_m - o.map_y_m) / h.m_per_px) - o.map_size_px / 2.0;
  std::vector<std::uint8_t> win(std::size_t{o.map_size_px} * o.map_size_px, 0);
  for (std::uint32_t r = 0; r < o.map_size_px; ++r) {
    for (std::uint32_t c = 0; c < o.map_size_px; ++c) {
      const double col = c0 + c;
      const double row = r0 + r;
      if (col >= 0 && row >= 0 && col < h.width_px && row < h.height_px) {
        win[std::size_t{r} * o.map_size_px + c] =
            bsp::map_image(p, l)[static_cast<std::size_t>(row) * h.width_px + static_cast<std::size_t>(col)];
      }
    }
  }
  if (!write_pgm(o.map_path, win.data(), o.map_size_px, o.map_size_px)) {
    std::fprintf(stderr, "world_view: cannot write %s\n", o.map_path.c_str());
    return 1;
  }
  report(o.layer + " map around (" + std::to_string(o.map_x_m) + ", " + std::to_string(o.map_y_m) + ") m at " +
             std::to_string(h.m_per_px) + " m/px",
         o.map_path);
  return 0;
}

/** One Markdown table per section, the format docs/SCENARIO.md keeps (and a test checks). */
void print_keys() {
  std::string section;
  for (const tools::ScenarioKeyDoc& k : tools::scenario_keys()) {
    if (k.section != section) {
      section = k.section;
      std::printf("\n### [%s]\n\n| key | type | allowed | default | meaning |\n|---|---|---|---|---|\n",
                  section.c_str());
    }
    std::printf("| `%s` | %s | %s | %s | %s |\n", k.key.c_str(), k.type.c_str(), k.range.c_str(),
                k.default_value.c_str(), k.meaning.c_str());
  }
}

int run(int argc, char** argv) {
  CLI::App app{"world_view: dump a camera frame and a reference-map region of a scenario as PGM/PNG"};
  Options o;
  app.add_option("--scenario", o.scenario, "Scenario TOML file (default: the built-in scenario)");
  app.add_option("--time", o.time_s, "Capture time, s from the start of the descent")->check(CLI::Range(0.0, 1e4));
  app.add_option("--frame", o.frame_path, "Output PGM of the camera frame ('' to skip)");
  app.add_option("--map", o.map_path, "Output PGM of a map region (skipped if not given)");
  app.add_option("--layer", o.layer, "Map layer")->check(CLI::IsMember({"fine", "coarse"}));
  app.add_option("--map-x", o.map_x_m, "Centre of the map region, east, m");
  app.add_option("--map-y", o.map_y_m, "Centre of the map region, north, m");
  app.add_option("--map-size", o.map_size_px, "Side of the map region, px")->check(CLI::Range(16U, 8192U));
  bool keys = false;
  app.add_flag("--scenario-keys", keys, "Print the scenario keys as the Markdown table of docs/SCENARIO.md and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : kUsageError;
  }
  if (keys) {
    print_keys();
    return 0;
  }
  const tools::ScenarioResult sr =
      o.scenario.empty() ? tools::ScenarioResult{tools::default_scenario(), ""} : tools::load_scenario(o.scenario);
  if (!sr.ok()) {
    std::fprintf(stderr, "%s\n", sr.error.c_str());
    return kUsageError;
  }
  const tools::Scenario& sc = *sr.scenario;
  if (bsp::world::terrain_build(sc.terrain) != bsp::world::WorldError::kOk) {
    std::fprintf(stderr, "world_view: terrain configuration rejected\n");
    return kUsageError;
  }
  bsp::world::Trajectory traj;
  if (traj.init(sc.trajectory) != bsp::world::WorldError::kOk) {
    std::fprintf(stderr, "world_view: trajectory configuration rejected\n");
    return kUsageError;
  }
  if (!o.frame_path.empty()) {
    bsp::CameraDevice cam;
    if (cam.init(&traj, sc.camera, sc.seed) != bsp::CameraError::kOk) {
      std::fprintf(stderr, "world_view: camera configuration rejected\n");
      return kUsageError;
    }
    const bsp::FrameInfo f = cam.capture(o.time_s);
    if (f.error != bsp::CameraError::kOk || !write_pgm(o.frame_path, f.pixels, sc.camera.width_px, sc.camera.height_px)) {
      std::fprintf(stderr, "world_view: cannot render or write %s\n", o.frame_path.c_str());
      return 1;
    }
    const bsp::world::TruthState s = traj.at(o.time_s);
    report("frame at t=" + std::to_string(o.time_s) + " s, altitude " + std::to_string(s.r_m.z()) + " m, position (" +
               std::to_string(s.r_m.x()) + ", " + std::to_string(s.r_m.y()) + ")",
           o.frame_path);
  }
  return o.map_path.empty() ? 0 : dump_map(o, sc);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "world_view: %s\n", e.what());
    return 1;
  }
}
