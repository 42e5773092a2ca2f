/**
 * @file supervisors.cpp
 * @brief The TRN supervisor tree's three tasks (see supervisors.hpp).
 */
#include "trn/tasks/supervisors/supervisors.hpp"
#include "trn/events.hpp"

#include "bsp_tile64/api/memory.hpp"
#include "fdir/event_log.hpp"
#include "fdir/tile_health.hpp"
#include "kernel/kernel.hpp"
#include "trn/tasks/messages.hpp"
#include "trn/tasks/settings_copy.hpp"
#include "udn/endpoint.hpp"

#include <bit>
#include <new>

namespace trn::tasks {
namespace {

constexpr auto kRel = static_cast<std::uint8_t>(fdir::Constraint::kReliability);
constexpr auto kPow = static_cast<std::uint8_t>(fdir::Constraint::kPower);
constexpr auto kCap = static_cast<std::uint8_t>(fdir::Constraint::kCapacity);

/** Messages taken per pass at most. */
constexpr std::uint32_t kDrainPerPass = 16U;
/** Ticks a message to another node may wait for the network. */
constexpr std::uint32_t kSendTicks = kControlSendTicks;

fdir::AlternativeList alts(std::uint8_t a, std::uint8_t b = 0U) noexcept {
  fdir::AlternativeList l{};
  l.alt[0] = a;
  l.count = 1U;
  if (b != 0U) {
    l.alt[1] = b;
    l.count = 2U;
  }
  return l;
}

fdir::SupervisorSpec make_trn() noexcept {
  fdir::SupervisorSpec s{};
  s.id = kNodeTrn;
  s.parent = fdir::kNoSupervisor;
  s.debounce = 2U;
  s.settle = 0U;
  s.plan[kRel][0] = alts(kAltDelegate);
  s.plan[kRel][1] = alts(kAltDelegate, kAltAcceptSimplex);
  s.plan[kPow][0] = alts(kAltDelegate);
  s.plan[kPow][1] = alts(kAltDelegate);
  // The vision supervisor's escalation at full rate: half the rate; at half rate, nothing left.
  s.plan[kCap][0] = alts(kAltHalfRate);
  return s;
}


fdir::SupervisorSpec make_filter() noexcept {
  fdir::SupervisorSpec s{};
  s.id = kNodeFilter;
  s.parent = kNodeTrn;
  s.debounce = 2U;
  s.settle = kFilterSettle;
  s.plan[kRel][0] = alts(kAltSimplex);
  s.plan[kRel][1] = alts(kAltTmr, kAltTmrReseed);
  s.plan[kPow][0] = alts(kAltReplicasOn);
  s.plan[kPow][1] = alts(kAltReplicasParked);
  return s;
}

fdir::SupervisorSpec make_vision() noexcept {
  fdir::SupervisorSpec s{};
  s.id = kNodeVision;
  s.parent = kNodeTrn;
  s.debounce = 2U;  // two frames in a row
  s.settle = 0U;    // the next frame's status already reflects a new rate
  s.plan[kCap][0] = alts(kAltFullRate);
  s.plan[kCap][1] = alts(kAltHalfRate);
  return s;
}

const std::array<fdir::SupervisorSpec, 3> kSpecs = {make_trn(), make_vision(), make_filter()};

/**
 * What an upset of a node's framework state does (bsp::ControlLayout): every
 * member is the tile's own (phases, levels, alternatives in use, debounce
 * counts); the stats pointer is host state.
 */
constexpr std::array kConstraintStateFields{
    BSP_CONTROL_STATE(fdir::ConstraintState, phase),       BSP_CONTROL_STATE(fdir::ConstraintState, level),
    BSP_CONTROL_STATE(fdir::ConstraintState, index),       BSP_CONTROL_STATE(fdir::ConstraintState, settle_left),
    BSP_CONTROL_STATE(fdir::ConstraintState, bad),         BSP_CONTROL_STATE(fdir::ConstraintState, good),
    BSP_CONTROL_STATE(fdir::ConstraintState, from),
};
constexpr bsp::ControlLayout kConstraintStateLayout{kConstraintStateFields, sizeof(fdir::ConstraintState),
                                                    alignof(fdir::ConstraintState)};
static_assert(bsp::control_layout_ok(kConstraintStateLayout), "every member of fdir::ConstraintState");
constexpr std::array kSupervisorStateFields{
    BSP_CONTROL_NESTED(fdir::SupervisorState, c, kConstraintStateLayout),
    BSP_CONTROL_STATE(fdir::SupervisorState, applied),
    BSP_CONTROL_STATE(fdir::SupervisorState, escalations),
};
constexpr bsp::ControlLayout kSupervisorStateLayout{kSupervisorStateFields, sizeof(fdir::SupervisorState),
                                                    alignof(fdir::SupervisorState)};
static_assert(bsp::control_layout_ok(kSupervisorStateLayout), "every member of fdir::SupervisorState");

/** A node's state, in the RAM of the tile it runs on (carve kSupNodeCarve); one node per tile. */
struct NodeState {
  fdir::SupervisorState sup;
  SupervisorStats* stats;  ///< the node's counters: its record in its tile's RAM (kSupervisorStatsRecord)
};
constexpr std::array kNodeStateFields{
    BSP_CONTROL_NESTED(NodeState, sup, kSupervisorStateLayout),
    BSP_CONTROL_HOST(NodeState, stats),
};
constexpr bsp::ControlLayout kNodeStateLayout{kNodeStateFields, sizeof(NodeState), alignof(NodeState)};
static_assert(bsp::control_layout_ok(kNodeStateLayout), "every member of NodeState, the pointer as host state");

/** Each node's state in its tile's RAM (host pointers: set when the node's task starts, by node id). */
std::array<NodeState*, 3> g_nodes{};

void send_words(bsp::TileId to, std::span<const std::uint32_t> w) noexcept {
  if (to != bsp::kNoTile) {
    (void)udn::endpoint_send(to, kChanControl, w, kSendTicks);  // a lost policy is sent again at the next refresh
  }
}

/** A policy (@p held: the one the parent holds for the child, sent again). */
void send_policy(bsp::TileId to, std::uint8_t constraint, std::uint8_t level, std::uint8_t from, bool held = false) noexcept {
  std::array<std::uint32_t, fdir::kSupMsgWords> w{};
  (void)fdir::msg::encode(held ? kPolicyHeldOnControl : kPolicyOnControl, fdir::SupMessage{constraint, level, from}, w);
  send_words(to, w);
}

void send_escalation(bsp::TileId to, const fdir::SupDecision& d, std::uint8_t node) noexcept {
  std::array<std::uint32_t, fdir::kSupMsgWords> w{};
  (void)fdir::msg::encode(kEscalateOnControl, fdir::SupMessage{d.constraint, d.level, node}, w);
  send_words(to, w);
}

/** What a node's handler reads besides the message: the tree's configuration and the sender. */
struct Inbox {
  const SupervisorsConfig& c;
  bsp::TileId source;
};

/** Takes a node's messages waiting on kChanControl (a few per pass), each by its tag in @p table. */
template <std::size_t N>
void drain(const std::array<fdir::msg::Handler<Inbox>, N>& table, const SupervisorsConfig& c) noexcept {
  udn::FtMessage m{};
  for (std::uint32_t i = 0; i < kDrainPerPass && udn::endpoint_receive(kChanControl, m) == udn::FtError::kOk; ++i) {
    Inbox in{c, m.source};
    (void)fdir::msg::dispatch(table, std::span<const std::uint32_t>(m.data.data(), m.data_words), in);
  }
}

bsp::TileId filter_sup(const SupervisorsConfig& c) noexcept {
  return udn::endpoint_role_tile(kSlotFilterSupervisor, c.filter_supervisor_tile);
}
bsp::TileId vision_sup(const SupervisorsConfig& c) noexcept {
  return udn::endpoint_role_tile(kSlotVisionSupervisor, c.vision_supervisor_tile);
}

/** The TRN supervisor's tile now (tile health, network health and the tree's top move together). */
bsp::TileId trn_tile_now(const SupervisorsConfig& c) noexcept {
  return udn::endpoint_role_tile(kSlotTrnSupervisor, c.trn_supervisor_tile);
}

/** The tile-health supervisor's tile now: it runs beside the TRN supervisor, and moves with it. */
bsp::TileId health_tile_now(const SupervisorsConfig& c) noexcept {
  return udn::endpoint_role_tile(kSlotTrnSupervisor, c.health_tile);
}

// ------------------------------------------------------------------ the TRN supervisor

/** The TRN supervisor's children, as indexes of the policies it holds for them. */
enum Child : std::uint8_t { kChildFilter = 0U, kChildVision = 1U, kChildren = 2U };

/** No policy handed down yet for a constraint. */
constexpr std::uint8_t kNoLevel = 0xFFU;


struct TrnState {
  std::uint32_t phase = 0xFFFF'FFFFU;  ///< index of the phase whose policies went down
  std::uint32_t woken_for = 0xFFFF'FFFFU;  ///< the phase whose replicas were asked for ahead of it
  std::array<std::uint8_t, fdir::kMaxConstraints> level{};  ///< the level each policy asks now
  /** Per child and constraint: the level last handed down (kNoLevel: none). */
  std::array<std::array<std::uint8_t, fdir::kMaxConstraints>, kChildren> down{};
  std::uint32_t refreshed = 0U;  ///< mission tick of the last refresh
};
/** The TRN supervisor's own state is emulated state through and through (bsp::ControlLayout). */
constexpr std::array kTrnStateFields{
    BSP_CONTROL_STATE(TrnState, phase), BSP_CONTROL_STATE(TrnState, woken_for), BSP_CONTROL_STATE(TrnState, level),
    BSP_CONTROL_STATE(TrnState, down),  BSP_CONTROL_STATE(TrnState, refreshed),
};
constexpr bsp::ControlLayout kTrnStateLayout{kTrnStateFields, sizeof(TrnState), alignof(TrnState)};
static_assert(bsp::control_layout_ok(kTrnStateLayout), "every member of TrnState");
/** In the TRN supervisor's tile's RAM (carve kSupTrnCarve), set at its task's start. */
TrnState* g_trn = nullptr;

/** Hands @p child the policy (@p constraint, @p level) and keeps it, to hand again at each refresh. */
void hand_down(const SupervisorsConfig& c, Child child, std::uint8_t constraint, std::uint8_t level) noexcept {
  g_trn->down[child][constraint] = level;
  send_policy(child == kChildFilter ? filter_sup(c) : vision_sup(c), constraint, level, kNodeTrn);
}

/** Every kPolicyRefreshTicks of mission tick @p now: the policies held for the children, again. */
void trn_refresh(const SupervisorsConfig& c, std::uint32_t now) noexcept {
  if (now - g_trn->refreshed < kPolicyRefreshTicks) {
    return;
  }
  g_trn->refreshed = now;
  for (std::uint8_t child = 0U; child < kChildren; ++child) {
    for (std::uint8_t k = 0U; k < fdir::kMaxConstraints; ++k) {
      if (g_trn->down[child][k] != kNoLevel) {
        send_policy(child == kChildFilter ? filter_sup(c) : vision_sup(c), k, g_trn->down[child][k], kNodeTrn, true);
      }
    }
  }
}

void trn_act(const SupervisorsConfig& c, const fdir::SupDecision& d) noexcept {
  NodeState& n = *g_nodes[kNodeTrn];
  if (d.action == fdir::SupAction::kEscalate) {
    ++n.stats->safe_mode;  // nobody above: the vehicle is told
    trn::report(ev::kSafeMode, d.constraint, 0U, d.level, 0U);
    return;
  }
  if (d.action != fdir::SupAction::kApply) {
    return;
  }
  ++n.stats->applied;
  switch (d.alternative) {
    case kAltDelegate:
      if (d.constraint == kRel || d.constraint == kPow) {
        hand_down(c, kChildFilter, d.constraint, d.level);
      }
      break;
    case kAltAcceptSimplex:
      hand_down(c, kChildFilter, kRel, fdir::kReliabilityNormal);
      break;
    case kAltHalfRate:
      hand_down(c, kChildVision, kCap, fdir::kCapacityHalfRate);
      break;
    default:
      break;
  }
}

void trn_policy(const SupervisorsConfig& c, std::uint8_t constraint, std::uint8_t level, std::uint32_t from) noexcept {
  if (constraint >= fdir::kMaxConstraints) {
    return;
  }
  g_trn->level[constraint] = level;
  if (from == fdir::kFromGround) {
    g_nodes[kNodeTrn]->sup.c[constraint] = fdir::ConstraintState{};  // a ground command is obeyed again, not debounced
  }
  ++g_nodes[kNodeTrn]->stats->policies;
  trn_act(c, fdir::supervisor_policy(kSpecs[kNodeTrn], g_nodes[kNodeTrn]->sup, constraint, level, from));
}

/** The phase of mission tick @p now: its policies go down when it begins. */
void trn_phase(const SupervisorsConfig& c, std::uint32_t now) noexcept {
  std::uint32_t p = 0U;
  for (std::uint32_t i = 1U; i < c.phase_count && i < kMaxPhases; ++i) {
    p = now >= c.phases[i].start_tick ? i : p;
  }
  if (c.phase_count == 0U || p == g_trn->phase) {
    return;
  }
  g_trn->phase = p;
  g_nodes[kNodeTrn]->stats->phase = p;
  g_trn->woken_for = 0xFFFF'FFFFU;
  const PhaseSpec& ph = c.phases[p];
  trn::report(ev::kPhaseBegin, p, 0U, ph.reliability, ph.power);
  trn_policy(c, kRel, ph.reliability, fdir::kFromPhase);
  trn_policy(c, kPow, ph.power, fdir::kFromPhase);
}

/**
 * Ahead of a phase that needs the replicas (reliability high) the power
 * policy goes to full, so that they are booted and idle when its reliability
 * comes: tiles are woken before they are needed, not when.
 */
void trn_wake_ahead(const SupervisorsConfig& c, std::uint32_t now) noexcept {
  const std::uint32_t next = g_trn->phase + 1U;
  if (g_trn->phase >= c.phase_count || next >= c.phase_count || next >= kMaxPhases || g_trn->woken_for == next) {
    return;
  }
  const PhaseSpec& n = c.phases[next];
  const PhaseSpec& cur = c.phases[g_trn->phase];
  const bool needs = n.reliability == fdir::kReliabilityHigh && cur.reliability != fdir::kReliabilityHigh &&
                     cur.power == fdir::kPowerSave;
  if (needs && now + c.wake_lead_ticks >= n.start_tick) {
    g_trn->woken_for = next;
    trn_policy(c, kPow, fdir::kPowerFull, fdir::kFromPhase);
  }
}

/** A ground policy through the I/O tile. */
void trn_take_policy(Inbox& in, const fdir::SupMessage& sm) noexcept { trn_policy(in.c, sm.constraint, sm.level, sm.from); }

void trn_take_escalation(Inbox& in, const fdir::SupMessage& sm) noexcept {
  trn_act(in.c, fdir::supervisor_escalation(kSpecs[kNodeTrn], g_nodes[kNodeTrn]->sup, sm.constraint, sm.level, sm.from));
}

/** The kinds the TRN supervisor takes on kChanControl; anything else there is dropped. */
constexpr std::array<fdir::msg::Handler<Inbox>, 2> kTrnHandlers{{
    fdir::msg::on<kPolicyOnControl, &trn_take_policy, Inbox>(),
    fdir::msg::on<kEscalateOnControl, &trn_take_escalation, Inbox>(),
}};
static_assert(fdir::msg::handlers_fit(kTrnHandlers, kChanControl, role_bit(Role::kTrnSupervisor)),
              "the TRN supervisor's handlers are kinds declared for it on kChanControl");

void trn_messages(const SupervisorsConfig& c) noexcept { drain(kTrnHandlers, c); }

// ------------------------------------------------------------------ the filter supervisor

struct FilterSupState {
  bool have_status = false;
  std::uint32_t mode = kFilterModeSimplex;  ///< the filter's mode at the last status
  bool power_save = false;         ///< the power policy is save: the replicas off while not needed
  bool tmr_after_wake = false;     ///< TMR is commanded once the replicas have booted
  std::uint32_t off = 0U;          ///< replicas switched off (bit per replica), as the tile-health supervisor answered
  std::array<std::uint32_t, 3> asked{};   ///< per replica: 0 nothing pending, 1 park asked, 2 wake asked
  std::array<k::Ticks, 3> asked_at{};
  std::uint32_t no_majority = 0U;  ///< the filter's counts at the last status
  std::uint32_t skipped = 0U;
  bool reseed_tmr = false;         ///< the reseed alternative waits for simplex to command TMR
};
/** The filter supervisor's own state is emulated state through and through (bsp::ControlLayout). */
constexpr std::array kFilterSupStateFields{
    BSP_CONTROL_STATE(FilterSupState, have_status),    BSP_CONTROL_STATE(FilterSupState, mode),
    BSP_CONTROL_STATE(FilterSupState, power_save),     BSP_CONTROL_STATE(FilterSupState, tmr_after_wake),
    BSP_CONTROL_STATE(FilterSupState, off),            BSP_CONTROL_STATE(FilterSupState, asked),
    BSP_CONTROL_STATE(FilterSupState, asked_at),       BSP_CONTROL_STATE(FilterSupState, no_majority),
    BSP_CONTROL_STATE(FilterSupState, skipped),        BSP_CONTROL_STATE(FilterSupState, reseed_tmr),
};
constexpr bsp::ControlLayout kFilterSupStateLayout{kFilterSupStateFields, sizeof(FilterSupState),
                                                   alignof(FilterSupState)};
static_assert(bsp::control_layout_ok(kFilterSupStateLayout), "every member of FilterSupState");
/** In the filter supervisor's tile's RAM (carve kSupFilterCarve), set at its task's start. */
FilterSupState* g_fsup = nullptr;

void command_filter(const SupervisorsConfig& c, std::uint32_t code) noexcept {
  std::array<std::uint32_t, kSupCommandWords> w{};
  (void)fdir::msg::encode(kSupCommandMsg, SupCommand{code, kNodeFilter}, w);
  send_words(udn::endpoint_role_tile(kSlotIo, c.io_tile), w);
  ++g_nodes[kNodeFilter]->stats->commands;
}

/** @p commanded: the filter was already commanded (a ground command the I/O tile forwarded itself). */
void filter_act(const SupervisorsConfig& c, const fdir::SupDecision& d, bool commanded = false) noexcept {
  NodeState& n = *g_nodes[kNodeFilter];
  if (d.action == fdir::SupAction::kEscalate) {
    ++n.stats->escalations;
    send_escalation(trn_tile_now(c), d, kNodeFilter);
    return;
  }
  if (d.action != fdir::SupAction::kApply) {
    return;
  }
  ++n.stats->applied;
  if (d.alternative == kAltReplicasOn || d.alternative == kAltReplicasParked) {
    g_fsup->power_save = d.alternative == kAltReplicasParked;
    return;  // replica_power() asks for the switching
  }
  g_fsup->reseed_tmr = false;
  g_fsup->tmr_after_wake = false;
  if (commanded) {
    return;
  }
  if (d.alternative == kAltSimplex) {
    command_filter(c, kCmdFilterSimplex);
  } else if (d.alternative == kAltTmr && g_fsup->off != 0U) {
    g_fsup->tmr_after_wake = true;  // parked replicas: woken first (replica_power), TMR once they booted
  } else if (d.alternative == kAltTmr) {
    command_filter(c, kCmdFilterTmr);
  } else if (d.alternative == kAltTmrReseed) {
    command_filter(c, kCmdFilterSimplex);  // a fresh seed: back to one filter, then TMR from its state
    g_fsup->reseed_tmr = true;
  }
}

/** Judges the reliability level from one status of the filter. */
void filter_status(const SupervisorsConfig& c, const FilterStatus& st) noexcept {
  NodeState& n = *g_nodes[kNodeFilter];
  ++n.stats->statuses;
  const std::uint32_t mode = st.mode;
  const auto voting = static_cast<std::uint32_t>(std::popcount(st.voting));
  const bool fresh_faults = g_fsup->have_status && (st.no_majority != g_fsup->no_majority || st.skipped != g_fsup->skipped);
  g_fsup->have_status = true;
  g_fsup->mode = mode;
  g_fsup->no_majority = st.no_majority;
  g_fsup->skipped = st.skipped;
  if (g_fsup->reseed_tmr && mode == kFilterModeSimplex) {
    g_fsup->reseed_tmr = false;
    command_filter(c, kCmdFilterTmr);
  }
  const fdir::ConstraintState& rel = n.sup.c[kRel];
  const bool met = rel.level == fdir::kReliabilityHigh ? (mode == kFilterModeTmr && voting >= 2U && !fresh_faults)
                                                       : mode == kFilterModeSimplex;
  filter_act(c, fdir::supervisor_judge(kSpecs[kNodeFilter], n.sup, kRel, met));
}

/** Ticks an unanswered park or wake request waits before it is sent again. */
constexpr k::Ticks kParkRetryTicks = 200U;

/**
 * The replicas are needed unless the power policy is save, reliability
 * normal and the filter simplex: then they are switched off, and on again as
 * soon as any of that changes. TMR waits for them to boot.
 */
void replica_power(const SupervisorsConfig& c) noexcept {
  const fdir::ConstraintState& rel = g_nodes[kNodeFilter]->sup.c[kRel];
  const bool park = g_fsup->power_save && rel.level == fdir::kReliabilityNormal && rel.phase == fdir::ConstraintPhase::kMet &&
                    g_fsup->mode == kFilterModeSimplex && !g_fsup->tmr_after_wake;
  const k::Ticks now = k::now_ticks();
  for (std::uint32_t i = 0; i < 3U; ++i) {
    const bool off = ((g_fsup->off >> i) & 1U) != 0U;
    const std::uint32_t want = park && !off ? 1U : (!park && off ? 2U : 0U);
    if (want == 0U || (g_fsup->asked[i] == want && now - g_fsup->asked_at[i] < kParkRetryTicks)) {
      continue;
    }
    const bsp::TileId t = udn::endpoint_role_tile(kSlotReplica0 + i, c.replica_tiles[i]);
    std::array<std::uint32_t, fdir::kParkWords> w{};
    (void)fdir::msg::encode(fdir::kParkMsg, fdir::ParkRequest{bsp::current_tile(), t, want == 1U, kChanControl}, w);
    if (t != bsp::kNoTile && udn::endpoint_send(health_tile_now(c), udn::kFtChanHealth, w, kSendTicks) == udn::FtError::kOk) {
      g_fsup->asked[i] = want;
      g_fsup->asked_at[i] = now;
    }
  }
  if (g_fsup->tmr_after_wake && g_fsup->off == 0U) {
    g_fsup->tmr_after_wake = false;
    command_filter(c, kCmdFilterTmr);
  }
  // Judged once the tile-health supervisor answered every request (a boot takes a few ticks): the
  // replicas are off when they are not needed, on when they are. Unanswered past the retry, not met.
  bool answered = true;
  for (std::uint32_t i = 0; i < 3U; ++i) {
    answered = answered && (g_fsup->asked[i] == 0U || now - g_fsup->asked_at[i] >= kParkRetryTicks);
  }
  if (answered) {
    const bool met = park ? g_fsup->off == 7U : g_fsup->off == 0U;
    filter_act(c, fdir::supervisor_judge(kSpecs[kNodeFilter], g_nodes[kNodeFilter]->sup, kPow, met));
  }
}

/** The tile-health supervisor's answer: a replica is off, or booted again. */
void filter_park_done(const SupervisorsConfig& c, const fdir::ParkDone& done) noexcept {
  for (std::uint32_t i = 0; i < 3U; ++i) {
    if (udn::endpoint_role_tile(kSlotReplica0 + i, c.replica_tiles[i]) != done.tile) {
      continue;
    }
    g_fsup->asked[i] = 0U;
    if (done.off) {
      g_fsup->off |= 1U << i;
      ++g_nodes[kNodeFilter]->stats->parks;
    } else if ((g_fsup->off & (1U << i)) != 0U) {
      g_fsup->off &= ~(1U << i);
      ++g_nodes[kNodeFilter]->stats->wakes;
    }
  }
}

void filter_take_status(Inbox& in, const FilterStatus& status) noexcept { filter_status(in.c, status); }

void filter_take_park_done(Inbox& in, const fdir::ParkDone& done) noexcept {
  if (in.source == health_tile_now(in.c)) {
    filter_park_done(in.c, done);
  }
}

void filter_take_policy(Inbox& in, const fdir::SupMessage& sm) noexcept {
  ++g_nodes[kNodeFilter]->stats->policies;
  // A ground filter_tmr / filter_simplex reached the filter straight from the I/O tile: the
  // supervisor takes its mode as the policy (until the TRN supervisor sends another) and sends nothing.
  const bool ground = sm.from == fdir::kFromGround;
  if (ground) {
    g_nodes[kNodeFilter]->sup.c[sm.constraint] = fdir::ConstraintState{};
  }
  filter_act(in.c, fdir::supervisor_policy(kSpecs[kNodeFilter], g_nodes[kNodeFilter]->sup, sm.constraint, sm.level, sm.from),
             ground);
}

/** The policy the parent holds, sent again: taken while the node holds none or only its default. */
void filter_take_held(Inbox& in, const fdir::SupMessage& sm) noexcept {
  if (fdir::supervisor_takes_held(g_nodes[kNodeFilter]->sup, sm.constraint)) {
    filter_take_policy(in, sm);
  }
}

/** The kinds the filter supervisor takes on kChanControl; anything else there is dropped. */
constexpr std::array<fdir::msg::Handler<Inbox>, 4> kFilterHandlers{{
    fdir::msg::on<kFilterStatusMsg, &filter_take_status, Inbox>(),
    fdir::msg::on<kParkDoneOnControl, &filter_take_park_done, Inbox>(),
    fdir::msg::on<kPolicyOnControl, &filter_take_policy, Inbox>(),
    fdir::msg::on<kPolicyHeldOnControl, &filter_take_held, Inbox>(),
}};
static_assert(fdir::msg::handlers_fit(kFilterHandlers, kChanControl, role_bit(Role::kFilterSupervisor)),
              "the filter supervisor's handlers are kinds declared for it on kChanControl");

void filter_messages(const SupervisorsConfig& c) noexcept {
  drain(kFilterHandlers, c);
  replica_power(c);
}

// ------------------------------------------------------------------ the vision supervisor

void send_rate(const SupervisorsConfig& c, std::uint32_t div) noexcept {
  const std::array<std::uint32_t, kVisionRateWords> w{kMsgVisionRate, div};
  send_words(udn::endpoint_role_tile(kSlotCoordinator, c.coordinator_tile), w);
  g_nodes[kNodeVision]->stats->rate_div = div;
}

void vision_act(const SupervisorsConfig& c, const fdir::SupDecision& d) noexcept {
  NodeState& n = *g_nodes[kNodeVision];
  if (d.action == fdir::SupAction::kEscalate) {
    ++n.stats->escalations;
    send_escalation(trn_tile_now(c), d, kNodeVision);
    return;
  }
  if (d.action != fdir::SupAction::kApply) {
    return;
  }
  ++n.stats->applied;
  send_rate(c, d.alternative == kAltHalfRate ? 2U : 1U);
}

void vision_status(const SupervisorsConfig& c, const VisionStatus& st) noexcept {
  NodeState& n = *g_nodes[kNodeVision];
  ++n.stats->statuses;
  const fdir::ConstraintState& cap = n.sup.c[kCap];
  if (cap.phase == fdir::ConstraintPhase::kIdle) {
    // No policy from above yet: the full rate is the default demand.
    vision_act(c, fdir::supervisor_policy(kSpecs[kNodeVision], n.sup, kCap, fdir::kCapacityFull, fdir::kFromDefault));
  }
  if (st.rate_div != n.stats->rate_div) {
    send_rate(c, n.stats->rate_div);  // a restarted coordinator: the rate again
  }
  const std::uint32_t healthy = st.healthy;
  const std::uint32_t need = cap.level == fdir::kCapacityHalfRate ? c.vision_min_half : c.vision_min_full;
  vision_act(c, fdir::supervisor_judge(kSpecs[kNodeVision], n.sup, kCap, healthy >= need));
}

void vision_take_status(Inbox& in, const VisionStatus& status) noexcept { vision_status(in.c, status); }

/** A capacity policy (the node has no other constraint). */
void vision_take_policy(Inbox& in, const fdir::SupMessage& sm) noexcept {
  if (sm.constraint == kCap) {
    ++g_nodes[kNodeVision]->stats->policies;
    vision_act(in.c, fdir::supervisor_policy(kSpecs[kNodeVision], g_nodes[kNodeVision]->sup, kCap, sm.level, sm.from));
  }
}

/** The policy the parent holds, sent again: taken while the node holds none or only its default. */
void vision_take_held(Inbox& in, const fdir::SupMessage& sm) noexcept {
  if (fdir::supervisor_takes_held(g_nodes[kNodeVision]->sup, sm.constraint)) {
    vision_take_policy(in, sm);
  }
}

/** The kinds the vision supervisor takes on kChanControl; anything else there is dropped. */
constexpr std::array<fdir::msg::Handler<Inbox>, 3> kVisionHandlers{{
    fdir::msg::on<kVisionStatusMsg, &vision_take_status, Inbox>(),
    fdir::msg::on<kPolicyOnControl, &vision_take_policy, Inbox>(),
    fdir::msg::on<kPolicyHeldOnControl, &vision_take_held, Inbox>(),
}};
static_assert(fdir::msg::handlers_fit(kVisionHandlers, kChanControl, role_bit(Role::kVisionSupervisor)),
              "the vision supervisor's handlers are kinds declared for it on kChanControl");

void vision_messages(const SupervisorsConfig& c) noexcept { drain(kVisionHandlers, c); }

/** @p T value-initialised in the running tile's RAM (a control carve named @p what, laid out by @p l); nullptr if short. */
template <class T>
T* carve_own(const char* what, const bsp::ControlLayout& l) noexcept {
  bsp::MemError err = bsp::MemError::kOk;
  return bsp::carve_record(bsp::Region{bsp::current_tile()}, bsp::RamRecord<T>{what, &l}, &err);
}

/**
 * A node's counters' record and its state, afresh in its tile's RAM (a
 * restart starts from the parent's next policy). @return false if the RAM is short.
 */
bool carve_node(std::uint8_t node) noexcept {
  g_nodes[node] = nullptr;
  bsp::MemError err = bsp::MemError::kOk;
  SupervisorStats* const stats = bsp::carve_record(bsp::Region{bsp::current_tile()}, kSupervisorStatsRecord, &err);
  NodeState* const n = stats != nullptr ? carve_own<NodeState>(kSupNodeCarve, kNodeStateLayout) : nullptr;
  if (n == nullptr) {
    return false;
  }
  n->stats = stats;
  g_nodes[node] = n;
  return true;
}

/**
 * The node's settings in RAM against their seal, before each pass: changed, built again from the
 * image (@p image) and reported (tile_settings_bad, about node @p node).
 */
void check_settings(SettingsCopy<SupervisorsConfig>& set, const SupervisorsConfig& image, std::uint8_t node) noexcept {
  bsp::Work work{};
  if (!settings_intact(set, work)) {
    settings_seal(set, image, work);
    trn::report(ev::kTileSettingsBad, node, ev::kSettingsOfSupervisor, ev::kSettingsAtStart, 0U);
  }
  bsp::consume(work);
}

/**
 * A node's task once its state is carved (@p state_ok), then its loop. Each pass runs with the
 * settings in the tile's RAM (kSupSettingsCarve, carved last), checked before it.
 */
template <void (*Pass)(const SupervisorsConfig&)>
void node_main(void* arg, bool state_ok, std::uint8_t node) noexcept {
  const auto* cfg = static_cast<const SupervisorsConfig*>(arg);
  if (cfg == nullptr || !state_ok || !udn::endpoint_wait_ready(100U)) {
    return;
  }
  bsp::MemError err = bsp::MemError::kOk;
  auto* set = bsp::carve_array<SettingsCopy<SupervisorsConfig>>(bsp::Region{bsp::current_tile()}, 1,
                                                                 kSupSettingsCarve, &err);
  if (set == nullptr) {
    return;
  }
  bsp::Work work{};
  settings_seal(*set, *cfg, work);
  bsp::consume(work);
  for (;;) {
    check_settings(*set, *cfg, node);
    Pass(set->s);
    k::checkin();
    k::sleep(kSupPeriodTicks);
  }
}

void trn_pass(const SupervisorsConfig& c) noexcept {
  trn_messages(c);
  const auto now = static_cast<std::uint32_t>(bsp::now() / bsp::tick_cycles());  // mission time, not the tile's since its boot
  trn_phase(c, now);
  trn_wake_ahead(c, now);
  trn_refresh(c, now);
  // A delegated policy holds until a child escalates.
  for (std::uint8_t k = 0; k < fdir::kMaxConstraints; ++k) {
    trn_act(c, fdir::supervisor_judge(kSpecs[kNodeTrn], g_nodes[kNodeTrn]->sup, k, true));
  }
}

}  // namespace

void trn_supervisor_main(void* arg) noexcept {
  g_trn = carve_node(kNodeTrn) ? carve_own<TrnState>(kSupTrnCarve, kTrnStateLayout) : nullptr;
  if (g_trn != nullptr) {
    for (auto& child : g_trn->down) {
      child.fill(kNoLevel);
    }
  }
  node_main<&trn_pass>(arg, g_trn != nullptr, kNodeTrn);
}

void filter_supervisor_main(void* arg) noexcept {
  g_fsup = carve_node(kNodeFilter) ? carve_own<FilterSupState>(kSupFilterCarve, kFilterSupStateLayout) : nullptr;
  node_main<&filter_messages>(arg, g_fsup != nullptr, kNodeFilter);
}

void vision_supervisor_main(void* arg) noexcept { node_main<&vision_messages>(arg, carve_node(kNodeVision), kNodeVision); }

const bsp::ControlLayout& sup_node_state_layout() noexcept { return kNodeStateLayout; }
const bsp::ControlLayout& sup_trn_state_layout() noexcept { return kTrnStateLayout; }
const bsp::ControlLayout& sup_filter_state_layout() noexcept { return kFilterSupStateLayout; }

const fdir::SupervisorSpec& supervisor_spec(std::uint8_t node) noexcept {
  return kSpecs[node < kSpecs.size() ? node : 0U];
}

}  // namespace trn::tasks
