/**
 * @file main.cpp
 * @brief The mission image: builds the world, boots the chip's tiles from their task tables,
 *        seals the heap and flies the descent.
 *
 * Today the image runs what exists end to end: the I/O tile forwards the IMU
 * over the UDN, the filter tile navigates at 100 Hz (IMU only: the vision
 * tiles join with the fault-tolerant network layer). Host time is measured
 * here, in the front end, never in emulated behaviour.
 */
#include "bsp_tile64/board.hpp"
#include "bsp_tile64/devices/device_bus.hpp"
#include "bsp_tile64/host/heap_guard.hpp"
#include "bsp_tile64/memory.hpp"
#include "bsp_tile64/trace.hpp"
#include "bsp_tile64/udn_net.hpp"
#include "bsp_tile64/world/terrain.hpp"
#include "bsp_tile64/world/trajectory.hpp"
#include "kernel/kernel.hpp"
#include "tools/common/memory_report.hpp"
#include "trn/tasks/filter_task.hpp"
#include "trn/tasks/io_task.hpp"
#include "trn/tasks/roles.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>

#include <unistd.h>

namespace {

constexpr bsp::TileId kIoTile = 9;
constexpr bsp::TileId kFilterTile = 18;

struct Options {
  std::uint64_t seed = 1;
  double duration_s = 20.0;
  bool quiet = false;
  bool memory_map = false;
};

bsp::world::Trajectory g_truth;
bsp::ImuModel g_imu;

/** Builds the world and the devices; everything here may allocate (before the seal). */
bool build_world(const Options& o) {
  bsp::world::TerrainConfig tc;
  tc.seed = o.seed;
  if (bsp::world::terrain_build(tc) != bsp::world::WorldError::kOk ||
      g_truth.init(bsp::world::TrajectoryConfig{}) != bsp::world::WorldError::kOk ||
      g_imu.init(&g_truth, bsp::ImuErrorConfig{}, o.seed) != bsp::ImuError::kOk) {
    std::fprintf(stderr, "trn_mission: cannot build the world\n");
    return false;
  }
  // The filter starts from the truth: the position and velocity errors of a
  // real start (km-level) need the vision tiles to be corrected.
  const bsp::world::TruthState t0 = g_truth.at(0.0);
  trn::tasks::g_filter_role_config.initial.x.p_m = t0.r_m;
  trn::tasks::g_filter_role_config.initial.x.v_mps = t0.v_mps;
  trn::tasks::g_filter_role_config.initial.x.q_mb = t0.q_mb;
  trn::tasks::g_filter_role_config.initial.sigma_p_m = trn::filter::Vec3::Constant(1.0);
  trn::tasks::g_filter_role_config.initial.sigma_v_mps = trn::filter::Vec3::Constant(0.05);
  return true;
}

/** Powers the tiles of the roles, registers their tables, starts the network and devices. */
bool boot_chip(const Options& o) {
  bsp::BoardConfig cfg = bsp::default_config(bsp::kTile64);
  cfg.seed = o.seed;
  cfg.powered_at_start = (1ULL << kIoTile) | (1ULL << kFilterTile);  // the rest stay off
  cfg.monitor_tile = bsp::kNoTile;
  cfg.boot[kIoTile] = &k::boot_entry;
  cfg.boot[kFilterTile] = &k::boot_entry;
  trn::tasks::g_io_role_config.filter_tile = kFilterTile;
  k::set_task_table(kIoTile, trn::tasks::kIoRole, cfg.tick_cycles);
  k::set_task_table(kFilterTile, trn::tasks::kFilterRole, cfg.tick_cycles);
  bsp::DeviceBusConfig bus;
  bus.io_tile = kIoTile;
  bus.imu = &g_imu;
  bus.last_time_s = o.duration_s;
  if (bsp::board_init(cfg) != bsp::BoardError::kOk || bsp::udn_net_init(bsp::NetConfig{}) != bsp::NetError::kOk ||
      bsp::attach_devices(bus) != bsp::DeviceBusError::kOk) {
    std::fprintf(stderr, "trn_mission: cannot boot the chip\n");
    return false;
  }
  return true;
}

struct NavError {
  double position_m;
  double three_sigma_m;
  double altitude_m;
  double t_s;
};

NavError nav_error() {
  trn::filter::NavOutput o{};
  if (!trn::tasks::filter_task_output(kFilterTile, &o)) {
    return NavError{NAN, NAN, NAN, 0.0};
  }
  const bsp::world::TruthState t = g_truth.at(o.t_s);
  const double dx = o.p_m[0] - t.r_m.x();
  const double dy = o.p_m[1] - t.r_m.y();
  const double dz = o.p_m[2] - t.r_m.z();
  return NavError{std::sqrt(dx * dx + dy * dy + dz * dz),
                  3.0 * std::sqrt(o.var_diag[0] + o.var_diag[1] + o.var_diag[2]), t.r_m.z(), o.t_s};
}

/** Flies the descent in one-second steps with a progress line. Nothing here may allocate. */
void fly(const Options& o) {
  const bsp::Cycles second = bsp::kTile64.clock_hz;
  const auto steps = static_cast<std::uint32_t>(std::ceil(o.duration_s));
  // On a terminal the progress line rewrites itself; in a log, one line every 5 s.
  const bool tty = ::isatty(::fileno(stdout)) != 0;
  for (std::uint32_t s = 0; s < steps; ++s) {
    (void)bsp::run_for(second);
    if (o.quiet || (!tty && (s + 1U) % 5U != 0U && s + 1U != steps)) {
      continue;
    }
    const NavError e = nav_error();
    std::printf("%s  t %5.1f s  altitude %6.0f m  position error %7.3f m (3-sigma %7.3f m)%s", tty ? "\r" : "",
                e.t_s, e.altitude_m, e.position_m, e.three_sigma_m, tty ? "" : "\n");
    std::fflush(stdout);
  }
  if (!o.quiet && tty) {
    std::printf("\n");
  }
}

void summary(double host_s, const Options& o) {
  const NavError e = nav_error();
  const trn::tasks::FilterTaskStats fs = trn::tasks::filter_task_stats(kFilterTile);
  k::TaskStats ks{};
  (void)k::task_stats(kFilterTile, k::find_task(kFilterTile, "filter"), &ks);
  std::printf("summary\n");
  std::printf("  emulated time          %.2f s (host %.2f s, real-time factor %.1f)\n", o.duration_s, host_s,
              o.duration_s / host_s);
  std::printf("  final position error   %.3f m (3-sigma %.3f m), IMU-only navigation\n", e.position_m,
              e.three_sigma_m);
  std::printf("  filter jobs            %u (IMU samples %u, worst job %.3f ms of 10 ms)\n", fs.jobs, fs.imu_used,
              static_cast<double>(fs.max_job_cycles) * 1000.0 / static_cast<double>(bsp::kTile64.clock_hz));
  std::printf("  deadline misses        %u, overruns %u\n", ks.deadline_misses, ks.overruns);
  std::printf("  heap allocs after init %llu\n", static_cast<unsigned long long>(bsp::heap::allocs_after_seal()));
  std::printf("  trace hash             %016llx\n", static_cast<unsigned long long>(bsp::trace_hash()));
}

int run(int argc, char** argv) {
  CLI::App app{"trn_mission: terrain relative navigation on an emulated TILE64"};
  Options o;
  app.add_option("--seed", o.seed, "Seed of the world, sensors and faults")->check(CLI::Range(0ULL, ~0ULL));
  app.add_option("--duration", o.duration_s, "Emulated seconds to fly (1..46)")->check(CLI::Range(1.0, 46.0));
  app.add_flag("--quiet", o.quiet, "No progress line");
  app.add_flag("--memory-map", o.memory_map, "Print the memory map after the run");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  std::printf("trn_mission: building the world (seed %llu)\n", static_cast<unsigned long long>(o.seed));
  if (!build_world(o) || !boot_chip(o)) {
    return 1;
  }
  std::printf("trn_mission: booted I/O tile %u and filter tile %u; heap sealed; flying %.0f s\n", kIoTile,
              kFilterTile, o.duration_s);
  std::fflush(stdout);
  const auto t0 = std::chrono::steady_clock::now();
  bsp::heap::seal(bsp::heap::SealMode::kFatal);
  fly(o);
  bsp::heap::unseal();
  const double host_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  summary(host_s, o);
  if (o.memory_map) {
    tools::write_memory_report(std::cout, bsp::kTile64.tiles());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "trn_mission: %s\n", e.what());
    return 1;
  }
}
