/**
 * @file comm.cpp
 * @brief Per-tile fault-tolerant messaging endpoint and its service task.
 */
#include "trn/tasks/comm.hpp"

#include "bsp_tile64/memory.hpp"
#include "kernel/kernel.hpp"

#include <array>
#include <new>

namespace trn::tasks {
namespace {

struct Endpoint {
  udn::FtNode* node;
  std::uint32_t map_version;  ///< fault-map version the node's routes were built from
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
  if (!g_map_set) {
    const std::uint32_t cols = bsp::udn_grid_cols();
    if (cols == 0U || udn::fault_map_init(g_map, cols, bsp::tile_count() / cols) != udn::RouteError::kOk) {
      return false;
    }
    g_map_set = true;
  }
  bsp::MemError err = bsp::MemError::kOk;
  auto* node = bsp::carve_array<udn::FtNode>(bsp::Region{self}, 1, "ft_node", &err);
  if (err != bsp::MemError::kOk) {
    return false;
  }
  ::new (node) udn::FtNode{};
  if (udn::ft_init(*node, self, g_map, udn::ft_task_port(), kCommFtConfig) != udn::FtError::kOk) {
    return false;
  }
  ep.map_version = g_map_version;
  ep.node = node;
  return true;
}

}  // namespace

void comm_set_fault_map(const udn::FaultMap& map) noexcept {
  g_map = map;
  g_map_set = true;
  ++g_map_version;
}

void comm_task_main(void* /*arg*/) noexcept {
  const bsp::TileId self = bsp::current_tile();
  Endpoint& ep = g_endpoints[self];
  ep = Endpoint{};
  if (!open_node(ep, self)) {
    return;
  }
  for (;;) {
    {
      const IrqGuard guard;
      if (ep.map_version != g_map_version) {
        bsp::Work work{};
        if (udn::ft_set_fault_map(*ep.node, g_map, work) == udn::FtError::kOk) {
          ep.map_version = g_map_version;
        }
        bsp::consume(work);
      }
      (void)udn::ft_poll(*ep.node, tick32(), kCommPacketsPerTick);
    }
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
    if (e != udn::FtError::kWindowFull && e != udn::FtError::kNetFull) {
      return e;
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
