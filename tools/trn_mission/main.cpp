/**
 * @file main.cpp
 * @brief The mission image: the whole chip booted from the tile map flies the descent, with
 *        faults injected by plan, and leaves a run folder behind.
 *
 * Order: every input is read and checked and the run folder's staging area is
 * made before anything runs (bad input: a message and exit status 2, nothing
 * written); the world is built and the chip booted; the heap is sealed; the
 * descent is flown in steps of kStepS emulated seconds, sampling the
 * navigation against the truth and turning what the flight code reports
 * (fault-tolerant messaging counters, the vision coordinator's events) into
 * the event log; then the heap is unsealed and the outputs written. Host time
 * is measured here, in the front end, never in emulated behaviour.
 */
#include "bsp_tile64/board.hpp"
#include "bsp_tile64/fault_injector.hpp"
#include "bsp_tile64/host/heap_guard.hpp"
#include "bsp_tile64/trace.hpp"
#include "kernel/kernel.hpp"
#include "tools/common/fault_plan.hpp"
#include "tools/common/memory_report.hpp"
#include "tools/common/mission.hpp"
#include "tools/common/run_folder.hpp"
#include "tools/common/scenario.hpp"
#include "tools/common/tile_view.hpp"
#include "trn/tasks/comm.hpp"
#include "trn/tasks/filter_task.hpp"
#include "trn/tasks/health.hpp"
#include "trn/tasks/tile_map.hpp"
#include "trn/tasks/vision_task.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <exception>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

namespace {

using trn::tasks::kCoordinatorTile;
using trn::tasks::kFilterTile;

constexpr double kStepS = 0.1;  ///< sampling step of the flight loop, emulated seconds
/** The position is "converged" once the filter's horizontal 3-sigma bound first falls below this. */
constexpr double kConvergedSigma3M = 30.0;

struct Options {
  std::string scenario_path;
  std::string faults_path;
  bool demo_faults = false;
  std::optional<std::uint64_t> seed;
  std::string out;
  double duration_s = 0.0;  ///< 0: the whole descent
  bool quiet = false;
  bool view = false;
  bool memory_map = false;
};

/** Everything checked before the run: scenario, plan, run folder. */
struct Inputs {
  tools::Scenario scenario;
  std::optional<tools::FaultPlan> plan;
  double duration_s = 0.0;
  std::optional<tools::RunFolder> folder;
};

int bad_input(const std::string& msg) {
  std::fprintf(stderr, "trn_mission: %s\n", msg.c_str());
  return 2;
}

/** Reads and checks every input; @return 0, or the exit status (2) after printing why. */
int prepare(const Options& o, Inputs& in) {
  if (o.scenario_path.empty()) {
    in.scenario = tools::default_scenario();
  } else {
    tools::ScenarioResult r = tools::load_scenario(o.scenario_path);
    if (!r.ok()) {
      return bad_input(r.error);
    }
    in.scenario = *r.scenario;
  }
  if (o.seed.has_value()) {
    in.scenario.seed = *o.seed;
    in.scenario.terrain.seed = *o.seed;
  }
  bsp::world::Trajectory probe;
  if (probe.init(in.scenario.trajectory) != bsp::world::WorldError::kOk) {
    return bad_input("the scenario's trajectory is not valid");
  }
  const double descent_s = std::floor(probe.duration_s());
  in.duration_s = o.duration_s > 0.0 ? o.duration_s : descent_s;
  if (in.duration_s > descent_s) {
    return bad_input("--duration " + std::to_string(o.duration_s) + ": the descent lasts " +
                     std::to_string(descent_s) + " s");
  }
  if (o.demo_faults && !o.faults_path.empty()) {
    return bad_input("--faults and --demo-faults exclude each other");
  }
  if (o.demo_faults) {
    in.plan = tools::demo_fault_plan();
  } else if (!o.faults_path.empty()) {
    tools::FaultPlanResult r = tools::load_fault_plan(o.faults_path, bsp::kTile64.tiles(), in.duration_s);
    if (!r.ok()) {
      return bad_input(r.error);
    }
    in.plan = *r.plan;
  }
  const std::string out = o.out.empty() ? "out/" + in.scenario.name + "-seed" + std::to_string(in.scenario.seed)
                                        : o.out;
  std::string error;
  in.folder = tools::RunFolder::open(out, error);
  if (!in.folder.has_value()) {
    return bad_input(error);
  }
  return 0;
}

// ------------------------------------------------------------------ what the flight code reports

struct FtTotals {
  std::uint64_t corrected = 0;
  std::uint64_t damaged = 0;
  std::uint64_t retransmitted = 0;
  std::uint64_t gave_up = 0;
};

/** Turns flight-code counters and events into the event log and the fault accounting; no allocation. */
class Observer {
 public:
  explicit Observer(tools::EventLog& log) : log_(log) {}

  void poll(double clock_hz) {
    poll_injections();
    poll_messaging(clock_hz);
    poll_health(clock_hz);
    poll_vision(clock_hz);
  }

  std::uint64_t injected() const { return injected_; }
  std::uint64_t detected() const { return detected_; }
  std::uint64_t recovered() const { return recovered_; }
  std::uint32_t frames() const { return frames_; }
  std::uint64_t matches() const { return matches_; }
  const std::array<std::uint32_t, bsp::kMaxTiles>& tile_faults() const { return tile_faults_; }
  const std::array<std::uint8_t, bsp::kMaxTiles>& tile_state() const { return tile_state_; }

  enum : std::uint8_t { kOk = 0, kSuspect = 1, kRecovered = 2, kFailed = 3 };

 private:
  void poll_injections() {
    const std::span<const bsp::FaultRecord> all = bsp::fault_log();
    for (; seen_faults_ < all.size(); ++seen_faults_) {
      const bsp::FaultRecord& r = all[seen_faults_];
      if (r.status == bsp::FaultStatus::kScheduled || r.status == bsp::FaultStatus::kArmed) {
        break;  // not applied yet: look again next step (lines are written after the flight)
      }
      if (r.status != bsp::FaultStatus::kApplied) {
        continue;
      }
      ++injected_;
      if (r.spec.tile < bsp::kMaxTiles) {
        ++tile_faults_[r.spec.tile];
      }
      if (r.spec.kind == bsp::FaultKind::kPacketBitFlip) {
        ++flips_pending_;
      } else if (r.spec.tile < bsp::kMaxTiles) {
        ++pending_[r.spec.tile];
      }
    }
  }

  void poll_messaging(double clock_hz) {
    const double t = static_cast<double>(bsp::board_time()) / clock_hz;
    for (bsp::TileId tile = 0; tile < bsp::kTile64.tiles(); ++tile) {
      const udn::FtNode* n = trn::tasks::comm_node(tile);
      if (n == nullptr) {
        continue;
      }
      FtTotals& last = ft_[tile];
      const std::uint64_t corrected = n->stats.corrected - last.corrected;
      const std::uint64_t damaged = n->stats.uncorrectable_detected - last.damaged;
      const std::uint64_t retx = n->stats.retransmitted - last.retransmitted;
      const std::uint64_t gave_up = n->stats.gave_up - last.gave_up;
      last = FtTotals{n->stats.corrected, n->stats.uncorrectable_detected, n->stats.retransmitted, n->stats.gave_up};
      for (std::uint64_t i = 0; i < corrected; ++i) {
        (void)log_.add(t, tools::EventCategory::kDetect, tile, "packet bit error found by the SECDED code");
        (void)log_.add(t, tools::EventCategory::kRecover, tile, "packet corrected and delivered");
        account_flip(true);
      }
      for (std::uint64_t i = 0; i < damaged; ++i) {
        (void)log_.add(t, tools::EventCategory::kDetect, tile, "packet damaged beyond correction: NACK");
        account_flip(false);
      }
      for (std::uint64_t i = 0; i < retx && damaged_unrecovered_ > 0U; ++i) {
        (void)log_.add(t, tools::EventCategory::kRecover, tile, "damaged packet retransmitted");
        --damaged_unrecovered_;
        ++recovered_;
      }
      if (gave_up > 0U) {
        (void)log_.addf(t, tools::EventCategory::kInfo, tile,
                        "%llu packet(s) given up after retries (receiver busy, or no route yet)",
                        static_cast<unsigned long long>(gave_up));
      }
    }
  }

  void account_flip(bool corrected) {
    if (flips_pending_ == 0U) {
      return;  // a detection without an injected flip would be a model error: not counted as ours
    }
    --flips_pending_;
    ++detected_;
    if (corrected) {
      ++recovered_;
    } else {
      ++damaged_unrecovered_;
    }
  }

  void poll_vision(double clock_hz) {
    const std::uint32_t count = trn::tasks::vision_coord_event_count(kCoordinatorTile);
    for (; seen_vision_ < count; ++seen_vision_) {
      trn::tasks::VisionEvent e{};
      if (!trn::tasks::vision_coord_event(kCoordinatorTile, seen_vision_, &e)) {
        continue;
      }
      const double t = static_cast<double>(e.cycle) / clock_hz;
      switch (e.kind) {
        case trn::tasks::VisionEventKind::kTileSilent:
          (void)log_.addf(t, tools::EventCategory::kDetect, kCoordinatorTile,
                          "vision tile %u silent for %u frames: isolated, its landmarks go to the others", e.tile,
                          trn::tasks::kSuspectAfterMisses);
          tile_state_[e.tile] = kSuspect;
          detect_tile_fault(e.tile);
          break;
        case trn::tasks::VisionEventKind::kTileBack:
          (void)log_.addf(t, tools::EventCategory::kRecover, kCoordinatorTile,
                          "vision tile %u answers again: back in the frame", e.tile);
          tile_state_[e.tile] = kRecovered;
          break;
        case trn::tasks::VisionEventKind::kFrameDone:
          ++frames_;
          matches_ += e.matches;
          if (awaiting_recovery_ > 0U && e.units_lost == 0U) {
            (void)log_.addf(t, tools::EventCategory::kRecover, kCoordinatorTile,
                            "frame %u complete without the failed tile(s): %u matches", e.frame, e.matches);
            recovered_ += awaiting_recovery_;
            awaiting_recovery_ = 0;
          }
          break;
      }
    }
  }

  /** An injected fault of @p tile (other than a packet flip) is found: detected, recovery pending. */
  void detect_tile_fault(bsp::TileId tile) {
    if (tile < bsp::kMaxTiles && pending_[tile] > 0U) {
      --pending_[tile];
      ++detected_;
      ++awaiting_recovery_;
    }
  }

  void poll_health(double clock_hz) {
    const std::uint32_t count = trn::tasks::health_event_count();
    for (; seen_health_ < count; ++seen_health_) {
      trn::tasks::HealthEvent e{};
      if (!trn::tasks::health_event(seen_health_, &e)) {
        continue;
      }
      const double t = static_cast<double>(e.cycle) / clock_hz;
      if (e.kind == trn::tasks::HealthEventKind::kReport) {
        (void)log_.addf(t, tools::EventCategory::kDetect, e.reporter,
                        "neighbour switch %u does not answer the probe (vote %u of %u)", e.suspect, e.votes,
                        trn::tasks::kVotesToFail);
        continue;
      }
      (void)log_.addf(t, tools::EventCategory::kDetect, trn::tasks::kSupervisorTile,
                      "switch of tile %u declared failed (%u neighbours agree)", e.suspect, e.votes);
      (void)log_.addf(t, tools::EventCategory::kRecover, trn::tasks::kSupervisorTile,
                      "fault map version %u published: every tile routes around tile %u", e.map_version, e.suspect);
      tile_state_[e.suspect] = kFailed;
      detect_tile_fault(e.suspect);
    }
  }

  tools::EventLog& log_;
  std::uint32_t seen_health_ = 0;
  std::array<std::uint32_t, bsp::kMaxTiles> pending_{};
  std::uint64_t awaiting_recovery_ = 0;
  std::size_t seen_faults_ = 0;
  std::uint32_t seen_vision_ = 0;
  std::array<FtTotals, bsp::kMaxTiles> ft_{};
  std::array<std::uint32_t, bsp::kMaxTiles> tile_faults_{};
  std::array<std::uint8_t, bsp::kMaxTiles> tile_state_{};
  std::uint64_t injected_ = 0;
  std::uint64_t detected_ = 0;
  std::uint64_t recovered_ = 0;
  std::uint64_t flips_pending_ = 0;
  std::uint64_t damaged_unrecovered_ = 0;
  std::uint32_t frames_ = 0;
  std::uint64_t matches_ = 0;
};

// ------------------------------------------------------------------ flight

struct FlightRecord {
  tools::NavSample last{};
  double max_error_after_convergence_m = 0.0;
  double converged_at_s = -1.0;
};

const char* health_name(bool on, std::uint8_t state) {
  if (!on) {
    return "off";
  }
  switch (state) {
    case Observer::kSuspect: return "suspect";
    case Observer::kRecovered: return "recovered";
    case Observer::kFailed: return "failed";
    default: return "ok";
  }
}

std::vector<tools::TileInfo> tile_infos(const tools::Mission& m, const Observer& obs) {
  std::vector<tools::TileInfo> v(bsp::kTile64.tiles());
  for (std::uint32_t t = 0; t < v.size(); ++t) {
    const trn::tasks::Role r = trn::tasks::kTileRoles[t];
    v[t].role = trn::tasks::role_name(r);
    const bool on = ((m.powered_mask() >> t) & 1ULL) != 0ULL;
    v[t].health = health_name(on, obs.tile_state()[t]);
    v[t].faults_injected = obs.tile_faults()[t];
  }
  return v;
}

void progress(const Options& o, const FlightRecord& rec, const Observer& obs, bool tty) {
  if (o.quiet) {
    return;
  }
  const tools::NavSample& n = rec.last;
  std::printf("%s  t %5.1f s  altitude %6.0f m  position error %9.2f m (3-sigma %8.2f m)  frames %3u  faults %llu%s",
              tty ? "\r" : "", n.t_s, n.altitude_m, n.position_error_m, n.sigma3_p.head<2>().norm(), obs.frames(),
              static_cast<unsigned long long>(obs.injected()), tty ? "" : "\n");
  std::fflush(stdout);
}

void fly(const Options& o, const tools::Mission& m, double duration_s, tools::NavCsv& csv, Observer& obs,
         FlightRecord& rec, std::vector<tools::TileInfo>& infos) {
  const double clock_hz = static_cast<double>(bsp::kTile64.clock_hz);
  const auto steps = static_cast<std::uint32_t>(std::llround(duration_s / kStepS));
  const bool tty = ::isatty(::fileno(stdout)) != 0;
  std::array<char, 8192> grid{};
  const std::uint32_t per_second = static_cast<std::uint32_t>(std::llround(1.0 / kStepS));
  for (std::uint32_t s = 1; s <= steps; ++s) {
    const auto target = static_cast<bsp::Cycles>(std::llround(s * kStepS * clock_hz));
    if (target > bsp::board_time()) {
      (void)bsp::run_for(target - bsp::board_time());
    }
    obs.poll(clock_hz);
    const tools::NavSample n = m.nav();
    if (!n.valid) {
      continue;
    }
    rec.last = n;
    tools::NavRow row;
    row.t_s = n.t_s;
    for (int i = 0; i < 3; ++i) {
      const auto k = static_cast<std::size_t>(i);
      row.truth_p_m[k] = n.truth_p[i];
      row.est_p_m[k] = n.est_p[i];
      row.truth_v_mps[k] = n.truth_v[i];
      row.est_v_mps[k] = n.est_v[i];
      row.sigma3_p_m[k] = n.sigma3_p[i];
    }
    row.attitude_error_deg = n.attitude_error_deg;
    (void)csv.write(row);
    if (rec.converged_at_s < 0.0 && n.sigma3_p.head<2>().norm() < kConvergedSigma3M) {
      rec.converged_at_s = n.t_s;
    }
    if (rec.converged_at_s >= 0.0) {
      rec.max_error_after_convergence_m = std::max(rec.max_error_after_convergence_m, n.position_error_m);
    }
    if (s % per_second != 0U && s != steps) {
      continue;
    }
    if (o.view) {
      // The grid's strings are rebuilt in place (same lengths), so the view allocates nothing.
      for (std::uint32_t t = 0; t < infos.size(); ++t) {
        const bool on = ((m.powered_mask() >> t) & 1ULL) != 0ULL;
        const std::uint8_t st = obs.tile_state()[t];  // NOLINT(readability-identifier-length)
        infos[t].health.assign(health_name(on, st));
        infos[t].faults_injected = obs.tile_faults()[t];
      }
      const std::size_t len =
          tools::render_tile_grid_to(bsp::kTile64.cols, bsp::kTile64.rows, infos, tty, grid);
      std::printf("%s%.*s", tty ? "\x1b[H\x1b[2J" : "\n", static_cast<int>(len), grid.data());
      progress(o, rec, obs, false);
    } else if (tty || s % (5U * per_second) == 0U || s == steps) {
      progress(o, rec, obs, tty);
    }
  }
  if (!o.quiet && tty && !o.view) {
    std::printf("\n");
  }
}

// ------------------------------------------------------------------ outputs

tools::Summary make_summary(const Inputs& in, const tools::Mission& m, const Observer& obs, const FlightRecord& rec,
                            double host_s, std::uint64_t allocs) {
  (void)m;
  tools::Summary s;
  s.scenario = in.scenario.name;
  s.fault_plan = in.plan.has_value() ? in.plan->name : "";
  s.seed = in.scenario.seed;
  s.emulated_s = in.duration_s;
  s.host_s = host_s;
  s.realtime_factor = host_s > 0.0 ? in.duration_s / host_s : 0.0;
  s.final_position_error_m = rec.last.position_error_m;
  s.max_position_error_after_convergence_m = rec.converged_at_s >= 0.0 ? rec.max_error_after_convergence_m : NAN;
  s.final_velocity_error_mps = rec.last.velocity_error_mps;
  s.final_attitude_error_deg = rec.last.attitude_error_deg;
  s.frames = obs.frames();
  s.matches_per_frame_mean = obs.frames() > 0U ? static_cast<double>(obs.matches()) / obs.frames() : 0.0;
  std::uint64_t misses = 0;
  for (bsp::TileId t = 0; t < bsp::kTile64.tiles(); ++t) {
    if (((m.powered_mask() >> t) & 1ULL) == 0ULL) {
      continue;
    }
    const k::TaskTable table = trn::tasks::role_table(trn::tasks::kTileRoles[t]);
    for (const k::TaskSpec& spec : table) {
      k::TaskStats ks{};
      if (k::task_stats(t, k::find_task(t, spec.name), &ks) == k::Status::kOk) {
        misses += ks.deadline_misses;
      }
    }
  }
  s.deadline_misses = misses;
  s.heap_allocs_after_init = allocs;
  s.faults_injected = obs.injected();
  s.faults_detected = obs.detected();
  s.faults_recovered = obs.recovered();
  s.trace_hash = tools::trace_hash_hex(bsp::trace_hash());
  const trn::tasks::VisionCoordStats c = trn::tasks::vision_coord_stats(kCoordinatorTile);
  s.extra.emplace_back("converged_at_s", rec.converged_at_s);
  s.extra.emplace_back("landmarks_selected", c.landmarks_selected);
  s.extra.emplace_back("coarse_accepted", c.coarse_accepted);
  s.extra.emplace_back("vision_units_lost", c.units_lost);
  s.extra.emplace_back("worst_frame_ms", static_cast<double>(c.max_frame_cycles) * 1000.0 /
                                             static_cast<double>(bsp::kTile64.clock_hz));
  s.extra.emplace_back("final_position_3sigma_m", rec.last.sigma3_p.norm());
  return s;
}

void print_summary(const tools::Summary& s, const std::string& dir) {
  std::printf("summary\n");
  std::printf("  scenario               %s (seed %llu)%s%s\n", s.scenario.c_str(),
              static_cast<unsigned long long>(s.seed), s.fault_plan.empty() ? "" : ", faults: ",
              s.fault_plan.c_str());
  std::printf("  emulated time          %.1f s in %.2f host s (real-time factor %.1f)\n", s.emulated_s, s.host_s,
              s.realtime_factor);
  std::printf("  final position error   %.2f m (max after convergence %.2f m)\n", s.final_position_error_m,
              s.max_position_error_after_convergence_m);
  std::printf("  final velocity error   %.3f m/s, attitude error %.4f deg\n", s.final_velocity_error_mps,
              s.final_attitude_error_deg);
  std::printf("  frames                 %llu, %.1f matches per frame\n", static_cast<unsigned long long>(s.frames),
              s.matches_per_frame_mean);
  std::printf("  deadline misses        %llu\n", static_cast<unsigned long long>(s.deadline_misses));
  std::printf("  heap allocs after init %llu\n", static_cast<unsigned long long>(s.heap_allocs_after_init));
  std::printf("  faults                 %llu injected, %llu detected, %llu recovered\n",
              static_cast<unsigned long long>(s.faults_injected), static_cast<unsigned long long>(s.faults_detected),
              static_cast<unsigned long long>(s.faults_recovered));
  std::printf("  trace hash             %s\n", s.trace_hash.c_str());
  std::printf("outputs in %s/ (summary.json, nav.csv, events.log, plots)\n", dir.c_str());
}

bool write_outputs(Inputs& in, const tools::Summary& s, const tools::EventLog& log,
                   const std::vector<tools::TileInfo>& tiles, std::string& error) {
  tools::RunFolder& f = *in.folder;
  return tools::write_summary_json(f.staging_path("summary.json"), s, error) &&
         log.write(f.staging_path("events.log"), error) &&
         tools::write_tile_map_csv(f.staging_path("tile_map.csv"), bsp::kTile64.cols, bsp::kTile64.rows, tiles,
                                   error) &&
         tools::write_plots(f.staging_dir(), error) && f.commit(error);
}

int run(int argc, char** argv) {
  CLI::App app{"trn_mission: terrain relative navigation on an emulated TILE64"};
  Options o;
  std::uint64_t seed = 0;
  app.add_option("--scenario", o.scenario_path, "Scenario file (TOML); default: the built-in scenario");
  app.add_option("--faults", o.faults_path, "Fault-plan file (TOML); default: no faults");
  app.add_flag("--demo-faults", o.demo_faults, "Inject the built-in demonstration fault plan");
  auto* seed_opt = app.add_option("--seed", seed, "Seed of the world, sensors and faults (overrides the scenario's)");
  app.add_option("--out", o.out, "Run folder (default out/<scenario>-seed<N>)");
  app.add_option("--duration", o.duration_s, "Emulated seconds to fly (default: the whole descent)")
      ->check(CLI::Range(1.0, 1000.0));
  app.add_flag("--quiet", o.quiet, "No progress display");
  app.add_flag("--view", o.view, "Show the tile grid live (role and health of each tile)");
  app.add_flag("--memory-map", o.memory_map, "Print the memory map after the run");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  if (seed_opt->count() > 0U) {
    o.seed = seed;
  }
  Inputs in;
  if (const int rc = prepare(o, in); rc != 0) {
    return rc;
  }
  std::printf("trn_mission: building the world (scenario %s, seed %llu)\n", in.scenario.name.c_str(),
              static_cast<unsigned long long>(in.scenario.seed));
  std::fflush(stdout);
  tools::Mission mission;
  tools::MissionSetup setup;
  setup.scenario = in.scenario;
  setup.duration_s = in.duration_s;
  std::string error;
  if (!mission.build(setup, error) || !mission.boot(error)) {
    std::fprintf(stderr, "trn_mission: %s\n", error.c_str());
    return 1;
  }
  if (in.plan.has_value() && !tools::arm_fault_plan(*in.plan, static_cast<double>(bsp::kTile64.clock_hz), error)) {
    return bad_input(error);
  }
  tools::EventLog log;
  tools::NavCsv csv;
  if (!csv.open(in.folder->staging_path("nav.csv"), error)) {
    return bad_input(error);
  }
  Observer obs(log);
  FlightRecord rec;
  std::printf("trn_mission: %u tiles booted (vision coordinator %u, I/O %u, filter %u, 40 vision tiles); "
              "flying %.0f s%s\n",
              static_cast<unsigned>(__builtin_popcountll(mission.powered_mask())), kCoordinatorTile,
              trn::tasks::kIoTile, kFilterTile, in.duration_s,
              in.plan.has_value() ? (", fault plan " + in.plan->name).c_str() : "");
  std::fflush(stdout);
  std::vector<tools::TileInfo> infos = tile_infos(mission, obs);
  const auto t0 = std::chrono::steady_clock::now();
  bsp::heap::seal(bsp::heap::SealMode::kFatal);
  fly(o, mission, in.duration_s, csv, obs, rec, infos);
  const std::uint64_t allocs = bsp::heap::allocs_after_seal();
  bsp::heap::unseal();
  const double host_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  (void)tools::log_injections(bsp::fault_log(), static_cast<double>(bsp::kTile64.clock_hz), log);
  const tools::Summary s = make_summary(in, mission, obs, rec, host_s, allocs);
  if (!csv.close(error) || !write_outputs(in, s, log, tile_infos(mission, obs), error)) {
    std::fprintf(stderr, "trn_mission: cannot write the run folder: %s\n", error.c_str());
    return 1;
  }
  print_summary(s, in.folder->dir());
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
