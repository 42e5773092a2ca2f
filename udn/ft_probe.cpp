/**
 * @file ft_probe.cpp
 * @brief Neighbour pings, miss counting and suspect reports.
 */
#include "udn/ft_probe.hpp"

namespace udn {

ProbeError ft_probe_init(FtProbe& probe, const FtNode& node, const ProbeConfig& config, SuspectHook hook,
                         void* hook_ctx) noexcept {
  if (config.miss_threshold == 0U || node.self == bsp::kNoTile || node.routes.cols == 0U) {
    return ProbeError::kBadArgs;
  }
  probe = FtProbe{};
  probe.config = config;
  probe.hook = hook;
  probe.hook_ctx = hook_ctx;
  const std::uint32_t cols = node.routes.cols;
  const std::uint32_t rows = node.routes.tiles / cols;
  const std::uint32_t x = node.self % cols;
  const std::uint32_t y = node.self / cols;
  probe.neighbour[static_cast<std::size_t>(bsp::UdnDir::kEast)] = (x + 1U < cols) ? node.self + 1U : bsp::kNoTile;
  probe.neighbour[static_cast<std::size_t>(bsp::UdnDir::kWest)] = (x > 0U) ? node.self - 1U : bsp::kNoTile;
  probe.neighbour[static_cast<std::size_t>(bsp::UdnDir::kNorth)] = (y > 0U) ? node.self - cols : bsp::kNoTile;
  probe.neighbour[static_cast<std::size_t>(bsp::UdnDir::kSouth)] = (y + 1U < rows) ? node.self + cols : bsp::kNoTile;
  return ProbeError::kOk;
}

std::uint32_t ft_probe_round(FtProbe& probe, FtNode& node, std::uint32_t now_tick) noexcept {
  std::uint32_t reported = 0U;
  ++probe.round;
  for (std::size_t d = 0U; d < bsp::kUdnDirs; ++d) {
    const bsp::TileId nb = probe.neighbour[d];
    if (nb >= node.routes.tiles || nb >= kRouteMaxTiles) {  // kNoTile, or an upset one (the endpoint sets it up again)
      continue;
    }
    if (probe.nonce[d] != 0U) {
      if (node.pong_nonce[nb] == probe.nonce[d]) {
        probe.misses[d] = 0U;
        probe.reported[d] = false;
      } else {
        ++probe.misses[d];
      }
    }
    if (probe.misses[d] >= probe.config.miss_threshold && !probe.reported[d]) {
      probe.reported[d] = true;
      ++reported;
      ft_event_emit(node.sink, node.self, FtEvent{now_tick, FtCause::kSuspectNeighbour, 0U, 0U, nb, 0U});
      if (probe.hook != nullptr) {
        probe.hook(probe.hook_ctx, node.self, nb);
      }
    }
    // Nonce: round in the high bits, direction in the low ones, never 0.
    const std::uint32_t nonce = (probe.round << 2U) | static_cast<std::uint32_t>(d) | 0x8000'0000U;
    const bool sent = ft_send_control(node, nb, FtKind::kPing, 0U, nonce, false) == FtError::kOk;
    probe.nonce[d] = sent ? nonce : 0U;  // a refused ping is not a miss of the neighbour
  }
  return reported;
}

}  // namespace udn
