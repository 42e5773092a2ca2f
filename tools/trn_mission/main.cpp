/**
 * @file main.cpp
 * @brief The mission image: the whole chip booted from the tile map flies the descent, with
 *        faults injected by plan, and leaves a run folder behind.
 *
 * Order: every input is read and checked and the run folder's staging area is
 * made before anything runs (bad input: a message and exit status 2, nothing
 * written); the world is built and the chip booted; the heap is sealed; the
 * descent is flown in steps of kStepS emulated seconds, sampling the
 * navigation against the truth and collecting the flight event log (every
 * detection, isolation and recovery the flight code reports) into events.log;
 * a step that crosses a phase boundary stops there first, so the board's
 * energy meter is snapshotted at the boundary's cycle (tools/common/mission/phase_energy.hpp);
 * then the heap is unsealed, the flight's events are joined to the injector's
 * ground truth (tools/common/accounting/fdir_join.hpp, docs/FDIR.md) and the outputs
 * written. The final error is scored against the truth at the end of the run. Host time
 * is measured here, in the front end, never in emulated behaviour.
 */
#include "bsp_tile64/emu/board.hpp"
#include "trn/events.hpp"
#include "bsp_tile64/emu/energy.hpp"
#include "bsp_tile64/faults/fault_injector.hpp"
#include "bsp_tile64/emu/host/frame_ahead.hpp"
#include "bsp_tile64/emu/host/heap_guard.hpp"
#include "bsp_tile64/emu/trace.hpp"
#include "bsp_tile64/emu/udn_net.hpp"
#include "fdir/tile_health.hpp"
#include "kernel/kernel.hpp"
#include "tools/common/cli_checks.hpp"
#include "tools/common/accounting/fault_account.hpp"
#include "tools/common/mission/fault_plan.hpp"
#include "tools/common/accounting/fdir_join.hpp"
#include "tools/common/mission/fdir_params_doc.hpp"
#include "tools/common/mission/memory_report.hpp"
#include "tools/common/mission/mission.hpp"
#include "tools/common/mission/nav_integrity.hpp"
#include "tools/common/mission/phase_energy.hpp"
#include "tools/common/mission/ram_record.hpp"
#include "tools/common/mission/run_folder.hpp"
#include "tools/common/mission/scenario.hpp"
#include "tools/common/mission/tile_view.hpp"
#include "tools/common/mission/trace_dump.hpp"
#include "trn/tasks/filter/filter_task.hpp"
#include "trn/tasks/io/io_task.hpp"
#include "trn/tasks/supervisors/supervisors.hpp"
#include "tools/common/mission/message_doc.hpp"
#include "trn/tasks/tile_map.hpp"
#include "trn/tasks/vision/vision_coord.hpp"
#include "udn/endpoint.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <exception>
#include <iostream>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <unistd.h>

namespace {

/** The role tile @p t boots on the chip flown (the deployment the image was configured with). */
trn::tasks::Role role_of(bsp::TileId t) { return trn::tasks::tile_role(*trn::tasks::image_config().deployment, t); }

constexpr double kStepS = 0.1;  ///< sampling step of the flight loop (nav.csv, the view), emulated seconds
/**
 * The host reads the filter's newest output this often within a step: every
 * output of the 100 Hz stream guidance consumes is held against its 3-sigma
 * (integrity, fix, convergence, maximum error), not one in ten.
 */
constexpr std::uint32_t kChecksPerStep = 10U;

/**
 * Record @p rec as the flight left it in the RAM of @p tile
 * (tools/common/mission/ram_record.hpp); T{} and a warning when the tile holds none
 * (the role's task never started there, or the tile restarted and has not carved it again).
 */
template <class T>
T flight_record(bsp::TileId tile, const bsp::RamRecord<T>& rec) {
  T out{};
  std::string error;
  if (!tools::read_record(tile, rec, out, error)) {
    std::fprintf(stderr, "trn_mission: %s\n", error.c_str());
  }
  return out;
}

struct Options {
  std::string scenario_path;
  std::string faults_path;
  bool demo_faults = false;
  std::optional<std::uint64_t> seed;
  std::string out;
  double duration_s = 0.0;  ///< 0: the whole descent
  std::uint32_t vision_tiles = 0;  ///< 0: all of the chip's
  std::string chip;                ///< empty: the scenario's
  bool no_spares = false;
  bool quiet = false;
  bool view = false;
  bool memory_map = false;
  bool no_plots = false;
  bool onboard_landmarks = false;
  bool one_host_thread = false;
  std::string world_cache;
  std::string trace_dump;  ///< empty: no dump
  std::string golden;      ///< summary.json of the fault-free flight of the same scenario, seed and duration (empty: none)
};

/** Everything checked before the run: scenario, plan, run folder. */
struct Inputs {
  tools::Scenario scenario;
  std::optional<tools::FaultPlan> plan;
  double duration_s = 0.0;
  std::optional<tools::RunFolder> folder;
  bool no_plots = false;
  /** The golden flight's delivered stream (--golden): its CRC, solutions delivered, last job, counts' start. */
  std::optional<std::array<double, 4>> golden_stream;
};

/** Lines of events.log for the flight's events (a flood beyond them is counted at its end). */
constexpr std::size_t kEventLogLines = std::size_t{1} << 15U;

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
  if (!o.chip.empty()) {
    in.scenario.chip = o.chip;
  }
  const tools::Chip chip = tools::find_chip(in.scenario.chip);
  if (chip.deployment == nullptr) {
    return bad_input("no such chip: \"" + in.scenario.chip + "\" (tile64 or maestro)");
  }
  const std::uint32_t vision_count = trn::tasks::count_role(*chip.deployment, trn::tasks::Role::kVision);
  if (o.vision_tiles > vision_count) {
    return bad_input("--vision-tiles " + std::to_string(o.vision_tiles) + ": the " + in.scenario.chip + " has " +
                     std::to_string(vision_count) + " vision tiles");
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
    in.plan = tools::demo_fault_plan(*chip.deployment);
  } else if (!o.faults_path.empty()) {
    tools::FaultPlanResult r = tools::load_fault_plan(o.faults_path, *chip.deployment, in.duration_s);
    if (!r.ok()) {
      return bad_input(r.error);
    }
    in.plan = *r.plan;
  }
  in.no_plots = o.no_plots;
  if (!o.golden.empty()) {
    std::ifstream f(o.golden);
    nlohmann::json g;
    try {
      if (!f) {
        throw std::runtime_error("cannot be read");
      }
      f >> g;
      const auto seed = g.at("seed").get<std::uint64_t>();
      const auto emulated = g.at("emulated_s").get<double>();
      if (g.at("faults_injected").get<std::uint64_t>() != 0U || g.value("faults_not_delivered", 0.0) != 0.0) {
        throw std::runtime_error("is not a fault-free flight");
      }
      if (g.at("scenario").get<std::string>() != in.scenario.name || seed != in.scenario.seed ||
          emulated != in.duration_s || g.value("chip", std::string("tile64")) != in.scenario.chip) {
        throw std::runtime_error("flew another scenario, chip, seed or duration (" +
                                 g.at("scenario").get<std::string>() + ", " + g.value("chip", std::string("tile64")) +
                                 ", seed " + std::to_string(seed) + ", " + std::to_string(emulated) + " s)");
      }
      in.golden_stream = std::array<double, 4>{
          g.at("filter_output_crc").get<double>(), g.at("filter_outputs_delivered").get<double>(),
          g.at("filter_last_job").get<double>(), g.at("filter_counts_since_job").get<double>()};
    } catch (const std::exception& e) {
      return bad_input("--golden " + o.golden + ": " + e.what());
    }
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

// ------------------------------------------------------------------ flight

/** A run whose newest navigation output is older than this at the end has lost its navigation. */
constexpr double kLostOutputAgeS = 0.5;

struct FlightRecord {
  tools::NavSample last{};
  double max_error_after_convergence_m = 0.0;
  double fix_at_s = -1.0;        ///< first output whose horizontal 3-sigma is below tools::kFixSigma3M
  double converged_at_s = -1.0;  ///< first output whose horizontal 3-sigma is within tools::kConvergedSigma3M
  double longest_gap_s = 0.0;  ///< longest time between two successive new outputs (or the start and the first)
  tools::NavIntegrity integrity{};  ///< outputs from the fix on against their own 3-sigma, per axis
  double last_checked_s = -1.0;     ///< time of the newest output check() saw
  /** (time, truth altitude) of every output check() saw; reserved before the heap is sealed, never grown. */
  std::vector<std::pair<double, double>> altitude;
  /** Time of every new output check() saw (the filter role's stream, for the join); reserved like altitude. */
  std::vector<double> outputs_s;
  /** Check times at which the I/O role had forwarded more IMU samples than at the check before; reserved. */
  std::vector<double> io_samples_s;
  std::uint32_t io_forwarded = 0U;
  /** Check times at which the tile-health supervisor's count of self-test rounds had changed; reserved. */
  std::vector<double> health_rounds_s;
  std::uint32_t health_rounds = 0U;
};

/** Holds a new output @p n against the record's rules: fix, convergence, maximum error, integrity. */
void check(const tools::NavSample& n, FlightRecord& rec) {
  if (!n.valid || n.t_s == rec.last_checked_s) {
    return;  // no output yet, or the one already seen
  }
  rec.last_checked_s = n.t_s;
  if (rec.altitude.size() < rec.altitude.capacity()) {
    rec.altitude.emplace_back(n.t_s, n.altitude_m);
  }
  if (rec.outputs_s.size() < rec.outputs_s.capacity()) {
    // When it was seen (a late job carries its own, older time).
    rec.outputs_s.push_back(static_cast<double>(bsp::board_time()) / static_cast<double>(bsp::board_config().profile.clock_hz));
  }
  const double sigma3_h = n.sigma3_p.head<2>().norm();
  if (rec.fix_at_s < 0.0 && sigma3_h < tools::kFixSigma3M) {
    rec.fix_at_s = n.t_s;
  }
  if (rec.converged_at_s < 0.0 && sigma3_h <= tools::kConvergedSigma3M) {
    rec.converged_at_s = n.t_s;
  }
  if (rec.converged_at_s >= 0.0) {
    rec.max_error_after_convergence_m = std::max(rec.max_error_after_convergence_m, n.position_error_m);
  }
  if (rec.fix_at_s >= 0.0) {
    rec.integrity.add(n.t_s, {n.est_p[0] - n.truth_p[0], n.est_p[1] - n.truth_p[1], n.est_p[2] - n.truth_p[2]},
                      {n.sigma3_p[0], n.sigma3_p[1], n.sigma3_p[2]});
  }
}

/** Faults applied so far per tile, from the injector's log (ground truth: the view's count, never a detection). */
void count_tile_faults(std::array<std::uint32_t, bsp::kMaxTiles>& per_tile) {
  per_tile.fill(0U);
  for (const bsp::FaultRecord& r : bsp::fault_log()) {
    if (r.status == bsp::FaultStatus::kApplied && r.spec.tile < bsp::kMaxTiles) {
      ++per_tile[r.spec.tile];
    }
  }
}

std::uint64_t count_applied() {
  std::uint64_t n = 0;
  for (const bsp::FaultRecord& r : bsp::fault_log()) {
    n += r.status == bsp::FaultStatus::kApplied ? 1U : 0U;
  }
  return n;
}

const char* health_name(bool on, tools::TileHealth h) { return on ? tools::tile_health_name(h) : "off"; }

std::vector<tools::TileInfo> tile_infos(const tools::Mission& m, const tools::FlightEventCollector& flight) {
  std::array<std::uint32_t, bsp::kMaxTiles> faults{};
  count_tile_faults(faults);
  std::vector<tools::TileInfo> v(bsp::board_config().profile.tiles());
  for (std::uint32_t t = 0; t < v.size(); ++t) {
    const trn::tasks::Role r = role_of(t);
    v[t].role = trn::tasks::role_name(r);
    const bool on = ((m.powered_mask() >> t) & 1ULL) != 0ULL;
    v[t].health = health_name(on, flight.tile_health()[t]);
    v[t].faults_injected = faults[t];
    v[t].power = bsp::power_state_name(bsp::metered_state(t));
    v[t].energy_j = bsp::tile_energy(t).joules;
    if (on) {
      for (const k::TaskSpec& spec : trn::tasks::role_table(r)) {
        k::TaskStats ks{};
        if (k::task_stats(t, k::find_task(t, spec.name), &ks) == k::Status::kOk) {
          v[t].deadline_misses += static_cast<std::uint32_t>(ks.deadline_misses);
        }
      }
    }
  }
  return v;
}

void progress(const Options& o, const FlightRecord& rec, const tools::FlightEventCollector& flight, bool tty) {
  if (o.quiet) {
    return;
  }
  const tools::NavSample& n = rec.last;
  std::printf("%s  t %5.1f s  altitude %6.0f m  position error %9.2f m (3-sigma %8.2f m)  frames %3u  faults %llu%s",
              tty ? "\r" : "", n.t_s, n.altitude_m, n.position_error_m, n.sigma3_p.head<2>().norm(), flight.frames(),
              static_cast<unsigned long long>(count_applied()), tty ? "" : "\n");
  std::fflush(stdout);
}

/** The phases energy is reported by: the scenario's (the parser makes the first start at 0 s). */
std::vector<tools::PhaseWindow> phase_windows(const tools::Scenario& scenario) {
  std::vector<tools::PhaseWindow> w;
  for (const tools::MissionPhase& p : scenario.phases) {
    w.push_back({p.name, p.start_s});
  }
  return w;
}

/** What the view's chip line compares with: the meter at the previous view. */
struct ViewMeter {
  bsp::Cycles cycle = 0U;
  double joules = 0.0;
  bsp::StateCycles sum{0U, 0U, 0U, 0U};  ///< over all tiles
};

/** The view's chip line: tiles per metered state now; since the last view the chip's mean power, the active share. */
void print_chip_line(ViewMeter& last) {
  std::array<std::uint32_t, bsp::kPowerStateCount> n{};
  bsp::StateCycles sum{0U, 0U, 0U, 0U};
  for (bsp::TileId t = 0; t < bsp::tile_count(); ++t) {
    ++n[static_cast<std::size_t>(bsp::metered_state(t))];
    const bsp::StateCycles c = bsp::tile_energy(t).cycles;
    sum = bsp::StateCycles{sum.off + c.off, sum.booting + c.booting, sum.idle + c.idle, sum.active + c.active};
  }
  const auto count = [&n](bsp::PowerState s) { return n[static_cast<std::size_t>(s)]; };
  const double j = bsp::chip_energy_j();
  const bsp::Cycles now = bsp::board_time();
  const double dt_s = static_cast<double>(now - last.cycle) / static_cast<double>(bsp::board_config().profile.clock_hz);
  const auto on = static_cast<double>((sum.total() - sum.off) - (last.sum.total() - last.sum.off));
  const auto active = static_cast<double>(sum.active - last.sum.active);
  std::printf("chip: %u active, %u idle, %u booting, %u off; last %.1f s: %.2f W, %.1f %% of on-tile cycles active; "
              "%.1f J so far\n",
              count(bsp::PowerState::kActive), count(bsp::PowerState::kIdle), count(bsp::PowerState::kBooting),
              count(bsp::PowerState::kOff), dt_s, dt_s > 0.0 ? (j - last.joules) / dt_s : 0.0,
              on > 0.0 ? 100.0 * active / on : 0.0, j);
  last = ViewMeter{now, j, sum};
}

void fly(const Options& o, const tools::Mission& m, double duration_s, tools::NavCsv& csv, tools::EventLog& log,
         tools::FlightEventCollector& flight, FlightRecord& rec, std::vector<tools::TileInfo>& infos,
         tools::PhaseEnergy& energy) {
  const double clock_hz = static_cast<double>(bsp::board_config().profile.clock_hz);
  const auto steps = static_cast<std::uint32_t>(std::llround(duration_s / kStepS));
  const bool tty = ::isatty(::fileno(stdout)) != 0;
  std::array<char, 8192> grid{};
  const std::uint32_t per_second = static_cast<std::uint32_t>(std::llround(1.0 / kStepS));
  ViewMeter view_meter;
  const auto check_cycles = static_cast<bsp::Cycles>(std::llround(kStepS / kChecksPerStep * clock_hz));
  for (std::uint32_t s = 1; s <= steps; ++s) {
    for (std::uint32_t c = 1; c <= kChecksPerStep; ++c) {
      (void)tools::run_with_phases((static_cast<bsp::Cycles>(s - 1U) * kChecksPerStep + c) * check_cycles, energy);
      check(m.nav(), rec);
      // The I/O role's count as its tile holds it; while the tile restarts (no record), the count before.
      trn::tasks::IoTaskStats io_stats{};
      io_stats.imu_forwarded = rec.io_forwarded;
      (void)tools::try_read_record(trn::tasks::slot_tile_now(trn::tasks::kSlotIo), trn::tasks::kIoTaskStatsRecord,
                                   io_stats);
      const std::uint32_t io = io_stats.imu_forwarded;
      // A count back at 0 is a record carved anew (a restart, or the role on its spare), not a sample sent.
      if (io != rec.io_forwarded && io != 0U && rec.io_samples_s.size() < rec.io_samples_s.capacity()) {
        rec.io_samples_s.push_back(static_cast<double>(bsp::board_time()) / clock_hz);
      }
      rec.io_forwarded = io;
      const std::uint32_t rounds = fdir::tile_health_view(trn::tasks::slot_tile_now(trn::tasks::kSlotTrnSupervisor)).self_tests;
      if (rounds != rec.health_rounds && rec.health_rounds_s.size() < rec.health_rounds_s.capacity()) {
        rec.health_rounds_s.push_back(static_cast<double>(bsp::board_time()) / clock_hz);
      }
      rec.health_rounds = rounds;
    }
    flight.poll(clock_hz, log);
    const tools::NavSample n = m.nav();
    if (!n.valid || (rec.last.valid && n.t_s == rec.last.t_s)) {
      continue;  // no output yet, or no new one since the last step
    }
    rec.longest_gap_s = std::max(rec.longest_gap_s, n.t_s - (rec.last.valid ? rec.last.t_s : 0.0));
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
    if (s % per_second != 0U && s != steps) {
      continue;
    }
    if (o.view) {
      // The grid's strings are rebuilt in place (same lengths), so the view allocates nothing.
      std::array<std::uint32_t, bsp::kMaxTiles> faults{};
      count_tile_faults(faults);
      for (std::uint32_t t = 0; t < infos.size(); ++t) {
        const bool on = ((m.powered_mask() >> t) & 1ULL) != 0ULL;
        infos[t].health.assign(health_name(on, flight.tile_health()[t]));
        infos[t].faults_injected = faults[t];
        infos[t].power.assign(bsp::power_state_name(bsp::metered_state(t)));
      }
      const std::size_t len =
          tools::render_tile_grid_to(bsp::board_config().profile.cols, bsp::board_config().profile.rows, infos, tty, grid);
      std::printf("%s%.*s", tty ? "\x1b[H\x1b[2J" : "\n", static_cast<int>(len), grid.data());
      print_chip_line(view_meter);
      progress(o, rec, flight, false);
    } else if (tty || s % (5U * per_second) == 0U || s == steps) {
      progress(o, rec, flight, tty);
    }
  }
  if (!o.quiet && tty && !o.view) {
    std::printf("\n");
  }
}

// ------------------------------------------------------------------ outputs

/** The navigation at the end of the run against the truth then: the last output, dead-reckoned to the end. */
struct FinalScore {
  double output_age_s = 0.0;  ///< end time minus the newest output's time (the whole run without any)
  double position_error_m = NAN;
  double velocity_error_mps = NAN;
  bool lost = true;           ///< no output, or the newest one older than kLostOutputAgeS
};

FinalScore score_end(const tools::Mission& m, const FlightRecord& rec, double end_s) {
  FinalScore f;
  if (!rec.last.valid) {
    f.output_age_s = end_s;
    return f;
  }
  f.output_age_s = std::max(0.0, end_s - rec.last.t_s);
  const bsp::world::TruthState t = m.truth().at(end_s);
  // What guidance would hold at the end: the last solution carried forward at its own velocity.
  const Eigen::Vector3d p = rec.last.est_p + rec.last.est_v * f.output_age_s;
  f.position_error_m = (p - t.r_m).norm();
  f.velocity_error_mps = (rec.last.est_v - t.v_mps).norm();
  f.lost = f.output_age_s > kLostOutputAgeS;
  return f;
}
/** What the supervisor tree did: each node's counters, its record in its tile's RAM (trn/tasks/supervisors/supervisors.hpp). */
void add_supervisor_keys(tools::Summary& s, const trn::tasks::VisionCoordStats& c) {
  using trn::tasks::kSupervisorStatsRecord;
  using trn::tasks::slot_tile_now;
  const trn::tasks::SupervisorStats top = flight_record(slot_tile_now(trn::tasks::kSlotTrnSupervisor), kSupervisorStatsRecord);
  const trn::tasks::SupervisorStats fs =
      flight_record(slot_tile_now(trn::tasks::kSlotFilterSupervisor), kSupervisorStatsRecord);
  const trn::tasks::SupervisorStats vs =
      flight_record(slot_tile_now(trn::tasks::kSlotVisionSupervisor), kSupervisorStatsRecord);
  s.extra.emplace_back("sup_phase_at_end", top.phase);
  s.extra.emplace_back("sup_policies", top.policies + fs.policies + vs.policies);
  s.extra.emplace_back("sup_alternatives_applied", top.applied + fs.applied + vs.applied);
  s.extra.emplace_back("sup_escalations", top.escalations + fs.escalations + vs.escalations);
  s.extra.emplace_back("sup_safe_mode", top.safe_mode);
  s.extra.emplace_back("sup_filter_commands", fs.commands);
  s.extra.emplace_back("sup_replicas_parked", fs.parks);
  s.extra.emplace_back("sup_replicas_woken", fs.wakes);
  s.extra.emplace_back("vision_rate_div", c.rate_div);
  s.extra.emplace_back("vision_frames_rate_skipped", c.frames_rate_skipped);
  s.extra.emplace_back("vision_healthy_tiles", c.healthy_tiles);
}

/** Altitude bands matches per frame are reported by, m (the default descent spans 4200 to 1080 m). */
constexpr double kAltitudeBandM = 500.0;

/**
 * Matches per frame by altitude band: each frame_done the coordinator reported
 * (its fine matches), put in the band of the truth altitude at the output
 * nearest before the report (the report comes at most a frame's work after the
 * capture: worst_frame_ms, ~0.2 s, ~15 m of descent). Keys
 * matches_per_frame_alt_<lo>_<hi>_m and frames_alt_<lo>_<hi>_m for every band
 * with a frame; none when there was no output yet.
 */
void add_matches_by_altitude(const tools::FlightEventCollector& flight, const FlightRecord& rec, tools::Summary& s) {
  std::map<std::int64_t, std::pair<std::uint64_t, std::uint64_t>> bands;  // lower edge -> frames, matches
  const double clock_hz = static_cast<double>(bsp::board_config().profile.clock_hz);
  for (const fdir::Event& e : flight.events()) {
    if (e.id != trn::ev::kFrameDone || rec.altitude.empty()) {
      continue;
    }
    const double t = static_cast<double>(e.cycle) / clock_hz;
    auto it = std::upper_bound(rec.altitude.begin(), rec.altitude.end(), t,
                               [](double v, const std::pair<double, double>& a) { return v < a.first; });
    if (it != rec.altitude.begin()) {
      --it;
    }
    const auto lo = static_cast<std::int64_t>(std::floor(it->second / kAltitudeBandM) * kAltitudeBandM);
    ++bands[lo].first;
    bands[lo].second += e.b;
  }
  for (auto b = bands.rbegin(); b != bands.rend(); ++b) {
    const std::string name =
        std::to_string(b->first) + "_" + std::to_string(b->first + static_cast<std::int64_t>(kAltitudeBandM)) + "_m";
    s.extra.emplace_back("matches_per_frame_alt_" + name,
                         static_cast<double>(b->second.second) / static_cast<double>(b->second.first));
    s.extra.emplace_back("frames_alt_" + name, static_cast<double>(b->second.first));
  }
}

/**
 * The messaging layer's flow control, from the tiles' own counters (since each tile's last boot):
 * BUSY answers to packets that found a full receive queue, and the resends that followed them,
 * which are not recovery events (docs/FT_MESSAGING.md, "Flow control").
 */
void add_flow_control(tools::Summary& s) {
  std::uint64_t busy = 0;
  std::uint64_t resent_busy = 0;
  for (bsp::TileId t = 0; t < bsp::board_config().profile.tiles(); ++t) {
    if (const udn::FtNode* node = udn::endpoint_node(t); node != nullptr) {
      busy += node->stats.busy_sent;
      resent_busy += node->stats.resent_busy;
    }
  }
  s.extra.emplace_back("udn_busy_answers", static_cast<double>(busy));
  s.extra.emplace_back("udn_flow_control_resends", static_cast<double>(resent_busy));
}

/**
 * The vision load (make sizing): work units lost at the deadline, frames the coordinator saw and
 * left out while busy with another, and the landmarks it planned per frame it processed.
 */
void add_vision_load(tools::Summary& s, const trn::tasks::VisionCoordStats& c) {
  s.extra.emplace_back("vision_units_lost", c.units_lost);
  s.extra.emplace_back("vision_frames_seen", c.frames_seen);
  s.extra.emplace_back("vision_frames_skipped", c.frames_skipped);
  s.extra.emplace_back("vision_planned_per_frame",
                       c.frames_processed == 0U ? 0.0
                                                : static_cast<double>(c.planned_total) / c.frames_processed);
}

/** The strict join's figures (docs/FDIR.md, "The join"); faults_no_effect only against a golden flight. */
void add_strict_accounting(tools::Summary& s, const tools::FaultAccount& faults, bool golden) {
  s.extra.emplace_back("faults_degraded_accepted", static_cast<double>(faults.degraded_accepted));
  s.extra.emplace_back("faults_misdiagnosed", static_cast<double>(faults.misdiagnosed));
  s.extra.emplace_back("false_alarms", static_cast<double>(faults.false_alarms.size()));
  s.extra.emplace_back("healthy_tiles_disturbed", static_cast<double>(faults.healthy_disturbed.size()));
  double no_effect = golden ? 0.0 : NAN;
  for (const tools::FaultOutcome& o : faults.outcomes) {
    no_effect += o.effect == tools::Effect::kNoEffect ? 1.0 : 0.0;
  }
  s.extra.emplace_back("faults_no_effect", no_effect);
}

tools::Summary make_summary(const Inputs& in, const tools::Mission& m, const tools::FlightEventCollector& flight,
                            const tools::FaultAccount& faults, const FlightRecord& rec, double host_s,
                            std::uint64_t allocs, const tools::PhaseEnergy& energy) {
  tools::Summary s;
  s.scenario = in.scenario.name;
  s.chip = in.scenario.chip;
  s.fault_plan = in.plan.has_value() ? in.plan->name : "";
  s.seed = in.scenario.seed;
  s.emulated_s = in.duration_s;
  s.host_s = host_s;
  s.realtime_factor = host_s > 0.0 ? in.duration_s / host_s : 0.0;
  s.extra.emplace_back("host_frames_rendered_ahead", static_cast<double>(bsp::frame_ahead::stats().taken));
  add_flow_control(s);
  const FinalScore end = score_end(m, rec, in.duration_s);
  s.final_position_error_m = end.position_error_m;
  s.max_position_error_after_convergence_m = rec.converged_at_s >= 0.0 ? rec.max_error_after_convergence_m : NAN;
  s.final_velocity_error_mps = end.velocity_error_mps;
  s.final_attitude_error_deg = rec.last.valid ? rec.last.attitude_error_deg : NAN;
  s.frames = flight.frames();
  s.matches_per_frame_mean =
      flight.frames() > 0U ? static_cast<double>(flight.matches()) / static_cast<double>(flight.frames()) : 0.0;
  std::uint64_t misses = 0;
  // Longest time between two check-ins of each task with its tile's health agent (the budgets' margin).
  std::vector<std::pair<std::string, double>> gaps;
  for (bsp::TileId t = 0; t < bsp::board_config().profile.tiles(); ++t) {
    if (((m.powered_mask() >> t) & 1ULL) == 0ULL) {
      continue;
    }
    const k::TaskTable table = trn::tasks::role_table(role_of(t));
    for (const k::TaskSpec& spec : table) {
      k::TaskStats ks{};
      if (k::task_stats(t, k::find_task(t, spec.name), &ks) == k::Status::kOk) {
        misses += ks.deadline_misses;
        const std::string key = std::string("checkin_gap_max_ms_") + spec.name;
        auto g = std::find_if(gaps.begin(), gaps.end(), [&](const auto& x) { return x.first == key; });
        if (g == gaps.end()) {
          gaps.emplace_back(key, 0.0);
          g = gaps.end() - 1;
        }
        g->second = std::max(g->second, static_cast<double>(ks.max_checkin_gap));
      }
    }
  }
  s.deadline_misses = misses;
  s.heap_allocs_after_init = allocs;
  s.faults_injected = faults.injected;
  s.faults_detected = faults.detected;
  s.faults_recovered = faults.recovered;
  s.trace_hash = tools::trace_hash_hex(bsp::trace_hash());
  const trn::tasks::VisionCoordStats c = flight_record(trn::tasks::slot_tile_now(trn::tasks::kSlotCoordinator),
                                                      trn::tasks::kVisionCoordStatsRecord);
  s.extra.emplace_back("mission_lost", end.lost ? 1.0 : 0.0);
  s.extra.emplace_back("nav_output_age_at_end_s", end.output_age_s);
  s.extra.emplace_back("nav_longest_gap_s", std::max(rec.longest_gap_s, end.output_age_s));
  s.extra.emplace_back("faults_not_delivered", static_cast<double>(faults.not_delivered));
  add_strict_accounting(s, faults, in.golden_stream.has_value());
  s.extra.emplace_back("detection_latency_mean_ms", faults.mean_detection_latency_s * 1e3);
  s.extra.emplace_back("detection_latency_max_ms", faults.max_detection_latency_s * 1e3);
  s.extra.emplace_back("flight_events", static_cast<double>(flight.events().size()));
  s.extra.emplace_back("flight_events_lost", static_cast<double>(flight.lost()));
  for (const auto& g : gaps) {
    s.extra.push_back(g);
  }
  s.extra.emplace_back("fix_at_s", rec.fix_at_s);
  s.extra.emplace_back("converged_at_s", rec.converged_at_s);
  // Integrity from the fix on: each axis's error against the 3-sigma the same output reports.
  const tools::NavIntegrity& ni = rec.integrity;
  s.extra.emplace_back("integrity_outputs", static_cast<double>(ni.outputs));
  for (int a = 0; a < 3; ++a) {
    const auto k = static_cast<std::size_t>(a);
    const std::string axis(1, static_cast<char>('x' + a));
    s.extra.emplace_back("integrity_beyond_3sigma_fraction_" + axis, ni.fraction_beyond_3sigma(a));
    s.extra.emplace_back("integrity_beyond_5sigma_" + axis, static_cast<double>(ni.beyond_5sigma[k]));
    s.extra.emplace_back("integrity_worst_ratio_" + axis, ni.worst_ratio[k]);
  }
  s.extra.emplace_back("integrity_worst_at_s", ni.worst_at_s);
  s.extra.emplace_back("integrity_bad_sigma", static_cast<double>(ni.bad_sigma));
  s.extra.emplace_back("landmarks_selected", c.landmarks_selected);
  s.extra.emplace_back("landmarks_from_ground", c.landmarks_from_ground);
  s.extra.emplace_back("vision_coordinator_ready_s", 1e-3 * c.ready_ms);
  s.extra.emplace_back("coarse_accepted", c.coarse_accepted);
  s.extra.emplace_back("vision_frames_before_ready", c.frames_before_ready);
  // The coarse stage's bands: dealt to the vision tiles, computed by the coordinator instead.
  s.extra.emplace_back("coarse_bands_sent", c.coarse_bands_sent);
  s.extra.emplace_back("coarse_bands_redone", c.coarse_bands_redone);
  s.extra.emplace_back("coarse_one_piece", c.coarse_one_piece);
  s.extra.emplace_back("coarse_stage_ms", 1e3 * static_cast<double>(c.max_coarse_cycles) /
                                              static_cast<double>(bsp::board_config().profile.clock_hz));
  add_vision_load(s, c);
  s.extra.emplace_back("vision_batch_send_failed", c.batch_send_failed);
  s.extra.emplace_back("vision_status_send_failed", c.status_send_failed);
  // The coordinator's consistency check of each frame's matches and what it did about wrong tiles.
  s.extra.emplace_back("vision_frames_checked", c.frames_checked);
  s.extra.emplace_back("vision_matches_checked", c.matches_checked);
  s.extra.emplace_back("vision_matches_failed", c.matches_failed);
  s.extra.emplace_back("vision_matches_unused", c.matches_unused);
  s.extra.emplace_back("vision_residual_scale_max_px", c.residual_scale_max_px);
  s.extra.emplace_back("vision_tile_bias_max_px", c.tile_bias_max_px);
  s.extra.emplace_back("vision_tiles_untrusted", c.tiles_untrusted);
  s.extra.emplace_back("vision_resets_asked", c.resets_asked);
  s.extra.emplace_back("vision_tiles_replaced", c.tiles_replaced);
  // Where the roles ran at the end (the supervisor's directory) and what that coordinator did.
  s.extra.emplace_back("coordinator_tile", trn::tasks::slot_tile_now(trn::tasks::kSlotCoordinator));
  s.extra.emplace_back("filter_tile", trn::tasks::slot_tile_now(trn::tasks::kSlotFilter));
  s.extra.emplace_back("coordinator_frames_processed", c.frames_processed);
  s.extra.emplace_back("vision_tiles_used",
                       m.setup().vision_tiles == 0U ? trn::tasks::count_role(m.deployment(), trn::tasks::Role::kVision)
                                                    : m.setup().vision_tiles);
  // The filter role's delivered solutions, in job order (a simplex or a voted one alike), and its TMR counts:
  // the flight's counters since the filter task last started (filter_counts_since_job; a restart clears them).
  const trn::tasks::FilterTaskStats f =
      flight_record(trn::tasks::slot_tile_now(trn::tasks::kSlotFilter), trn::tasks::kFilterTaskStatsRecord);
  s.extra.emplace_back("filter_counts_since_job", f.started_job);
  s.extra.emplace_back("filter_outputs_delivered", f.outputs_delivered);
  s.extra.emplace_back("filter_outputs_skipped", f.outputs_skipped);
  s.extra.emplace_back("filter_output_crc", f.output_crc);
  s.extra.emplace_back("filter_last_job", f.last_delivered_job);
  s.extra.emplace_back("filter_output_mark_job", f.mark_job);
  s.extra.emplace_back("filter_output_mark_crc", f.mark_crc);
  // The innovation monitor: windows judged and failed, and the largest window statistics (simplex).
  s.extra.emplace_back("filter_innovation_windows", f.innovation_windows);
  s.extra.emplace_back("filter_innovations_bad", f.innovations_bad);
  s.extra.emplace_back("filter_window_nis_max", 1e-3 * f.max_window_nis_milli);
  s.extra.emplace_back("filter_window_rejected_max", 1e-3 * f.max_window_reject_permille);
  s.extra.emplace_back("tmr_voted_outputs", f.tmr_jobs);
  s.extra.emplace_back("tmr_outvoted", f.tmr_outvoted);
  s.extra.emplace_back("tmr_no_majority", f.tmr_no_majority);
  s.extra.emplace_back("tmr_exclusions", f.tmr_exclusions);
  s.extra.emplace_back("tmr_resyncs", f.tmr_resyncs);
  // Emulated busy time of the filter role's tile and of the replica tiles (what TMR costs).
  const auto busy_ms = [](bsp::TileId t) {
    return static_cast<double>(bsp::tile_stats(t).active_cycles) * 1000.0 / static_cast<double>(bsp::board_config().profile.clock_hz);
  };
  s.extra.emplace_back("busy_ms_filter_tile", busy_ms(trn::tasks::slot_tile_now(trn::tasks::kSlotFilter)));
  double replicas_ms = 0.0;
  for (std::uint32_t i = 0; i < trn::tasks::kReplicas; ++i) {
    replicas_ms += busy_ms(trn::tasks::slot_tile_now(trn::tasks::kSlotReplica0 + i));
  }
  s.extra.emplace_back("busy_ms_replica_tiles", replicas_ms);
  s.extra.emplace_back("udn_packets_sent", static_cast<double>(bsp::udn_net_stats().sent));
  s.extra.emplace_back("worst_frame_ms", static_cast<double>(c.max_frame_cycles) * 1000.0 /
                                             static_cast<double>(bsp::board_config().profile.clock_hz));
  s.extra.emplace_back("final_position_3sigma_m", rec.last.sigma3_p.norm());
  add_matches_by_altitude(flight, rec, s);
  add_supervisor_keys(s, c);
  // Energy from the board's meter: the chip, per phase, per role of the tile map, per power state.
  std::vector<std::string> roles;
  for (bsp::TileId t = 0; t < bsp::board_config().profile.tiles(); ++t) {
    roles.emplace_back(trn::tasks::role_name(role_of(t)));
  }
  tools::add_energy_summary(energy, roles, in.duration_s, s);
  return s;
}

void print_summary(const tools::Summary& s, const std::string& dir) {
  std::printf("summary\n");
  std::printf("  scenario               %s (seed %llu)%s%s%s\n", s.scenario.c_str(),
              static_cast<unsigned long long>(s.seed), s.chip == "tile64" ? "" : (", on " + s.chip).c_str(),
              s.fault_plan.empty() ? "" : ", faults: ", s.fault_plan.c_str());
  std::printf("  emulated time          %.1f s in %.2f host s (real-time factor %.1f)\n", s.emulated_s, s.host_s,
              s.realtime_factor);
  std::printf("  final position error   %.2f m at the end (max after convergence %.2f m)\n",
              s.final_position_error_m, s.max_position_error_after_convergence_m);
  for (const auto& [key, value] : s.extra) {
    if (key == "mission_lost" && value != 0.0) {
      std::printf("  NAVIGATION LOST        the newest navigation output is stale at the end (see nav_output_age_at_end_s)\n");
    }
  }
  const auto extra = [&s](const char* key) {
    for (const auto& [k, v] : s.extra) {
      if (k == key) {
        return v;
      }
    }
    return static_cast<double>(NAN);
  };
  std::printf("  integrity              beyond 3-sigma from the fix on: x %.2f %%, y %.2f %%, z %.2f %% of %.0f "
              "outputs; worst error / 3-sigma %.2f, %.2f, %.2f\n",
              100.0 * extra("integrity_beyond_3sigma_fraction_x"), 100.0 * extra("integrity_beyond_3sigma_fraction_y"),
              100.0 * extra("integrity_beyond_3sigma_fraction_z"), extra("integrity_outputs"),
              extra("integrity_worst_ratio_x"), extra("integrity_worst_ratio_y"), extra("integrity_worst_ratio_z"));
  std::printf("  final velocity error   %.3f m/s, attitude error %.4f deg\n", s.final_velocity_error_mps,
              s.final_attitude_error_deg);
  std::printf("  frames                 %llu, %.1f matches per frame\n", static_cast<unsigned long long>(s.frames),
              s.matches_per_frame_mean);
  std::string bands;
  for (const auto& [key, value] : s.extra) {
    constexpr std::string_view kPrefix = "matches_per_frame_alt_";
    if (key.starts_with(kPrefix)) {
      std::string band = key.substr(kPrefix.size(), key.size() - kPrefix.size() - 2U);  // "<lo>_<hi>"
      band[band.find('_')] = '-';
      bands += (bands.empty() ? "" : ", ") + band + " m " + std::to_string(static_cast<int>(std::lround(value)));
    }
  }
  if (!bands.empty()) {
    std::printf("  matches by altitude    %s\n", bands.c_str());
  }
  std::printf("  deadline misses        %llu\n", static_cast<unsigned long long>(s.deadline_misses));
  std::printf("  heap allocs after init %llu\n", static_cast<unsigned long long>(s.heap_allocs_after_init));
  std::printf("  faults                 %llu injected, %llu detected, %llu recovered\n",
              static_cast<unsigned long long>(s.faults_injected), static_cast<unsigned long long>(s.faults_detected),
              static_cast<unsigned long long>(s.faults_recovered));
  double energy_j = NAN;
  double mean_power_w = NAN;
  double degraded = 0.0;
  double wrong = 0.0;
  double false_alarms = 0.0;
  double disturbed = 0.0;
  for (const auto& [key, value] : s.extra) {
    energy_j = key == "energy_j" ? value : energy_j;
    mean_power_w = key == "mean_power_w" ? value : mean_power_w;
    degraded = key == "faults_degraded_accepted" ? value : degraded;
    wrong = key == "faults_misdiagnosed" ? value : wrong;
    false_alarms = key == "false_alarms" ? value : false_alarms;
    disturbed = key == "healthy_tiles_disturbed" ? value : disturbed;
  }
  std::printf("  fault management       %.0f degraded (a mode given up), %.0f misdiagnosed, %.0f false alarms, "
              "%.0f actions on healthy tiles (faults.csv)\n",
              degraded, wrong, false_alarms, disturbed);
  std::printf("  energy                 %.1f J over the flight, mean power %.2f W (model: docs/BOARD.md)\n", energy_j,
              mean_power_w);
  std::printf("  trace hash             %s\n", s.trace_hash.c_str());
  std::printf("outputs in %s/ (summary.json, nav.csv, events.log, plots)\n", dir.c_str());
}

bool write_outputs(Inputs& in, const tools::Summary& s, const tools::EventLog& log,
                   const std::vector<tools::TileInfo>& tiles, const tools::FaultAccount& faults, std::string& error) {
  tools::RunFolder& f = *in.folder;
  return tools::write_summary_json(f.staging_path("summary.json"), s, error) &&
         log.write(f.staging_path("events.log"), error) &&
         tools::write_text_file(f.staging_path("faults.csv"), tools::faults_csv(bsp::fault_log(), faults), error) &&
         tools::write_tile_map_csv(f.staging_path("tile_map.csv"), bsp::board_config().profile.cols, bsp::board_config().profile.rows, tiles,
                                   error) &&
         (in.no_plots || tools::write_plots(f.staging_dir(), error)) && f.commit(error);
}

/** The options that choose the chip and what it has to spare. */
void add_chip_options(CLI::App& app, Options& o) {
  app.add_option("--chip", o.chip,
                 "Chip to fly (overrides the scenario's chip): tile64 (8x8, 700 MHz) or maestro (7x7, 342 MHz, "
                 "an FPU per tile)")
      ->check(CLI::IsMember({"tile64", "maestro"}));
  app.add_flag("--no-spares", o.no_spares,
               "Give the tile-health supervisor no spare tiles: a tile it gives up is not replaced and its role "
               "does not move (degradation studies)");
}

/** The line that says what booted: the chip, its role tiles, the flight's length and plan. */
void print_booted(const tools::Mission& mission, const Inputs& in) {
  using trn::tasks::Role;
  const trn::tasks::Deployment& dep = mission.deployment();
  std::printf("trn_mission: %s, %u tiles booted (vision coordinator %u, I/O %u, filter %u, %u vision tiles); "
              "flying %.0f s%s\n",
              dep.chip, static_cast<unsigned>(__builtin_popcountll(mission.powered_mask())),
              trn::tasks::boot_tile(dep, Role::kVisionCoordinator), trn::tasks::boot_tile(dep, Role::kIo),
              trn::tasks::boot_tile(dep, Role::kFilter), trn::tasks::count_role(dep, Role::kVision), in.duration_s,
              in.plan.has_value() ? (", fault plan " + in.plan->name).c_str() : "");
  std::fflush(stdout);
}

int run(int argc, char** argv) {
  CLI::App app{"trn_mission: terrain relative navigation on an emulated TILE64 or Maestro"};
  Options o;
  std::uint64_t seed = 0;
  app.add_option("--scenario", o.scenario_path, "Scenario file (TOML); default: the built-in scenario");
  app.add_option("--faults", o.faults_path, "Fault-plan file (TOML); default: no faults");
  app.add_flag("--demo-faults", o.demo_faults, "Inject the built-in demonstration fault plan");
  auto* seed_opt = app.add_option("--seed", seed, "Seed of the world, sensors and faults (overrides the scenario's)")
                       ->check(tools::kWholeNumber);
  app.add_option("--out", o.out, "Run folder (default out/<scenario>-seed<N>)");
  app.add_option("--duration", o.duration_s, "Emulated seconds to fly (default: the whole descent)")
      ->check(CLI::Range(1.0, 1000.0));
  app.add_option("--vision-tiles", o.vision_tiles,
                 "Vision tiles the coordinator uses, spread over the map (default: all, 40 on the TILE64 and 35 on "
                 "Maestro; the others stay on, idle)")
      ->check(CLI::Range(1U, 40U));
  add_chip_options(app, o);
  app.add_flag("--quiet", o.quiet, "No progress display");
  app.add_flag("--view", o.view, "Show the tile grid live (role and health of each tile)");
  app.add_flag("--memory-map", o.memory_map, "Print the memory map after the run");
  app.add_option("--world-cache", o.world_cache,
                 "Folder that keeps the built terrain and map product between runs (campaigns; default: none)");
  app.add_flag("--onboard-landmarks", o.onboard_landmarks,
               "Fly the map without the ground's landmark table: the coordinator selects its landmarks itself");
  app.add_flag("--one-host-thread", o.one_host_thread,
               "Render each camera frame at its capture instead of on a second host thread meanwhile "
               "(the same frames and trace hash; more host time)");
  app.add_flag("--no-plots", o.no_plots, "Write the run's data but no plots (campaigns: gnuplot costs time per run)");
  app.add_option("--golden", o.golden,
                 "summary.json of the fault-free flight of the same scenario, seed and duration: faults not detected "
                 "count as without effect when the delivered stream is that flight's bit for bit")
      ->check(CLI::ExistingFile);
  bool fdir_params = false;
  app.add_flag("--fdir-params", fdir_params,
               "Print the FDIR parameter table (docs/FDIR.md, \"Parameters\") as Markdown rows and exit");
  bool message_kinds = false;
  app.add_flag("--message-kinds", message_kinds,
               "Print the declared message kinds (docs/ARCHITECTURE.md, \"Message kinds\") as Markdown rows and exit");
  app.add_option("--trace-dump", o.trace_dump,
                 "Write every trace event of the run to this file (compare two runs with trn_trace diff)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  if (fdir_params) {
    std::fputs(tools::fdir_params_markdown().c_str(), stdout);
    return 0;
  }
  if (message_kinds) {
    std::fputs(tools::message_kinds_markdown().c_str(), stdout);
    return 0;
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
  // The dump opens before the board is built so that it holds every event the hash folds, boot included
  // (the board's init resets the hash; the sink stays installed).
  std::string error;
  tools::TraceDumpWriter dump;
  if (!o.trace_dump.empty() && !dump.open(o.trace_dump, error)) {
    return bad_input(error);
  }
  tools::Mission mission;
  tools::MissionSetup setup;
  setup.scenario = in.scenario;
  setup.duration_s = in.duration_s;
  setup.vision_tiles = o.vision_tiles;
  setup.world_cache = o.world_cache;
  setup.ground_landmarks = !o.onboard_landmarks;
  setup.render_ahead = !o.one_host_thread;
  setup.no_spares = o.no_spares;
  if (!mission.build(setup, error) || !mission.boot(error)) {
    std::fprintf(stderr, "trn_mission: %s\n", error.c_str());
    return 1;
  }
  if (in.plan.has_value() && !tools::arm_fault_plan(*in.plan, static_cast<double>(bsp::board_config().profile.clock_hz), error)) {
    return bad_input(error);
  }
  tools::EventLog log(kEventLogLines);
  tools::NavCsv csv;
  if (!csv.open(in.folder->staging_path("nav.csv"), error)) {
    return bad_input(error);
  }
  tools::FlightEventCollector flight;
  FlightRecord rec;
  print_booted(mission, in);
  std::vector<tools::TileInfo> infos = tile_infos(mission, flight);
  tools::PhaseEnergy energy;
  if (!energy.init(phase_windows(in.scenario), bsp::power_model(), bsp::board_config().quantum_cycles,
                   bsp::board_config().profile.tiles(), error)) {
    return bad_input(error);
  }
  // One entry per output check (kChecksPerStep per step), room taken before the seal.
  const std::size_t checks = static_cast<std::size_t>(std::llround(in.duration_s / kStepS)) * kChecksPerStep + 1U;
  rec.altitude.reserve(checks);
  rec.outputs_s.reserve(checks);
  rec.io_samples_s.reserve(checks);
  rec.health_rounds_s.reserve(checks);
  const auto t0 = std::chrono::steady_clock::now();
  bsp::heap::seal(bsp::heap::SealMode::kFatal);
  fly(o, mission, in.duration_s, csv, log, flight, rec, infos, energy);
  energy.finish(bsp::board_time());
  if (!dump.close(error)) {
    std::fprintf(stderr, "trn_mission: %s\n", error.c_str());
    return 1;
  }
  const std::uint64_t allocs = bsp::heap::allocs_after_seal();
  bsp::heap::unseal();
  const double host_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double clock_hz = static_cast<double>(bsp::board_config().profile.clock_hz);
  tools::ServiceStreams streams;
  streams.filter_outputs_s = rec.outputs_s;
  streams.io_samples_s = rec.io_samples_s;
  streams.health_rounds_s = rec.health_rounds_s;
  tools::FaultAccount faults = tools::join_faults(bsp::fault_log(), flight.events(), clock_hz, streams);
  // Without effect: nothing was detected and the delivered stream is the golden flight's bit for bit.
  if (in.golden_stream.has_value()) {
    const trn::tasks::FilterTaskStats f =
        flight_record(trn::tasks::slot_tile_now(trn::tasks::kSlotFilter), trn::tasks::kFilterTaskStatsRecord);
    const std::array<double, 4> mine{static_cast<double>(f.output_crc), static_cast<double>(f.outputs_delivered),
                                     static_cast<double>(f.last_delivered_job), static_cast<double>(f.started_job)};
    if (mine == *in.golden_stream) {
      tools::mark_no_effect(faults);
    }
  }
  log.grow(bsp::fault_log().size() + faults.false_alarms.size() + faults.healthy_disturbed.size());
  tools::log_fault_outcomes(bsp::fault_log(), flight.events(), faults, clock_hz, log);
  const tools::Summary s = make_summary(in, mission, flight, faults, rec, host_s, allocs, energy);
  if (!csv.close(error) || !write_outputs(in, s, log, tile_infos(mission, flight), faults, error)) {
    std::fprintf(stderr, "trn_mission: cannot write the run folder: %s\n", error.c_str());
    return 1;
  }
  print_summary(s, in.folder->dir());
  if (o.memory_map) {
    tools::write_memory_report(std::cout, bsp::board_config().profile.tiles());
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
