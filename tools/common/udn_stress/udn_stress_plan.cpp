/**
 * @file udn_stress_plan.cpp
 * @brief udn_stress: the traffic plan, destinations, the board and the faults at t=0 both runs share.
 */
#include "tools/common/udn_stress/udn_stress_plan.hpp"

#include "kernel/kernel.hpp"

#include <algorithm>
#include <chrono>

namespace tools {
namespace detail {
namespace {

bool listed(const std::vector<std::uint32_t>& tiles, bsp::TileId t) {
  return std::find(tiles.begin(), tiles.end(), t) != tiles.end();
}

/** A uniform draw among the addressed tiles other than @p self. */
bsp::TileId uniform_target(const TrafficPlan& plan, bsp::Rng& rng, bsp::TileId self) {
  const bool self_addressed = self < bsp::kMaxTiles && plan.addressed[self];
  if (plan.target_count == 0U || (self_addressed && plan.target_count == 1U)) {
    return self;
  }
  auto i = static_cast<std::uint32_t>(rng.below(plan.target_count - (self_addressed ? 1U : 0U)));
  // targets are in id order: skipping self's slot keeps the draw uniform over the others.
  if (self_addressed && plan.targets[i] >= self) {
    ++i;
  }
  return plan.targets[i];
}

void link_utilisation(StressResult& r, const bsp::ChipProfile& p, bsp::Cycles elapsed) {
  double total = 0.0;
  std::uint32_t links = 0U;
  for (bsp::TileId t = 0; t < p.tiles(); ++t) {
    const std::uint32_t x = t % p.cols;
    const std::uint32_t y = t / p.cols;
    const std::array<bool, bsp::kUdnDirs> exists{x + 1U < p.cols, x > 0U, y > 0U, y + 1U < p.rows};
    for (std::uint32_t d = 0; d < bsp::kUdnDirs; ++d) {
      if (!exists[d] || elapsed == 0U) {
        continue;
      }
      const double u = static_cast<double>(bsp::udn_link_busy_cycles(t, static_cast<bsp::UdnDir>(d))) /
                       static_cast<double>(elapsed);
      total += u;
      r.link_utilisation_max = std::max(r.link_utilisation_max, u);
      ++links;
    }
  }
  r.link_utilisation_mean = links == 0U ? 0.0 : total / links;
}

}  // namespace

const bsp::ChipProfile& profile_named(const std::string& name) {
  return name == "maestro" ? bsp::kMaestro : bsp::kTile64;
}

TrafficPlan make_plan(const StressOptions& opts) {
  TrafficPlan plan;
  plan.profile = profile_named(opts.profile);
  plan.pattern = opts.pattern;
  for (bsp::TileId t = 0; t < plan.profile.tiles(); ++t) {
    const bool out = listed(opts.failed_tiles, t) || (opts.ft && listed(opts.failed_switches, t));
    plan.sends[t] = !out;
    plan.addressed[t] = !out;
    if (!out) {
      plan.targets[plan.target_count++] = t;
    }
  }
  plan.sender_count = plan.target_count;  // the same tiles send and are addressed in both modes
  std::uint32_t i = 0U;
  for (bsp::TileId t = 0; plan.sender_count > 0U && t < plan.profile.tiles(); ++t) {
    if (plan.sends[t]) {
      plan.quota[t] = opts.packets / plan.sender_count + (i < opts.packets % plan.sender_count ? 1U : 0U);
      ++i;
    }
  }
  return plan;
}

bsp::TileId pick_destination(const TrafficPlan& plan, bsp::Rng& rng, bsp::TileId self) {
  const bsp::ChipProfile& p = plan.profile;
  switch (plan.pattern) {
    case TrafficPattern::kTranspose: {
      const bsp::TileId d = (self % p.cols) * p.cols + self / p.cols;  // grids are square
      return plan.addressed[d] ? d : uniform_target(plan, rng, self);
    }
    case TrafficPattern::kHotspot: {
      const bsp::TileId hot = (p.rows / 2U) * p.cols + p.cols / 2U;
      if (rng.below(4U) == 0U && hot != self && plan.addressed[hot]) {
        return hot;
      }
      return uniform_target(plan, rng, self);
    }
    case TrafficPattern::kUniform:
      break;
  }
  return uniform_target(plan, rng, self);
}

bool boot_stress_board(const StressOptions& opts, const TrafficPlan& plan, k::TaskTable tasks,
                       const bsp::NetConfig& net) {
  const bsp::ChipProfile& p = plan.profile;
  bsp::BoardConfig cfg = bsp::default_config(p);
  const auto quantum = static_cast<bsp::Cycles>(opts.quantum_us * static_cast<double>(p.clock_hz) / 1e6);
  cfg.quantum_cycles = quantum < 1U ? 1U : (quantum > cfg.tick_cycles ? cfg.tick_cycles : quantum);
  cfg.seed = opts.seed;
  cfg.monitor_tile = bsp::kNoTile;
  for (bsp::TileId t = 0; t < p.tiles(); ++t) {
    if (plan.sends[t]) {
      cfg.boot[t] = &k::boot_entry;
      k::set_task_table(t, tasks, cfg.tick_cycles);
    }
  }
  if (bsp::board_init(cfg) != bsp::BoardError::kOk || bsp::udn_net_init(net) != bsp::NetError::kOk) {
    return false;
  }
  bsp::udn_net_set_ber(opts.ber);
  bool ok = true;
  for (const std::uint32_t t : opts.failed_tiles) {
    ok = ok && bsp::udn_net_fail_switch(t) == bsp::NetError::kOk;
  }
  for (const std::uint32_t t : opts.failed_switches) {
    ok = ok && bsp::udn_net_fail_switch(t) == bsp::NetError::kOk;
  }
  for (const std::string& l : opts.failed_links) {
    LinkSpec spec{};
    ok = ok && parse_link(l, p.cols, p.rows, spec).empty() &&
         bsp::udn_net_fail_link(spec.tile, spec.dir) == bsp::NetError::kOk;
  }
  return ok;
}

void run_stress_board(const StressOptions& opts, const TrafficPlan& plan, bsp::StopPredicate done,
                      bsp::heap::SealMode seal, StressResult& r) {
  const bsp::ChipProfile& p = plan.profile;
  r.bound_ms = bound_ms(opts);
  const auto max_cycles = static_cast<bsp::Cycles>(r.bound_ms * static_cast<double>(p.cycles_per_ms()));
  const auto t0 = std::chrono::steady_clock::now();
  bsp::heap::seal(seal);
  const bsp::RunResult run = bsp::run_until(done, nullptr, max_cycles);
  bsp::heap::unseal();
  const auto t1 = std::chrono::steady_clock::now();
  r.heap_allocs_during_run = bsp::heap::allocs_after_seal();
  r.host_s = std::chrono::duration<double>(t1 - t0).count();
  r.net = bsp::udn_net_stats();
  r.end = done(nullptr) ? StressEnd::kCompleted : StressEnd::kBound;
  r.emulated_s = static_cast<double>(run.end_cycle) / static_cast<double>(p.clock_hz);
  link_utilisation(r, p, run.end_cycle);
}

}  // namespace detail

double bound_ms(const StressOptions& opts) {
  if (opts.max_ms > 0.0) {
    return opts.max_ms;
  }
  const detail::TrafficPlan plan = detail::make_plan(opts);
  const std::uint64_t busiest = plan.sender_count == 0U ? 0U : plan.quota[plan.targets[0]];
  // The busiest sender needs about busiest / rate us; twice that absorbs
  // back-pressure and retransmissions, and one second covers boot and drain.
  return 1000.0 + 2.0 * static_cast<double>(busiest) / opts.rate_per_us / 1000.0;
}

}  // namespace tools
