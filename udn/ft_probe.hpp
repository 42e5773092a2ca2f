/**
 * @file ft_probe.hpp
 * @brief Neighbour switch probe: a PING per round to each mesh neighbour, suspects after N misses.
 *
 * Meant for a low-priority periodic task per tile: each call of
 * ft_probe_round() first scores the previous round (a neighbour whose PONG
 * with the round's nonce has not come back through the tile's FtNode counts a
 * miss), then pings every neighbour again, straight (one hop, no routing), so
 * a ping tests exactly the neighbour's switch and the link to it. After
 * miss_threshold consecutive misses the neighbour is reported once: an
 * FtEvent (kSuspectNeighbour) in the node's log and the suspect hook, through
 * which the health layer updates the fault map. A PONG resets the count.
 * The period between rounds must exceed a one-hop round trip plus a poll of
 * both tiles: on the emulated board a leg becomes visible about two quanta
 * after the send, so a ping and its pong need some five quanta (the tests use
 * two ticks of four quanta).
 */
#pragma once

#include "udn/ft_link.hpp"

#include <array>
#include <cstdint>

namespace udn {

/** Called once per suspect: the health layer's entry point (may update the fault map). */
using SuspectHook = void (*)(void* ctx, bsp::TileId reporter, bsp::TileId suspect);

struct ProbeConfig {
  std::uint32_t miss_threshold = 3U;  ///< consecutive missed rounds before a neighbour is suspect (>= 1)
};

struct FtProbe {
  ProbeConfig config{};
  SuspectHook hook = nullptr;
  void* hook_ctx = nullptr;
  std::array<bsp::TileId, bsp::kUdnDirs> neighbour{};  ///< kNoTile off the grid
  std::array<std::uint32_t, bsp::kUdnDirs> misses{};
  std::array<std::uint32_t, bsp::kUdnDirs> nonce{};  ///< nonce of the outstanding ping (0: none)
  std::array<bool, bsp::kUdnDirs> reported{};
  std::uint32_t round = 0U;
};

enum class ProbeError : std::uint8_t { kOk, kBadArgs };

/** Sets up the probe of @p node's tile. @return kBadArgs for threshold 0 or an uninitialised node. */
ProbeError ft_probe_init(FtProbe& probe, const FtNode& node, const ProbeConfig& config, SuspectHook hook,
                         void* hook_ctx) noexcept;

/**
 * Scores the last round and sends the next one. The node must be polled in
 * between (its listener answers PINGs and records PONGs).
 * @return neighbours newly reported in this call.
 */
std::uint32_t ft_probe_round(FtProbe& probe, FtNode& node, std::uint32_t now_tick) noexcept;

}  // namespace udn
