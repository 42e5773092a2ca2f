/**
 * @file health_agent.cpp
 * @brief Every tile's health agent, and the self-test kernel (see health_agent.hpp).
 */
#include "fdir/health_agent.hpp"

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/power.hpp"
#include "bsp_tile64/api/udn_driver.hpp"
#include "fdir/assert.hpp"
#include "fdir/event_log.hpp"
#include "fdir/health_messages.hpp"
#include "fdir/health_table.hpp"
#include "fdir/net_health.hpp"
#include "kernel/kernel.hpp"
#include "udn/crc32c.hpp"
#include "udn/endpoint.hpp"

#include <array>
#include <bit>
#include <string_view>
#include <new>

namespace fdir {
namespace {

/** Boot reports the supervisor's queue takes per tick at start (its receive queue holds 8). */
constexpr bsp::TileId kReportsPerTick = 4U;

/** Ticks of the watched task furthest past its budget; 0 when all are within. */
struct Overdue {
  k::TaskId task = k::kNoTask;
  std::uint32_t late = 0U;
  std::uint32_t budget = 0U;
};

/** Carves and writes this tile's resident self-test pattern (at the agent's start, after each boot). */
void pattern_init(bsp::TileId self) noexcept {
  bsp::MemError err = bsp::MemError::kOk;
  auto* p = bsp::carve_array<std::uint8_t>(bsp::Region{self}, kSelfTestPatternBytes, kSelfTestCarve, &err);
  if (err == bsp::MemError::kOk && p != nullptr) {
    self_test_pattern_fill(std::span<std::uint8_t>{p, kSelfTestPatternBytes});
  }  // else no pattern, no answers: the tile shows as late, never as wrong
}

}  // namespace

std::span<std::uint8_t> self_test_pattern(bsp::TileId self) noexcept {
  const std::span<std::byte> ram = bsp::region_span(bsp::Region{self});
  for (const bsp::CarveRecord& c : bsp::region_carves(bsp::Region{self})) {
    if (c.what != nullptr && std::string_view(c.what) == kSelfTestCarve && c.bytes == kSelfTestPatternBytes &&
        c.offset + c.bytes <= ram.size()) {
      return std::span<std::uint8_t>{reinterpret_cast<std::uint8_t*>(ram.data() + c.offset), c.bytes};  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): raw region storage
    }
  }
  return {};
}

bool self_test_digest(bsp::TileId self, std::uint32_t seed, std::uint32_t& digest) noexcept {
  const std::span<std::uint8_t> pattern = self_test_pattern(self);
  if (pattern.empty()) {
    return false;
  }
  bsp::Work work{};
  digest = self_test_kernel(seed, pattern, work);
  self_test_pattern_fill(pattern);
  work.mem_words += kSelfTestPatternBytes / 4U;
  bsp::consume(work);
  (void)bsp::publish_filter(kSelfTestChannel, &digest, sizeof digest);
  return true;
}

namespace {

/** The watcher's view of the supervisor's heartbeat (its agent's, on the watcher's tile). */
struct Watch {
  k::Ticks last_alive = 0U;  ///< tick of the last heartbeat (the watcher's start before the first)
  k::Ticks reset_at = 0U;
  std::uint32_t resets = 0U;
  bool pending = false;  ///< reset by the watcher, not heard since
  bool silent = false;   ///< named silent, not heard since
  bool cut_off = false;  ///< the watcher heard nobody at its last check (reported once per spell)
};

/**
 * A self-test answer the network refused (back-pressure; sent without waiting): sent again at
 * the agent's next pass, until the next request replaces it. Lost, the round went late.
 */
struct OwedAnswer {
  std::array<std::uint32_t, kSelfTestResultWords> w{};
  bool owed = false;
};

/** Sends @p a to the supervisor; it stays owed if the network refuses it. */
void send_answer(const HealthAgentConfig& cfg, OwedAnswer& a) noexcept {
  a.owed = udn::endpoint_send(cfg.supervisor, udn::kFtChanHealth, a.w, 0U) != udn::FtError::kOk;
}

/** A heartbeat of the supervisor's tile: a reset the watcher commanded is closed by it. */
void take_alive(Watch& w, const TileBootReport& alive, bsp::TileId supervisor) noexcept {
  const k::Ticks now = k::now_ticks();
  if (w.pending) {
    report(EventId::kTileRecovered, supervisor, static_cast<std::uint32_t>(alive.cause),
           static_cast<std::uint32_t>(now >= w.reset_at ? now - w.reset_at : 0U));
  }
  w.pending = false;
  w.silent = false;
  w.cut_off = false;
  w.last_alive = now;
}

/**
 * Takes the messages waiting on the health channel (a few per pass): the
 * supervisor's self-test requests, answered, and, on the watcher's tile, the
 * supervisor tile's heartbeats.
 */
void take_agent_messages(bsp::TileId self, const HealthAgentConfig& cfg, Watch& watch, OwedAnswer& answer) noexcept {
  if (answer.owed) {
    send_answer(cfg, answer);
  }
  udn::FtMessage m{};
  for (std::uint32_t i = 0; i < 2U && udn::endpoint_receive(udn::kFtChanHealth, m) == udn::FtError::kOk; ++i) {
    if (m.source != cfg.supervisor) {
      continue;
    }
    const std::span<const std::uint32_t> in(m.data.data(), m.data_words);
    TileBootReport alive{};
    if (unpack_alive(in, alive) && cfg.watcher == self) {
      take_alive(watch, alive, cfg.supervisor);
      continue;
    }
    SelfTestRequest req{};
    std::uint32_t digest = 0U;
    if (!unpack_self_test(in, req) || !self_test_digest(self, req.seed, digest)) {
      continue;
    }
    pack_self_test_result(SelfTestResult{self, req.round, digest}, answer.w);
    send_answer(cfg, answer);  // refused, it is sent again at the next pass
  }
}

/**
 * The watcher's check: a heartbeat missing past its timeout names the
 * supervisor's tile once and resets it, under the cap; the next heartbeat
 * closes the recovery (take_alive).
 */
void watch_supervisor(Watch& w, const HealthAgentConfig& cfg, bsp::TileId self) noexcept {
  const k::Ticks now = k::now_ticks();
  const k::Ticks since = now >= w.last_alive ? now - w.last_alive : 0U;
  if (since <= cfg.watcher_timeout_ticks || w.silent) {
    return;
  }
  // A watcher that hears nobody (its own switch failed) misses the heartbeat for its own reason:
  // resetting a healthy supervisor would wipe the network-health votes that are to name this very
  // switch. It waits; once it hears its neighbours again the timeout runs afresh.
  if (udn::endpoint_cut_off()) {
    if (!w.cut_off) {
      report(EventId::kWatcherCutOff, cfg.supervisor, self, static_cast<std::uint32_t>(since));
    }
    w.cut_off = true;
    w.last_alive = now;
    return;
  }
  w.cut_off = false;
  w.silent = true;
  report(EventId::kSupervisorSilent, cfg.supervisor, self, static_cast<std::uint32_t>(since), w.resets);
  if (w.resets >= cfg.max_watcher_resets) {
    report(EventId::kActionCapped, cfg.supervisor, self, w.resets);
    return;
  }
  if (bsp::reset_tile(cfg.supervisor) != bsp::BoardError::kOk) {
    report(EventId::kTileLost, cfg.supervisor, self);
    return;
  }
  ++w.resets;
  w.pending = true;
  w.reset_at = now;
  w.last_alive = now;  // its boot and first heartbeat get a whole timeout again
  report(EventId::kTileReset, cfg.supervisor, 1U, w.resets, cfg.max_watcher_resets);
}

Overdue find_overdue(bsp::TileId self, k::Ticks now) noexcept {
  Overdue o{};
  const std::uint32_t n = k::task_count(self);
  for (std::uint32_t i = 0; i < n && i < k::config::kMaxTasks; ++i) {
    k::TaskWatch st{};
    if (k::task_watch(self, static_cast<k::TaskId>(i), &st) != k::Status::kOk || st.watch_ticks == 0U) {
      continue;
    }
    const k::Ticks since = now >= st.last_checkin ? now - st.last_checkin : 0U;
    if (since > st.watch_ticks && since - st.watch_ticks > o.late) {
      o.task = static_cast<k::TaskId>(i);
      o.late = static_cast<std::uint32_t>(since - st.watch_ticks);
      o.budget = st.watch_ticks;
    }
  }
  return o;
}

}  // namespace

void health_agent_main(void* arg) noexcept {
  const auto* cfg = static_cast<const HealthAgentConfig*>(arg);
  const bsp::TileId self = bsp::current_tile();
  if (cfg == nullptr || self >= bsp::kMaxTiles || cfg->watchdog_ticks < 2U * kAgentPeriodTicks) {
    return;  // no kicks: the hardware watchdog is never armed, the neighbours' probes still see the tile
  }
  const bsp::BootCause cause = bsp::boot_cause();
  // The supervisor's own tile has nobody above it: its watchdog resets it.
  const bool own_supervisor = cfg->supervisor == self;
  bsp::watchdog_arm(static_cast<bsp::Cycles>(cfg->watchdog_ticks) * bsp::tick_cycles(), own_supervisor);
  bool reported = cfg->supervisor == bsp::kNoTile || own_supervisor;
  bool overdue_written = false;
  std::array<std::uint32_t, kBootedWords> boot{};
  std::array<std::uint32_t, kAliveWords> alive{};
  pack_booted(TileBootReport{self, cause}, boot);
  pack_alive(TileBootReport{self, cause}, alive);
  const bool sends_alive = own_supervisor && cfg->watcher < bsp::kMaxTiles && cfg->watcher != self;
  const bool watches = cfg->watcher == self && cfg->supervisor < bsp::kMaxTiles && !own_supervisor;
  Watch watch{};
  watch.last_alive = k::now_ticks();
  OwedAnswer answer{};
  pattern_init(self);
  recovery_clear(self);  // a request from before this boot was the one the restart answered
  for (;;) {
    const Overdue o = find_overdue(self, k::now_ticks());
    // A failed flight check asked for the tile's recovery: no more kicks, the watchdog restarts it.
    if (o.task == k::kNoTask && recovery_requested(self) == 0U) {
      bsp::watchdog_kick();
      overdue_written = false;
      // The remote kick: the watcher hears it only while the supervisor's tasks are within budget.
      if (sends_alive && udn::endpoint_ready()) {
        (void)udn::endpoint_send(cfg->watcher, udn::kFtChanHealth, alive, 0U);  // a lost one is a late one
      }
    } else if (o.task != k::kNoTask && !overdue_written) {
      report(EventId::kTaskOverdue, o.task, self, o.late, o.budget);
      overdue_written = true;
    }
    // Staggered by tile: 40 tiles booting together would overrun the supervisor's queue.
    if (!reported && udn::endpoint_ready() && k::now_ticks() >= self / kReportsPerTick) {
      reported = udn::endpoint_send(cfg->supervisor, udn::kFtChanHealth, boot, 0U) == udn::FtError::kOk;
    }
    if (!own_supervisor && cfg->supervisor != bsp::kNoTile && udn::endpoint_ready()) {
      take_agent_messages(self, *cfg, watch, answer);
    }
    if (watches) {
      watch_supervisor(watch, *cfg, self);
    }
    (void)k::wait_period();
  }
}

namespace {
constexpr std::size_t kN = 6U;             ///< self-test matrices are kN x kN
constexpr std::size_t kCells = kN * kN;
constexpr std::size_t kBytes = 256U;       ///< self-test byte image
constexpr std::size_t kDigestWords = 2U * kCells + 2U;
}  // namespace

void self_test_pattern_fill(std::span<std::uint8_t> pattern) noexcept {
  std::uint32_t x = 0x5E1F7E57U;  // fixed: every tile holds the same pattern
  for (std::uint8_t& b : pattern) {
    x = x * 1664525U + 1013904223U;
    b = static_cast<std::uint8_t>(x >> 24U);
  }
}

std::uint32_t self_test_kernel(std::uint32_t seed, std::span<const std::uint8_t> pattern, bsp::Work& work) noexcept {
  std::array<double, kCells> a{};
  std::array<double, kCells> b{};
  std::array<double, kCells> c{};
  std::array<std::uint8_t, kBytes> img{};
  std::uint32_t x = seed | 1U;
  for (std::size_t i = 0; i < kCells; ++i) {
    x = x * 1664525U + 1013904223U;  // the seed's sequence: the same on every tile
    a[i] = static_cast<double>(x >> 8U) * 0x1p-24 - 0.5;
    x = x * 1664525U + 1013904223U;
    b[i] = static_cast<double>(x >> 8U) * 0x1p-24 - 0.5;
  }
  for (std::size_t i = 0; i < kBytes; ++i) {
    x = x * 1664525U + 1013904223U;
    img[i] = static_cast<std::uint8_t>(x >> 24U);
  }
  for (std::size_t i = 0; i < kN; ++i) {
    for (std::size_t j = 0; j < kN; ++j) {
      double acc = 0.0;
      for (std::size_t k = 0; k < kN; ++k) {
        acc += a[i * kN + k] * b[k * kN + j];
      }
      c[i * kN + j] = acc;
    }
  }
  std::uint32_t macs = 0U;
  for (std::size_t i = 0; i + 16U < kBytes; ++i) {
    macs += static_cast<std::uint32_t>(img[i]) * static_cast<std::uint32_t>(img[i + 16U]);
  }
  // Odd weights: a flipped bit of any pattern byte changes the sum (2^b times an odd number).
  std::uint32_t resident = 0U;
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    resident += static_cast<std::uint32_t>(pattern[i]) * (static_cast<std::uint32_t>(img[i % kBytes]) | 1U);
  }
  std::array<std::uint32_t, kDigestWords> words{};
  for (std::size_t i = 0; i < kCells; ++i) {
    const auto bits = std::bit_cast<std::uint64_t>(c[i]);
    words[2U * i] = static_cast<std::uint32_t>(bits);
    words[2U * i + 1U] = static_cast<std::uint32_t>(bits >> 32U);
  }
  words[kDigestWords - 2U] = macs;
  words[kDigestWords - 1U] = resident;
  work.flops += 2ULL * kN * kN * kN;
  work.int_macs += kBytes + pattern.size();
  work.int_ops += 4ULL * (2U * kN * kN + kBytes) + pattern.size();
  work.mem_words += 3ULL * kN * kN * 2U + kBytes / 4U + pattern.size() / 4U + words.size();
  return udn::crc32c_words(words);
}

}  // namespace fdir
