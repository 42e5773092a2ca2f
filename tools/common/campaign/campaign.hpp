/**
 * @file campaign.hpp
 * @brief Fault-injection campaigns: the spec file, each run's fault plan drawn from (seed, index),
 *        and the outcome class of a run judged from its summary against the campaign's bounds.
 *
 * A campaign spec (TOML) is validated key by key like a fault plan. Run i's
 * plan is drawn from a stream seeded by (campaign_seed, i) alone, written to
 * the run's folder, and checked by the fault-plan parser, so any run can be
 * flown again bit for bit with `trn_mission --faults`. The rules of the
 * outcome classes are in docs/CAMPAIGNS.md.
 *
 * Host code: allocation and exceptions are fine here.
 */
#pragma once

#include "bsp_tile64/faults/fault_injector.hpp"
#include "tools/common/campaign/campaign_stats.hpp"

#include "trn/tasks/tile_map.hpp"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace tools::campaign {

/** A telecommand copied into every run's plan (e.g. reliability_high, so that faults meet a TMR filter). */
struct SpecCommand {
  double t_s = 0.0;
  std::string name;
};

struct Spec {
  std::string name;
  std::string scenario;             ///< scenario file (resolved against the spec's folder); empty: the built-in one
  std::string chip;                 ///< the chip flown (trn_mission --chip); empty: the scenario's (load_spec fills it)
  std::uint64_t seed = 1U;          ///< the scenario's seed in every run (the world, sensors and the injector's draws)
  bool seed_per_run = false;        ///< run i flies the scenario seed `seed` + i (a seed sweep); the golden run flies `seed`
  std::uint64_t campaign_seed = 1U; ///< seeds the plans' draws
  std::uint32_t runs = 0U;
  std::uint32_t faults_per_run = 1U;  ///< 0: fault-free runs (no kinds, no targets), e.g. a seed sweep of the filter's integrity
  double duration_s = 0.0;          ///< emulated seconds per run; 0: the whole descent
  double window_lo_s = 0.0;         ///< faults drawn uniformly in [lo, hi]
  double window_hi_s = 0.0;
  bool same_time = false;           ///< every fault of a run at one time drawn in the window (common-mode faults)
  std::vector<bsp::FaultKind> kinds;
  std::vector<std::string> roles;   ///< targets by role (resolved by the role directory when due)
  std::vector<std::uint32_t> tiles; ///< targets by tile
  std::vector<std::string> points;  ///< sdc: the points drawn from (empty: the first the target publishes at)
  std::vector<std::string> carves;  ///< seu: the carves drawn from (empty: anywhere in the tile's data)
  double pass_bound_m = 2.0;        ///< a correct output: final position error within this, mission not lost
  double degraded_bound_m = 20.0;   ///< a degraded but kept mission: within this
  double timeout_s = 600.0;         ///< host seconds a run may take before it is killed (a hang)
  std::vector<SpecCommand> commands;
};

struct SpecResult {
  Spec spec;
  std::string error;  ///< empty when valid; else every problem, one per line
  [[nodiscard]] bool ok() const { return error.empty(); }
};

/** The roles' deployment on the spec's chip (the TILE64's when the chip is empty). */
const trn::tasks::Deployment& spec_deployment(const Spec& spec);

/** The scenario seed run @p index flies: `seed`, or `seed` + index in a seed sweep. */
std::uint64_t scenario_seed(const Spec& spec, std::uint32_t index);

/** Parses a spec's text (named @p source in messages); @p max_duration_s bounds the window when duration_s is 0. */
SpecResult parse_spec(std::string_view text, const std::string& source, double max_duration_s);

/** Reads and parses a spec file; scenario paths are resolved against its folder. */
SpecResult load_spec(const std::string& path, double max_duration_s);

/** One run's plan, drawn. */
struct DrawnPlan {
  std::string toml;   ///< the fault-plan file's text
  std::string kind;   ///< the fault kind of the run ("mixed" when its faults differ, "none" in a fault-free campaign)
  std::string role;   ///< the target drawn: its role, or "tile_<n>" for a tile ("mixed" and "none" as for kind)
  std::string error;  ///< empty when drawn; else why no valid plan could be drawn
};

/**
 * Run @p index's plan: every value drawn from a stream seeded by
 * (spec.campaign_seed, index) only, so shards and resumed campaigns draw the
 * same plans. Each draw is checked by the fault-plan parser for @p tile_count
 * tiles and @p run_s seconds; a refused one (a target that publishes nothing
 * an sdc can hit) is drawn again, at most 64 times.
 */
DrawnPlan draw_plan(const Spec& spec, std::uint32_t index, std::uint32_t tile_count, double run_s);

/** What a run left behind, as the outcome rules read it (the keys of its summary.json in docs/CAMPAIGNS.md). */
struct RunFacts {
  bool exited_ok = false;       ///< the image exited with status 0 and wrote its summary
  bool mission_lost = false;
  double final_error_m = 0.0;
  std::uint32_t injected = 0U;           ///< faults delivered to the chip
  std::uint32_t not_delivered = 0U;      ///< faults armed but never delivered
  std::uint32_t detected = 0U;
  std::uint32_t recovered = 0U;
  std::uint32_t degraded_accepted = 0U;  ///< detected faults whose recovery gave up a mode (e.g. TMR to simplex)
  bool output_as_golden = false;         ///< the delivered navigation stream is bit for bit the golden run's
  /// Flags: carried to the run's record and the report; they do not change the class.
  std::uint32_t misdiagnosed = 0U;       ///< faults for which the flight accused the wrong tile or class
  std::uint32_t false_alarms = 0U;       ///< accusations no injected fault explains
  std::uint32_t healthy_disturbed = 0U;  ///< healthy tiles reset, retired, excluded or outvoted
};

/**
 * The outcome class of a run (docs/CAMPAIGNS.md, "Outcome classes"), in this order: hang_crash without a
 * summary; not_delivered when no fault reached the chip but one was armed; with nothing detected no_effect
 * (the stream is the golden one), masked (correct) or sdc; detected: detected_lost (not kept),
 * detected_recovered (correct, every detection recovered, none by giving up a mode) or detected_degraded.
 */
Outcome classify(const RunFacts& f, double pass_bound_m, double degraded_bound_m);

/** splitmix64: the seed of run @p index's stream. */
std::uint64_t run_seed(std::uint64_t campaign_seed, std::uint32_t index);

/** A shard "i/N" (0 <= i < N); false on anything else. */
bool parse_shard(std::string_view text, std::uint32_t& i, std::uint32_t& n);

}  // namespace tools::campaign
