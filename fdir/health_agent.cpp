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
#include "fdir/tile_health.hpp"
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
  // The second opinion before a reset: the tiles beside the supervisor's asked whether they hear it.
  bool asking = false;         ///< questions out, answers awaited
  k::Ticks asked_at = 0U;
  std::uint32_t asked = 0U;    ///< witnesses asked (or this tile itself, if beside it)
  std::uint32_t unsent = 0U;   ///< witnesses whose question the network refused: sent again at the next pass
  std::uint32_t heard = 0U;    ///< of them, those whose probe hears the supervisor's tile
  std::uint32_t missed = 0U;   ///< those whose last ping to it went unanswered
  bool path_cut = false;       ///< supervisor_path_cut written this spell
  bool moved = false;          ///< its role was given to the standby (take_over): nothing more to do here
  std::uint32_t silent_ticks = 0U;  ///< how long it had been silent when the watcher reset it
  bsp::TileId subject = bsp::kNoTile;  ///< the supervisor's tile watched (a move starts the watch afresh)
};

/** Ticks the watcher waits for the witnesses' answers before it decides without them. */
constexpr std::uint32_t kWitnessWaitTicks = 20U;

/**
 * A self-test answer the network refused (back-pressure; sent without waiting): sent again at
 * the agent's next pass, until the next request replaces it. Lost, the round went late.
 */
struct OwedAnswer {
  std::array<std::uint32_t, kSelfTestResultWords> w{};
  bool owed = false;
  std::array<std::uint32_t, kHearAnswerWords> hear{};  ///< a witness's answer to the watcher, the same way
  bsp::TileId hear_to = bsp::kNoTile;                   ///< kNoTile: none owed
};

/** The watcher's tile now: where the directory has its role, or its configured tile. */
bsp::TileId watcher_now(const HealthAgentConfig& cfg) noexcept {
  return cfg.watcher_slot < udn::kRoleSlots ? udn::endpoint_role_tile(cfg.watcher_slot, cfg.watcher_tile) : cfg.watcher_tile;
}

/** The supervisor's tile now: where the directory has its role, or its configured tile. */
bsp::TileId supervisor_now(const HealthAgentConfig& cfg) noexcept {
  return cfg.supervisor_slot < udn::kRoleSlots ? udn::endpoint_role_tile(cfg.supervisor_slot, cfg.health_tile)
                                               : cfg.health_tile;
}

/** Sends @p a to the supervisor; it stays owed if the network refuses it. */
void send_answer(const HealthAgentConfig& cfg, OwedAnswer& a) noexcept {
  a.owed = udn::endpoint_send(supervisor_now(cfg), udn::kFtChanHealth, a.w, 0U) != udn::FtError::kOk;
}

/**
 * A heartbeat of the supervisor's tile: a reset the watcher commanded is
 * closed by it, and only now is the silence diagnosed: a reset ended it, so
 * the supervisor was hung (with its own watchdog failed), not cut off.
 */
void take_alive(Watch& w, const TileBootReport& alive, bsp::TileId supervisor, bsp::TileId self) noexcept {
  const k::Ticks now = k::now_ticks();
  if (w.pending) {
    const auto since_reset = static_cast<std::uint32_t>(now >= w.reset_at ? now - w.reset_at : 0U);
    report(EventId::kSupervisorSilent, supervisor, self, w.silent_ticks + since_reset, w.resets);
    report(EventId::kTileRecovered, supervisor, static_cast<std::uint32_t>(alive.cause), since_reset);
  }
  w.pending = false;
  w.silent = false;
  w.cut_off = false;
  w.asking = false;
  w.path_cut = false;
  w.last_alive = now;
}

/** Counts one witness's word on the supervisor's tile (while the watcher asks). */
void count_hearing(Watch& w, udn::Heard h) noexcept {
  if (!w.asking) {
    return;
  }
  w.heard += h == udn::Heard::kAnswers ? 1U : 0U;
  w.missed += h == udn::Heard::kSilent ? 1U : 0U;
}

/** The tiles beside @p sup on the grid (kNoTile off its edge), north, east, south, west. */
std::array<bsp::TileId, 4> beside(bsp::TileId sup) noexcept {
  const std::uint32_t cols = bsp::udn_grid_cols();
  const std::uint32_t rows = bsp::udn_grid_rows();
  if (cols == 0U || rows == 0U || sup >= cols * rows) {
    return {bsp::kNoTile, bsp::kNoTile, bsp::kNoTile, bsp::kNoTile};
  }
  const std::uint32_t x = sup % cols;
  const std::uint32_t y = sup / cols;
  return {y > 0U ? sup - cols : bsp::kNoTile, x + 1U < cols ? sup + 1U : bsp::kNoTile,
          y + 1U < rows ? sup + cols : bsp::kNoTile, x > 0U ? sup - 1U : bsp::kNoTile};
}

/** Sends the question to the witnesses still unsent (bit per direction); refused ones stay. */
void send_questions(Watch& w, bsp::TileId sup, bsp::TileId self) noexcept {
  std::array<std::uint32_t, kHearQueryWords> q{};
  (void)msg::encode(kHearQueryMsg, HearQuery{self, sup}, q);
  const std::array<bsp::TileId, 4> n = beside(sup);
  for (std::size_t d = 0; d < n.size(); ++d) {
    if (((w.unsent >> d) & 1U) != 0U && udn::endpoint_send(n[d], udn::kFtChanHealth, q, 0U) == udn::FtError::kOk) {
      w.unsent &= ~(1U << d);
    }
  }
}

/**
 * Asks the tiles beside the supervisor's that run a role (the role directory
 * names them; spares run no agent) whether their neighbour probe hears it; a
 * watcher beside it answers itself. @return how many are asked.
 */
std::uint32_t ask_witnesses(Watch& w, bsp::TileId sup, bsp::TileId self) noexcept {
  w.asking = true;
  w.asked = 0U;
  w.unsent = 0U;
  w.heard = 0U;
  w.missed = 0U;
  w.asked_at = k::now_ticks();
  const std::array<bsp::TileId, 4> n = beside(sup);
  const udn::RoleDirectory dir = udn::endpoint_roles();
  const std::uint64_t failed = udn::endpoint_fault_map().failed_tiles;
  for (std::size_t d = 0; d < n.size(); ++d) {
    if (n[d] >= bsp::kMaxTiles || ((failed >> n[d]) & 1ULL) != 0ULL) {
      continue;
    }
    if (n[d] == self) {
      ++w.asked;
      count_hearing(w, udn::endpoint_hears(sup));
      continue;
    }
    bool runs_role = false;
    for (const bsp::TileId t : dir.tile) {
      runs_role = runs_role || t == n[d];
    }
    if (runs_role) {
      ++w.asked;
      w.unsent |= 1U << d;
    }
  }
  send_questions(w, sup, self);
  return w.asked;
}

/** Sends a witness's answer owed; refused, it stays owed for the next pass (the watcher waits a while). */
void send_hearing(OwedAnswer& a) noexcept {
  if (a.hear_to != bsp::kNoTile && udn::endpoint_send(a.hear_to, udn::kFtChanHealth, a.hear, 0U) == udn::FtError::kOk) {
    a.hear_to = bsp::kNoTile;
  }
}

/** A witness's question answered from this tile's probe. */
void answer_witness(bsp::TileId self, const HearQuery& q, OwedAnswer& a) noexcept {
  (void)msg::encode(kHearAnswerMsg, HearAnswer{self, q.subject, udn::endpoint_hears(q.subject)}, a.hear);
  a.hear_to = q.asker;
  send_hearing(a);
}

/** What an agent's handler reads besides the message: its tile, its table, the supervisor's tile, the sender. */
struct AgentInbox {
  bsp::TileId self;
  const HealthAgentConfig& cfg;
  bsp::TileId sup;
  Watch& watch;
  OwedAnswer& answer;
  bsp::TileId source;
};

void take_hear_query(AgentInbox& in, const HearQuery& q) noexcept {
  if (q.asker == in.source) {
    answer_witness(in.self, q, in.answer);
  }
}

void take_hear_answer(AgentInbox& in, const HearAnswer& heard) noexcept {
  if (heard.tile == in.source && heard.subject == in.sup) {
    count_hearing(in.watch, heard.hearing);
  }
}

void take_alive_of(AgentInbox& in, const TileBootReport& alive) noexcept {
  if (in.source == in.sup && watcher_now(in.cfg) == in.self) {
    take_alive(in.watch, alive, in.sup, in.self);
  }
}

void take_self_test(AgentInbox& in, const SelfTestRequest& req) noexcept {
  std::uint32_t digest = 0U;
  if (in.source != in.sup || !self_test_digest(in.self, req.seed, digest)) {
    return;
  }
  (void)msg::encode(kSelfTestResultMsg, SelfTestResult{in.self, req.round, digest}, in.answer.w);
  send_answer(in.cfg, in.answer);  // refused, it is sent again at the next pass
}

/** The kinds an agent takes on the health channel; anything else there is dropped. */
constexpr std::array<msg::Handler<AgentInbox>, 4> kAgentHandlers{{
    msg::on<kHearQueryMsg, &take_hear_query, AgentInbox>(),
    msg::on<kHearAnswerMsg, &take_hear_answer, AgentInbox>(),
    msg::on<kAliveMsg, &take_alive_of, AgentInbox>(),
    msg::on<kSelfTestMsg, &take_self_test, AgentInbox>(),
}};

/**
 * Takes the messages waiting on the health channel (a few per pass): the
 * supervisor's self-test requests, answered, the watcher's questions to a
 * witness and their answers, and, on the watcher's tile, the supervisor
 * tile's heartbeats.
 */
void take_agent_messages(bsp::TileId self, const HealthAgentConfig& cfg, bsp::TileId sup, Watch& watch,
                         OwedAnswer& answer) noexcept {
  if (answer.owed) {
    send_answer(cfg, answer);
  }
  send_hearing(answer);
  udn::FtMessage m{};
  for (std::uint32_t i = 0; i < 2U && udn::endpoint_receive(udn::kFtChanHealth, m) == udn::FtError::kOk; ++i) {
    AgentInbox in{self, cfg, sup, watch, answer, m.source};
    (void)msg::dispatch(kAgentHandlers, std::span<const std::uint32_t>(m.data.data(), m.data_words), in);
  }
}

/**
 * The supervisor's tile stayed silent after the watcher's reset, to the
 * watcher and to the tiles beside it: no hang (a reset ends one), its switch
 * or every link. It is switched off for good and the standby switched on to
 * run the supervisor's role (boot_slot), which announces its move itself.
 */
void take_over(Watch& w, const HealthAgentConfig& cfg, bsp::TileId sup, bsp::TileId self, std::uint32_t since) noexcept {
  w.moved = true;
  const bsp::TileId standby = cfg.standby;
  const bool usable = standby < bsp::kMaxTiles && standby != sup && boot_slot(standby) == kNoSlot &&
                      ((udn::endpoint_fault_map().failed_tiles >> standby) & 1ULL) == 0ULL;
  if (!usable) {
    report(EventId::kNoSpare, cfg.supervisor_slot, sup);
    return;
  }
  (void)bsp::power_off(sup);
  if (!boot_slot_assign(standby, cfg.supervisor_slot) || bsp::power_on(standby) != bsp::BoardError::kOk) {
    report(EventId::kNoSpare, cfg.supervisor_slot, sup);
    return;
  }
  report(EventId::kSupervisorMoved, sup, self, standby, since);
}

/** Silent to the watcher and to the tiles beside it: a suspicion, and a reset under the cap to tell. */
void reset_supervisor(Watch& w, const HealthAgentConfig& cfg, bsp::TileId sup, bsp::TileId self,
                      std::uint32_t since) noexcept {
  w.silent = true;
  w.silent_ticks = since;
  report(EventId::kSupervisorUnheard, sup, self, since, w.resets);
  if (w.resets >= cfg.max_watcher_resets) {
    report(EventId::kActionCapped, sup, self, w.resets);
    return;
  }
  if (bsp::reset_tile(sup) != bsp::BoardError::kOk) {
    report(EventId::kTileLost, sup, self);
    return;
  }
  const k::Ticks now = k::now_ticks();
  ++w.resets;
  w.pending = true;
  w.reset_at = now;
  w.last_alive = now;  // its boot and first heartbeat get a whole timeout again
  report(EventId::kTileReset, sup, 1U, w.resets, cfg.max_watcher_resets);
}

/**
 * The watcher's check: a heartbeat missing past its timeout, to the tiles
 * beside the supervisor's too, is written once as a suspicion and the tile
 * reset, under the cap; the next heartbeat names the hang and closes the
 * recovery (take_alive). Still silent a whole timeout after that
 * reset, to the tiles beside it too, its role goes to the standby (take_over).
 */
void watch_supervisor(Watch& w, const HealthAgentConfig& cfg, bsp::TileId sup, bsp::TileId self) noexcept {
  const k::Ticks now = k::now_ticks();
  const k::Ticks since = now >= w.last_alive ? now - w.last_alive : 0U;
  const bool may_move = w.pending && cfg.standby < bsp::kMaxTiles;
  if (since <= cfg.watcher_timeout_ticks || w.moved || (w.silent && !may_move)) {
    return;
  }
  // A watcher that hears nobody (its own switch failed) misses the heartbeat for its own reason:
  // resetting a healthy supervisor would wipe the network-health votes that are to name this very
  // switch. It waits; once it hears its neighbours again the timeout runs afresh.
  if (udn::endpoint_cut_off(sup)) {
    if (!w.cut_off) {
      report(EventId::kWatcherCutOff, sup, self, static_cast<std::uint32_t>(since));
    }
    w.cut_off = true;
    w.last_alive = now;
    return;
  }
  w.cut_off = false;
  // A second opinion first: the tiles beside the supervisor's ping it. If they hear it and none
  // misses it, its core runs and its switch routes: only the way to this watcher is cut, and a
  // reset would wipe a healthy supervisor's state. Silent to one of them, or no answer, it is reset.
  if (!w.asking && ask_witnesses(w, sup, self) > 0U) {
    return;
  }
  send_questions(w, sup, self);
  const bool answered = w.heard + w.missed >= w.asked;
  if (w.asking && !answered && now - w.asked_at < kWitnessWaitTicks) {
    return;
  }
  w.asking = false;
  if (w.heard > 0U && w.missed == 0U) {
    if (!w.path_cut) {
      report(EventId::kSupervisorPathCut, sup, self, static_cast<std::uint32_t>(since), w.heard);
    }
    w.path_cut = true;
    w.last_alive = now;  // asked again after another whole timeout
    return;
  }
  if (may_move) {
    take_over(w, cfg, sup, self, static_cast<std::uint32_t>(now - w.reset_at));
    return;
  }
  // Silent to the tiles beside it too: hung with its own watchdog failed, or its switch failed.
  // Only the reset tells them apart (a heartbeat after it, or silence a whole timeout longer).
  reset_supervisor(w, cfg, sup, self, static_cast<std::uint32_t>(since));
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

/**
 * Kicks the tile's watchdog while every watched task is within budget, and sends the heartbeat
 * to @p alive_to (kNoTile: none); a task past its budget is written once and the kicks stop.
 */
void kick(bsp::TileId self, bool& overdue_written, bsp::TileId alive_to,
          std::span<const std::uint32_t, kAliveWords> alive) noexcept {
  const Overdue o = find_overdue(self, k::now_ticks());
  // A failed flight check asked for the tile's recovery: no more kicks, the watchdog restarts it.
  if (o.task == k::kNoTask && recovery_requested(self) == 0U) {
    bsp::watchdog_kick();
    overdue_written = false;
    // The remote kick: the watcher hears it only while the supervisor's tasks are within budget.
    if (alive_to != bsp::kNoTile && udn::endpoint_ready()) {
      (void)udn::endpoint_send(alive_to, udn::kFtChanHealth, alive, 0U);  // a lost one is a late one
    }
  } else if (o.task != k::kNoTask && !overdue_written) {
    report(EventId::kTaskOverdue, o.task, self, o.late, o.budget);
    overdue_written = true;
  }
}

}  // namespace

void health_agent_main(void* arg) noexcept {
  const auto* cfg = static_cast<const HealthAgentConfig*>(arg);
  const bsp::TileId self = bsp::current_tile();
  if (cfg == nullptr || self >= bsp::kMaxTiles || cfg->watchdog_ticks < 2U * kAgentPeriodTicks) {
    return;  // no kicks: the hardware watchdog is never armed, the neighbours' probes still see the tile
  }
  const bsp::BootCause cause = bsp::boot_cause();
  // The supervisor's own tile has nobody above it: its watchdog resets it. A standby switched on
  // to take the supervisor's role (its boot slot) is it from its boot, before the directory says so.
  const bool standby = cfg->supervisor_slot < udn::kRoleSlots && boot_slot(self) == cfg->supervisor_slot;
  bool own_supervisor = standby || supervisor_now(*cfg) == self;
  const bsp::Cycles watchdog = static_cast<bsp::Cycles>(cfg->watchdog_ticks) * bsp::tick_cycles();
  bsp::watchdog_arm(watchdog, own_supervisor);
  bool reported = cfg->health_tile == bsp::kNoTile || own_supervisor;
  bool overdue_written = false;
  std::array<std::uint32_t, kBootedWords> boot{};
  std::array<std::uint32_t, kAliveWords> alive{};
  (void)msg::encode(kBootedMsg, TileBootReport{self, cause}, boot);
  (void)msg::encode(kAliveMsg, TileBootReport{self, cause}, alive);
  bool watches = false;
  Watch watch{};  // started afresh at the first pass that watches
  OwedAnswer answer{};
  pattern_init(self);
  recovery_clear(self);  // a request from before this boot was the one the restart answered
  bool caught_up = false;
  for (;;) {
    if (!caught_up && udn::endpoint_ready()) {
      ledger_roles_apply();  // the moves made before this boot, the supervisor's own among them
      caught_up = true;
    }
    // The supervisor and its watcher follow their roles through the directory.
    const bsp::TileId sup = standby ? self : supervisor_now(*cfg);
    if ((sup == self) != own_supervisor) {
      own_supervisor = sup == self;
      bsp::watchdog_arm(watchdog, own_supervisor);  // the role came here, or left: reset on expiry with it
    }
    const bsp::TileId watcher = watcher_now(*cfg);
    const bool sends_alive = own_supervisor && watcher < bsp::kMaxTiles && watcher != self;
    // A tile that becomes the watcher, or whose supervisor moved, starts its watch with a whole timeout.
    const bool watches_now = sup < bsp::kMaxTiles && !own_supervisor && watcher == self;
    if (watches_now && (!watches || watch.subject != sup)) {
      watch = Watch{};
      watch.last_alive = k::now_ticks();
      watch.subject = sup;
    }
    watches = watches_now;
    kick(self, overdue_written, sends_alive ? watcher : bsp::kNoTile, alive);
    // Staggered by tile: 40 tiles booting together would overrun the supervisor's queue.
    if (!reported && udn::endpoint_ready() && k::now_ticks() >= self / kReportsPerTick) {
      reported = udn::endpoint_send(sup, udn::kFtChanHealth, boot, 0U) == udn::FtError::kOk;
    }
    if (!own_supervisor && sup != bsp::kNoTile && udn::endpoint_ready()) {
      take_agent_messages(self, *cfg, sup, watch, answer);
    }
    if (watches) {
      watch_supervisor(watch, *cfg, sup, self);
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
