/**
 * @file phase_energy.cpp
 * @brief Energy per mission phase from snapshots of the board's meter, and the summary's energy figures.
 */
#include "tools/common/mission/phase_energy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace tools {
namespace {

bsp::StateCycles minus(const bsp::StateCycles& a, const bsp::StateCycles& b) noexcept {
  return bsp::StateCycles{a.off - b.off, a.booting - b.booting, a.idle - b.idle, a.active - b.active};
}

bool check_windows(const std::vector<PhaseWindow>& w, std::string& error) {
  if (w.empty()) {
    error = "phases: none given (the flight needs at least one, starting at 0 s)";
    return false;
  }
  if (w.front().start_s != 0.0) {
    error = "phases: the first phase ('" + w.front().name + "') must start at 0 s";
    return false;
  }
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (w[i].name.empty() || !std::isfinite(w[i].start_s) || w[i].start_s < 0.0) {
      error = "phases: phase " + std::to_string(i) + " has no name or a start that is not a time";
      return false;
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (w[j].name == w[i].name) {
        error = "phases: the name '" + w[i].name + "' is used twice";
        return false;
      }
    }
  }
  return true;
}

}  // namespace

bool PhaseEnergy::init(std::vector<PhaseWindow> windows, const bsp::PowerModel& model, bsp::Cycles quantum_cycles,
                       std::uint32_t tiles, std::string& error) {
  if (!check_windows(windows, error)) {
    return false;
  }
  if (quantum_cycles == 0U || model.clock_hz == 0U || tiles == 0U || tiles > bsp::kMaxTiles) {
    error = "phases: the board's quantum, clock or tile count is not usable";
    return false;
  }
  std::vector<bsp::Cycles> starts;
  const auto q = static_cast<double>(quantum_cycles);
  for (std::size_t i = 0; i < windows.size(); ++i) {
    const double quanta = std::round(windows[i].start_s * static_cast<double>(model.clock_hz) / q);
    starts.push_back(static_cast<bsp::Cycles>(quanta) * quantum_cycles);
    if (i > 0U && starts[i] <= starts[i - 1U]) {
      error = "phases: '" + windows[i].name + "' does not start at least one quantum after '" +
              windows[i - 1U].name + "'";
      return false;
    }
  }
  windows_ = std::move(windows);
  starts_ = std::move(starts);
  snaps_.assign(windows_.size() + 1U, Snapshot{});
  taken_at_.assign(windows_.size() + 1U, 0U);
  tiles_ = tiles;
  model_ = model;
  finished_ = false;
  // The first phase starts at board time 0, where every count is 0: its snapshot is the zeros.
  taken_ = 1U;
  return true;
}

bsp::Cycles PhaseEnergy::next_boundary(bsp::Cycles now) const noexcept {
  for (const bsp::Cycles s : starts_) {
    if (s > now) {
      return s;
    }
  }
  return std::numeric_limits<bsp::Cycles>::max();
}

void PhaseEnergy::take(std::size_t index, bsp::Cycles now) noexcept {
  Snapshot& snap = snaps_[index];
  for (bsp::TileId t = 0; t < tiles_; ++t) {
    snap[t] = bsp::tile_energy(t).cycles;
  }
  taken_at_[index] = now;
}

void PhaseEnergy::step(bsp::Cycles now) noexcept {
  while (!finished_ && taken_ < starts_.size() && starts_[taken_] <= now) {
    take(taken_, now);
    ++taken_;
  }
}

void PhaseEnergy::finish(bsp::Cycles now) noexcept {
  if (finished_ || snaps_.empty()) {
    return;
  }
  step(now);
  for (; taken_ <= starts_.size(); ++taken_) {
    take(taken_, now);  // phases not started yet are empty; the last snapshot is the end of the flight
  }
  finished_ = true;
}

bsp::StateCycles PhaseEnergy::tile_cycles(std::size_t phase, bsp::TileId tile) const {
  if (phase >= windows_.size() || tile >= tiles_ || phase + 1U >= taken_) {
    return bsp::StateCycles{0U, 0U, 0U, 0U};
  }
  return minus(snaps_[phase + 1U][tile], snaps_[phase][tile]);
}

double PhaseEnergy::tile_j(std::size_t phase, bsp::TileId tile) const {
  return bsp::energy_j(tile_cycles(phase, tile), model_);
}

double PhaseEnergy::phase_j(std::size_t phase) const {
  double j = 0.0;
  for (bsp::TileId t = 0; t < tiles_; ++t) {
    j += tile_j(phase, t);
  }
  return j;
}

bsp::RunResult run_with_phases(bsp::Cycles target, PhaseEnergy& energy) noexcept {
  bsp::RunResult r{bsp::board_time(), bsp::StopReason::kTimeReached};
  // One run per boundary crossed, and one to the target: at most phases() + 1.
  for (std::size_t n = 0; n <= energy.phases() && bsp::board_time() < target; ++n) {
    const bsp::Cycles now = bsp::board_time();
    const bsp::Cycles stop = std::min(target, energy.next_boundary(now));
    r = bsp::run_for(stop - now);
    energy.step(r.end_cycle);
    if (r.reason != bsp::StopReason::kTimeReached) {
      break;  // stopped early: the caller's next step goes on from here, as it would without phases
    }
  }
  return r;
}

void add_energy_summary(const PhaseEnergy& phases, const std::vector<std::string>& tile_roles, double emulated_s,
                        Summary& s) {
  const double total = bsp::chip_energy_j();
  s.extra.emplace_back("energy_j", total);
  s.extra.emplace_back("mean_power_w", emulated_s > 0.0 ? total / emulated_s : 0.0);
  std::vector<std::pair<std::string, double>> by_phase;
  for (std::size_t p = 0; p < phases.phases(); ++p) {
    by_phase.emplace_back(phases.window(p).name, phases.phase_j(p));
  }
  std::vector<std::pair<std::string, double>> by_role;
  bsp::StateCycles states{0U, 0U, 0U, 0U};
  for (bsp::TileId t = 0; t < tile_roles.size() && t < bsp::tile_count(); ++t) {
    const bsp::TileEnergy e = bsp::tile_energy(t);
    auto it = std::find_if(by_role.begin(), by_role.end(), [&](const auto& r) { return r.first == tile_roles[t]; });
    if (it == by_role.end()) {
      by_role.emplace_back(tile_roles[t], 0.0);
      it = by_role.end() - 1;
    }
    it->second += e.joules;
    states.off += e.cycles.off;
    states.booting += e.cycles.booting;
    states.idle += e.cycles.idle;
    states.active += e.cycles.active;
  }
  const bsp::PowerModel model = bsp::power_model();
  const std::vector<std::pair<std::string, double>> by_state{
      {"off", bsp::energy_j(bsp::StateCycles{states.off, 0U, 0U, 0U}, model)},
      {"booting", bsp::energy_j(bsp::StateCycles{0U, states.booting, 0U, 0U}, model)},
      {"idle", bsp::energy_j(bsp::StateCycles{0U, 0U, states.idle, 0U}, model)},
      {"active", bsp::energy_j(bsp::StateCycles{0U, 0U, 0U, states.active}, model)},
  };
  s.objects.emplace_back("energy_j_by_phase", std::move(by_phase));
  s.objects.emplace_back("energy_j_by_role", std::move(by_role));
  s.objects.emplace_back("energy_j_by_state", by_state);
}

}  // namespace tools
