/**
 * @file energy.cpp
 * @brief The energy meter's queries: per-state cycles of a tile, their joules under the power model.
 *
 * The cycles are charged by the board where a tile's clock advances
 * (detail::charge_cycles); nothing here changes board state.
 */
#include "bsp_tile64/emu/energy.hpp"

#include "bsp_tile64/emu/board_state.hpp"

#include <cstddef>
#include <cstdint>

namespace bsp {
namespace {

/** Joules of @p cycles spent at @p uw microwatts under a clock of @p clock_hz. */
double state_j(Cycles cycles, std::uint64_t uw, std::uint64_t clock_hz) noexcept {
  return static_cast<double>(cycles) * static_cast<double>(uw) / (static_cast<double>(clock_hz) * 1e6);
}

StateCycles cycles_of(const detail::Tile& t) noexcept {
  const auto at = [&t](PowerState s) { return t.state_cycles[static_cast<std::size_t>(s)]; };
  return StateCycles{at(PowerState::kOff), at(PowerState::kBooting), at(PowerState::kIdle), at(PowerState::kActive)};
}

}  // namespace

PowerModel power_model() noexcept { return power_model_for(board_config().profile); }

double energy_j(const StateCycles& cycles, const PowerModel& model) noexcept {
  if (model.clock_hz == 0U) {
    return 0.0;
  }
  const std::uint64_t f = model.clock_hz;
  double j = state_j(cycles.off, tile_uw(model, PowerState::kOff), f);
  j += state_j(cycles.booting, tile_uw(model, PowerState::kBooting), f);
  j += state_j(cycles.idle, tile_uw(model, PowerState::kIdle), f);
  j += state_j(cycles.active, tile_uw(model, PowerState::kActive), f);
  return j;
}

TileEnergy tile_energy(TileId tile) noexcept {
  if (!detail::valid_tile(tile)) {
    return TileEnergy{StateCycles{0U, 0U, 0U, 0U}, 0.0};
  }
  const StateCycles c = cycles_of(detail::board().tile[tile]);
  return TileEnergy{c, energy_j(c, power_model())};
}

double chip_energy_j() noexcept {
  const PowerModel model = power_model();
  const detail::Board& b = detail::board();
  double j = 0.0;
  for (TileId t = 0; t < b.tiles; ++t) {
    j += energy_j(cycles_of(b.tile[t]), model);
  }
  return j;
}

PowerState metered_state(TileId tile) noexcept {
  if (!detail::valid_tile(tile)) {
    return PowerState::kOff;
  }
  const detail::Tile& t = detail::board().tile[tile];
  const bool on = t.power == PowerState::kActive || t.power == PowerState::kIdle;
  const bool ran = t.charged == PowerState::kActive || t.charged == PowerState::kIdle;
  // Off and booting are the board's word; a tile that is on is what its latest cycle did, once it has one.
  return on && ran ? t.charged : t.power;
}

const char* power_state_name(PowerState state) noexcept {
  switch (state) {
    case PowerState::kOff:
      return "off";
    case PowerState::kBooting:
      return "booting";
    case PowerState::kIdle:
      return "idle";
    case PowerState::kActive:
      break;
  }
  return "active";
}

}  // namespace bsp
