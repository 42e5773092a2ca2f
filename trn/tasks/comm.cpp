/**
 * @file comm.cpp
 * @brief Per-tile fault-tolerant messaging endpoint and its service task.
 */
#include "trn/tasks/comm.hpp"

#include "bsp_tile64/memory.hpp"
#include "kernel/kernel.hpp"
#include "trn/tasks/health.hpp"
#include "udn/ft_probe.hpp"

#include <array>
#include <new>

namespace trn::tasks {
namespace {

/** Suspect reports waiting to be sent to the health tile. */
constexpr std::uint32_t kPendingReports = 4U;

struct Endpoint {
  udn::FtNode* node;
  std::uint32_t map_version;  ///< fault-map version the node's routes were built from
  udn::FtProbe probe;
  bool probing;
  std::array<bsp::TileId, kPendingReports> pending;
  std::uint32_t pending_count;
};

std::array<Endpoint, bsp::kMaxTiles> g_endpoints{};
udn::FaultMap g_map{};
std::uint32_t g_map_version = 0U;
bool g_map_set = false;

/** Runs a node operation with interrupts masked (no preemption inside the node). */
class IrqGuard {
 public:
  IrqGuard() noexcept : was_(bsp::mask_irqs(true)) {}
  ~IrqGuard() { (void)bsp::mask_irqs(was_); }
  IrqGuard(const IrqGuard&) = delete;
  IrqGuard& operator=(const IrqGuard&) = delete;
  IrqGuard(IrqGuard&&) = delete;
  IrqGuard& operator=(IrqGuard&&) = delete;

 private:
  bool was_;
};

std::uint32_t tick32() noexcept { return static_cast<std::uint32_t>(k::now_ticks()); }

bool open_node(Endpoint& ep, bsp::TileId self) noexcept {
  const udn::FaultMap map = comm_fault_map();
  if (!g_map_set) {
    return false;
  }
  bsp::MemError err = bsp::MemError::kOk;
  auto* node = bsp::carve_array<udn::FtNode>(bsp::Region{self}, 1, "ft_node", &err);
  if (err != bsp::MemError::kOk) {
    return false;
  }
  ::new (node) udn::FtNode{};
  if (udn::ft_init(*node, self, map, udn::ft_task_port(), kCommFtConfig) != udn::FtError::kOk) {
    return false;
  }
  ep.map_version = g_map_version;
  ep.node = node;
  return true;
}

/** Probe hook (inside the service's guarded section): the report is sent after it. */
void on_suspect(void* ctx, bsp::TileId /*reporter*/, bsp::TileId suspect) noexcept {
  auto* ep = static_cast<Endpoint*>(ctx);
  if (ep->pending_count < kPendingReports) {
    ep->pending[ep->pending_count] = suspect;
    ++ep->pending_count;
  }
}

/** Stops probing neighbours that are off by design or failed in the fault map (nothing answers there). */
void prune_probe(Endpoint& ep) noexcept {
  const std::uint64_t skip = health_off_tiles() | g_map.failed_tiles;
  for (bsp::TileId& n : ep.probe.neighbour) {
    if (n != bsp::kNoTile && ((skip >> n) & 1ULL) != 0ULL) {
      n = bsp::kNoTile;
    }
  }
}

/** Sends waiting suspect reports without blocking; what the network refuses waits for the next tick. */
void send_reports(Endpoint& ep, bsp::TileId self) noexcept {
  const bsp::TileId to = health_tile();
  while (ep.pending_count > 0U && to != bsp::kNoTile) {
    const std::array<std::uint32_t, kSuspectWords> w{kMsgSuspect, self, ep.pending[ep.pending_count - 1U]};
    udn::FtError e = udn::FtError::kOk;
    {
      const IrqGuard guard;
      e = udn::ft_send(*ep.node, to, 0U, w, tick32());
    }
    if (e == udn::FtError::kWindowFull || e == udn::FtError::kNetFull) {
      return;
    }
    --ep.pending_count;  // sent, or no route to the health tile: nothing more to do
  }
}

}  // namespace

std::uint32_t comm_set_fault_map(const udn::FaultMap& map) noexcept {
  g_map = map;
  g_map_set = true;
  ++g_map_version;
  return g_map_version;
}

udn::FaultMap comm_fault_map() noexcept {
  if (!g_map_set) {
    const std::uint32_t cols = bsp::udn_grid_cols();
    if (cols != 0U && udn::fault_map_init(g_map, cols, bsp::tile_count() / cols) == udn::RouteError::kOk) {
      g_map_set = true;
    }
  }
  return g_map;
}

void comm_task_main(void* /*arg*/) noexcept {
  const bsp::TileId self = bsp::current_tile();
  Endpoint& ep = g_endpoints[self];
  ep = Endpoint{};
  if (!open_node(ep, self)) {
    return;
  }
  ep.probing = health_tile() != bsp::kNoTile &&
               udn::ft_probe_init(ep.probe, *ep.node, udn::ProbeConfig{kProbeMissThreshold}, &on_suspect, &ep) ==
                   udn::ProbeError::kOk;
  if (ep.probing) {
    prune_probe(ep);
  }
  for (std::uint32_t tick = 0;; ++tick) {
    {
      const IrqGuard guard;
      if (ep.probing && tick % kProbePeriodTicks == 0U) {
        (void)udn::ft_probe_round(ep.probe, *ep.node, tick32());
      }
      if (ep.map_version != g_map_version) {
        bsp::Work work{};
        if (udn::ft_set_fault_map(*ep.node, g_map, work) == udn::FtError::kOk) {
          ep.map_version = g_map_version;
        }
        if (ep.probing) {
          prune_probe(ep);
        }
        bsp::consume(work);
      }
      (void)udn::ft_poll(*ep.node, tick32(), kCommPacketsPerTick);
    }
    send_reports(ep, self);
    (void)k::wait_period();
  }
}

bool comm_ready() noexcept { return g_endpoints[bsp::current_tile()].node != nullptr; }

bool comm_wait_ready(std::uint32_t max_ticks) noexcept {
  for (std::uint32_t i = 0; i <= max_ticks; ++i) {
    if (comm_ready()) {
      return true;
    }
    k::sleep(1);
  }
  return false;
}

udn::FtError comm_send(bsp::TileId dest, std::uint32_t channel, std::span<const std::uint32_t> words,
                       std::uint32_t max_ticks) noexcept {
  udn::FtNode* node = g_endpoints[bsp::current_tile()].node;
  if (node == nullptr) {
    return udn::FtError::kBadArgs;
  }
  udn::FtError e = udn::FtError::kBadArgs;
  for (std::uint32_t i = 0; i <= max_ticks; ++i) {
    {
      const IrqGuard guard;
      e = udn::ft_send(*node, dest, channel, words, tick32());
    }
    if ((e != udn::FtError::kWindowFull && e != udn::FtError::kNetFull) || i == max_ticks) {
      return e;  // max_ticks 0: one attempt, never a wait
    }
    k::sleep(1);
  }
  return e;
}

udn::FtError comm_receive(std::uint32_t channel, udn::FtMessage& out) noexcept {
  udn::FtNode* node = g_endpoints[bsp::current_tile()].node;
  if (node == nullptr) {
    return udn::FtError::kBadArgs;
  }
  const IrqGuard guard;
  return udn::ft_receive(*node, channel, out);
}

const udn::FtNode* comm_node(bsp::TileId tile) noexcept {
  return tile < bsp::kMaxTiles ? g_endpoints[tile].node : nullptr;
}

}  // namespace trn::tasks
