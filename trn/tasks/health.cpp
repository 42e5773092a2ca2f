/**
 * @file health.cpp
 * @brief Suspect-switch voting and fault-map updates on the health tile.
 */
#include "trn/tasks/health.hpp"

#include "kernel/kernel.hpp"
#include "trn/tasks/comm.hpp"
#include "trn/tasks/messages.hpp"
#include "udn/route.hpp"

#include <array>
#include <bit>

namespace trn::tasks {
namespace {

struct HealthState {
  bsp::TileId tile = bsp::kNoTile;
  std::uint64_t off = 0;  ///< tiles switched off by design
  std::array<std::uint64_t, bsp::kMaxTiles> reporters{};  ///< per suspect: bit r = tile r reported it
  std::uint64_t failed = 0;                              ///< switches declared failed
  std::uint32_t written = 0;
  std::array<HealthEvent, kHealthEventCapacity> ring{};
};

HealthState g_health{};

/** Reports come a few per failure: the health task looks every few ticks. */
constexpr k::Ticks kHealthIdleTicks = 4;

void note(const HealthEvent& e) noexcept {
  g_health.ring[g_health.written % kHealthEventCapacity] = e;
  ++g_health.written;
}

void take_report(std::uint32_t reporter, std::uint32_t suspect) noexcept {
  if (reporter >= bsp::kMaxTiles || suspect >= bsp::kMaxTiles || ((g_health.off >> suspect) & 1ULL) != 0ULL ||
      ((g_health.failed >> suspect) & 1ULL) != 0ULL) {
    return;  // off on purpose (it answers no ping), already failed, or nonsense
  }
  std::uint64_t& who = g_health.reporters[suspect];
  if (((who >> reporter) & 1ULL) != 0ULL) {
    return;
  }
  who |= 1ULL << reporter;
  const auto votes = static_cast<std::uint32_t>(std::popcount(who));
  note(HealthEvent{bsp::now(), HealthEventKind::kReport, static_cast<bsp::TileId>(suspect),
                   static_cast<bsp::TileId>(reporter), votes, 0U});
  if (votes < kVotesToFail) {
    return;
  }
  udn::FaultMap map = comm_fault_map();
  if (udn::fault_map_fail_tile(map, static_cast<bsp::TileId>(suspect)) != udn::RouteError::kOk) {
    return;
  }
  g_health.failed |= 1ULL << suspect;
  const std::uint32_t version = comm_set_fault_map(map);
  note(HealthEvent{bsp::now(), HealthEventKind::kSwitchFailed, static_cast<bsp::TileId>(suspect),
                   static_cast<bsp::TileId>(reporter), votes, version});
}

}  // namespace

void health_set_tile(bsp::TileId tile, std::uint64_t off_by_design) noexcept {
  g_health = HealthState{};
  g_health.tile = tile;
  g_health.off = off_by_design;
}

bsp::TileId health_tile() noexcept { return g_health.tile; }

std::uint64_t health_off_tiles() noexcept { return g_health.off; }

void health_task_main(void* arg) noexcept {
  const auto* cfg = static_cast<const HealthConfig*>(arg);
  if (cfg == nullptr || !comm_wait_ready(100)) {
    return;
  }
  udn::FtMessage m{};
  for (;;) {
    while (comm_receive(kChanControl, m) == udn::FtError::kOk) {
      if (m.data_words == kSuspectWords && m.data[0] == kMsgSuspect && m.data[1] == m.source) {
        take_report(m.data[1], m.data[2]);
      }
    }
    k::sleep(kHealthIdleTicks);
  }
}

std::uint32_t health_event_count() noexcept { return g_health.written; }

bool health_event(std::uint32_t i, HealthEvent* out) noexcept {
  if (out == nullptr || i >= g_health.written || g_health.written - i > kHealthEventCapacity) {
    return false;
  }
  *out = g_health.ring[i % kHealthEventCapacity];
  return true;
}

}  // namespace trn::tasks
