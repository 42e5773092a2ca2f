/**
 * @file udn_stress_ft.cpp
 * @brief udn_stress --ft on: one fault-tolerant driver task per working tile, checked deliveries.
 *
 * Each working tile runs one task that owns its udn::FtNode: every tick it
 * polls the listener, drains and checks its receive channels, and sends its
 * share of the traffic (a credit of rate x tick per tick, deterministic) to
 * destinations drawn like the raw run's (udn_stress_plan.hpp: working tiles
 * only). Payloads are stamped and checked like the raw run's
 * (udn_stress_payload.hpp: corrupted, misdelivered); the order is checked per
 * (source, destination, channel) stream, the unit the layer keeps in order;
 * a message sent and never delivered counts as lost. Every give-up the layer
 * reports (its event sink) is checked against what the receivers really got
 * once the run is over: a give-up of a message that arrived is a false alarm.
 */
#include "tools/common/udn_stress/udn_stress.hpp"

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/rng.hpp"
#include "kernel/kernel.hpp"
#include "tools/common/udn_stress/udn_stress_payload.hpp"
#include "tools/common/udn_stress/udn_stress_plan.hpp"
#include "udn/ft_link.hpp"
#include "udn/raw.hpp"
#include "udn/route.hpp"

#include <array>
#include <memory>
#include <vector>

namespace tools {
namespace {

constexpr std::uint32_t kStackBytes = 16U * 1024U;
constexpr std::uint32_t kChannels = udn::kFtChannels;
/** Recent messages of a stream whose sequence number and sender's number are kept (a give-up names one by its sequence). */
constexpr std::uint32_t kRecent = 32U;
/** Give-ups checked against the deliveries at the end of a run; more are counted unchecked. */
constexpr std::size_t kGiveUpRecords = 1U << 16U;

/** A give-up the layer reported: the message (its sender's number) and what the reports said of it last. */
struct GiveUpRecord {
  bsp::TileId source = 0U;
  udn::FtDelivery claim = udn::FtDelivery::kUnknown;  ///< the give-up's, or the settling event's after it
  std::uint32_t number = 0U;                           ///< the sender's message number
};

/** A message the layer took: the sequence number it got and its sender's number. */
struct SentMessage {
  std::uint32_t number = 0U;
  std::uint8_t seq = 0U;
};

template <typename T>
using PerStream = std::array<std::array<std::array<T, kChannels>, bsp::kMaxTiles>, bsp::kMaxTiles>;

struct FtShared {
  StressOptions opts;
  detail::TrafficPlan plan;  ///< the working tiles send and are addressed
  udn::FaultMap map{};
  std::array<std::uint64_t, bsp::kMaxTiles> done{};  ///< messages sent or refused as unreachable
  std::array<bool, bsp::kMaxTiles> idle{};           ///< quota done and nothing unacknowledged
  PerStream<std::uint32_t> sent{};
  PerStream<std::array<SentMessage, kRecent>> recent{};  ///< stream message k at [k % kRecent]
  PerStream<std::uint32_t> after_last{};  ///< receiver: 1 + the sender's number of the last message delivered (0: none)
  std::uint64_t arrived = 0U;  ///< distinct messages delivered intact
  bool in_send = false;        ///< a driver is inside ft_send (a kUnreachable event then is a refused send)
  StressResult::Delivery delivery{};
  StressResult::Ft ft{};
};
FtShared g_ft;
std::array<udn::FtNode, bsp::kMaxTiles> g_ft_nodes{};
/** Per source, per message number: delivered (sized before the run, so the run allocates nothing). */
std::array<std::vector<std::uint8_t>, bsp::kMaxTiles> g_arrived;
std::vector<GiveUpRecord> g_give_ups;

/**
 * The sender's number of the latest message of stream (source, dest, ch) that
 * got sequence number @p seq: a sequence number that left the tile is never
 * given to another message, and the layer delivers or gives up only recent ones.
 * @return false if none of the recent ones has it.
 */
bool recent_number(bsp::TileId source, bsp::TileId dest, std::uint32_t ch, std::uint8_t seq, std::uint64_t& number) {
  const std::uint32_t c = g_ft.sent[source][dest][ch];
  const auto& recent = g_ft.recent[source][dest][ch];
  for (std::uint32_t back = 1U; back <= kRecent && back <= c; ++back) {
    const SentMessage& m = recent[(c - back) % kRecent];
    if (m.seq == seq) {
      number = m.number;
      return true;
    }
  }
  return false;
}

/**
 * A delivered message, known by its stamp (the sender's number modulo 2^16,
 * the latest such number the sender used; a one-word payload has none, its
 * sequence number says): twice is a duplicate, before the last of its stream
 * misordered; a gap is what the layer gave up.
 */
void take_delivered(bsp::TileId source, bsp::TileId self, std::uint32_t ch, std::uint8_t seq,
                    const PayloadStamp& st) {
  const std::uint64_t used = g_ft.done[source];  // the sender's numbers so far: 0 .. used - 1
  std::uint64_t number = (used - 1U) - ((used - 1U - st.number) & 0xFFFFU);
  if (used == 0U || (g_ft.opts.words < 2U && !recent_number(source, self, ch, seq, number))) {
    ++g_ft.ft.unmatched;  // cannot be told: counted as not arrived
    return;
  }
  std::uint32_t& after_last = g_ft.after_last[source][self][ch];
  if (number >= g_arrived[source].size() || g_arrived[source][number] != 0U) {
    ++g_ft.delivery.duplicated;
    return;
  }
  g_ft.delivery.misordered += number + 1U < after_last ? 1U : 0U;
  after_last = static_cast<std::uint32_t>(number + 1U);
  g_arrived[source][number] = 1U;
  ++g_ft.arrived;
}

/**
 * Records what the layer reported on @p tile (its sink) of a message it gave
 * up: the give-up, then maybe its settling; checked against deliveries at the end.
 */
void on_ft_event(void* /*ctx*/, bsp::TileId tile, const udn::FtEvent& e) {
  const bool refused = e.cause == udn::FtCause::kUnreachable && g_ft.in_send;  // nothing was sent
  const bool gave_up = (e.cause == udn::FtCause::kRetriesExhausted || e.cause == udn::FtCause::kUnreachable) && !refused;
  const bool settled = e.cause == udn::FtCause::kSettled;
  if ((!gave_up && !settled) || tile >= bsp::kMaxTiles || e.peer >= bsp::kMaxTiles || e.channel >= kChannels) {
    return;
  }
  std::uint64_t number = 0U;
  if (!recent_number(tile, e.peer, e.channel, e.seq, number)) {
    ++g_ft.ft.unmatched;
    return;
  }
  const auto claim = static_cast<udn::FtDelivery>(e.word);
  if (gave_up && g_give_ups.size() < g_give_ups.capacity()) {
    g_give_ups.push_back(GiveUpRecord{tile, claim, static_cast<std::uint32_t>(number)});
    return;
  }
  for (std::size_t i = g_give_ups.size(); settled && i > 0U; --i) {
    GiveUpRecord& g = g_give_ups[i - 1U];
    if (g.source == tile && g.number == number) {
      g.claim = claim;
      return;
    }
  }
  ++g_ft.ft.unmatched;  // a settling of no give-up seen, or no room left
}

void check_received(bsp::TileId self) {
  udn::FtMessage m{};
  for (std::uint32_t ch = 0; ch < kChannels; ++ch) {
    while (udn::ft_receive(g_ft_nodes[self], ch, m) == udn::FtError::kOk) {
      const std::size_t n = m.data_words < m.data.size() ? m.data_words : m.data.size();
      PayloadStamp st{};
      const PayloadVerdict v =
          check_payload(std::span(m.data.data(), n), m.data_words, g_ft.opts.words, m.source, self, st);
      g_ft.delivery.corrupted_delivered += v == PayloadVerdict::kCorrupted ? 1U : 0U;
      g_ft.delivery.misdelivered += v == PayloadVerdict::kMisdelivered ? 1U : 0U;
      ++g_ft.delivery.delivered;
      if (v == PayloadVerdict::kIntact && m.source < bsp::kMaxTiles) {
        take_delivered(m.source, self, ch, m.seq, st);
      }
    }
  }
}

/** A driver's sending state: its traffic stream, the credit of messages due and the next message's destination. */
struct Source {
  bsp::Rng rng;
  double credit = 0.0;
  bsp::TileId dest = bsp::kNoTile;  ///< drawn, not yet accepted (kNoTile: draw the next)
};

/** Sends while credit and quota last; stops at the first refusal (the same message is retried next tick). */
void send_some(bsp::TileId self, Source& src, std::array<std::uint32_t, udn::kFtMaxData>& data) {
  udn::FtNode& node = g_ft_nodes[self];
  bsp::TileId& dest = src.dest;
  while (src.credit >= 1.0 && g_ft.done[self] < g_ft.plan.quota[self]) {
    if (dest == bsp::kNoTile) {
      dest = detail::pick_destination(g_ft.plan, src.rng, self);
    }
    const auto ch = static_cast<std::uint32_t>(g_ft.done[self] % kChannels);
    const std::span<std::uint32_t> payload(data.data(), g_ft.opts.words);
    stamp_payload(PayloadStamp{self, dest, static_cast<std::uint16_t>(g_ft.done[self])}, payload);
    const std::uint8_t seq = node.tx_stream[dest][ch].next_seq;  // the one ft_send gives the message
    g_ft.in_send = true;
    const udn::FtError e = udn::ft_send(node, dest, ch, payload, static_cast<std::uint32_t>(k::now_ticks()));
    g_ft.in_send = false;
    if (e == udn::FtError::kOk) {
      std::uint32_t& k = g_ft.sent[self][dest][ch];
      g_ft.recent[self][dest][ch][k % kRecent] = SentMessage{static_cast<std::uint32_t>(g_ft.done[self]), seq};
      ++k;
      ++g_ft.delivery.sent;
    } else if (e == udn::FtError::kUnreachable) {
      ++g_ft.ft.unreachable;
    } else {
      return;
    }
    ++g_ft.done[self];
    src.credit -= 1.0;
    dest = bsp::kNoTile;
  }
}

void ft_driver(void* /*arg*/) {
  const bsp::TileId self = bsp::current_tile();
  if (udn::activate() != udn::RawError::kOk ||
      udn::ft_init(g_ft_nodes[self], self, g_ft.map, udn::ft_task_port(), udn::FtConfig{}) != udn::FtError::kOk) {
    return;
  }
  udn::ft_set_event_sink(g_ft_nodes[self], udn::FtEventSink{&on_ft_event, nullptr});
  const double per_tick = g_ft.opts.rate_per_us * 1e3;  // ticks are 1 ms
  Source src{bsp::Rng(g_ft.opts.seed, bsp::StreamId::kTraffic, self), per_tick, bsp::kNoTile};
  std::array<std::uint32_t, udn::kFtMaxData> data{};
  std::array<std::uint32_t, bsp::kUdnMaxLength> rx{};
  k::Ticks credited = k::now_ticks();
  for (;;) {
    // Sleep until an FT packet lands or the tick ends, then handle it and the rest.
    udn::RxInfo info{};
    if (udn::receive(udn::kFtQueue, info, rx, k::Timeout{1U}) == udn::RawError::kOk) {
      const std::size_t n = info.data_words < rx.size() ? info.data_words : rx.size();
      udn::ft_accept(g_ft_nodes[self], std::span(rx.data(), n), static_cast<std::uint32_t>(k::now_ticks()));
    }
    (void)udn::ft_poll(g_ft_nodes[self], static_cast<std::uint32_t>(k::now_ticks()), 256U);
    check_received(self);
    const k::Ticks now = k::now_ticks();
    src.credit += per_tick * static_cast<double>(now - credited);
    credited = now;
    send_some(self, src, data);
    g_ft.idle[self] = g_ft.done[self] == g_ft.plan.quota[self] && udn::ft_outstanding(g_ft_nodes[self]) == 0U;
  }
}

constexpr k::TaskSpec kFtTasks[] = {
    {"udn_ft", &ft_driver, nullptr, 2, 0, 0, kStackBytes, k::Policy::kPreemptive},
};
static_assert(k::check_table(kFtTasks) == k::TableError::kOk);

bool ft_all_done(void* /*arg*/) {
  for (std::uint32_t i = 0; i < g_ft.plan.sender_count; ++i) {
    if (!g_ft.idle[g_ft.plan.targets[i]]) {
      return false;
    }
  }
  std::uint64_t gave_up = 0U;
  for (const udn::FtNode& n : g_ft_nodes) {
    gave_up += n.stats.gave_up;
  }
  return g_ft.delivery.delivered + gave_up >= g_ft.delivery.sent && bsp::udn_net_in_flight() == 0U;
}

/** The fault map every node starts from: it knows every failure the run was given at t=0. */
bool build_map(const StressOptions& opts) {
  const bsp::ChipProfile& p = g_ft.plan.profile;
  if (udn::fault_map_init(g_ft.map, p.cols, p.rows) != udn::RouteError::kOk) {
    return false;
  }
  bool ok = true;
  for (const std::uint32_t t : opts.failed_tiles) {
    ok = ok && udn::fault_map_fail_tile(g_ft.map, t) == udn::RouteError::kOk;
  }
  for (const std::uint32_t t : opts.failed_switches) {
    ok = ok && udn::fault_map_fail_tile(g_ft.map, t) == udn::RouteError::kOk;  // its switch is not trusted
  }
  for (const std::string& l : opts.failed_links) {
    LinkSpec spec{};
    ok = ok && parse_link(l, p.cols, p.rows, spec).empty() &&
         udn::fault_map_fail_link(g_ft.map, spec.tile, spec.dir, true) == udn::RouteError::kOk;
  }
  return ok;
}

void collect(StressResult& r) {
  for (const udn::FtNode& n : g_ft_nodes) {
    g_ft.ft.corrected += n.stats.corrected;
    g_ft.ft.forwarded += n.stats.forwarded;
    g_ft.ft.retransmitted += n.stats.retransmitted;
    g_ft.ft.uncorrectable_detected += n.stats.uncorrectable_detected;
    g_ft.ft.gave_up += n.stats.gave_up;
  }
  g_ft.delivery.lost = g_ft.delivery.sent - g_ft.arrived;
  for (const GiveUpRecord& g : g_give_ups) {
    const bool arrived = g_arrived[g.source][g.number] != 0U;
    StressResult::Ft& f = g_ft.ft;
    switch (g.claim) {
      case udn::FtDelivery::kUnknown: ++f.gave_up_unknown; f.gave_up_unknown_arrived += arrived ? 1U : 0U; break;
      case udn::FtDelivery::kNotDelivered:
        ++f.gave_up_not_delivered;
        f.gave_up_not_delivered_arrived += arrived ? 1U : 0U;
        break;
      case udn::FtDelivery::kDelivered: ++f.acks_lost; f.acks_lost_missing += arrived ? 0U : 1U; break;
    }
  }
  r.delivery = g_ft.delivery;
  r.ft = g_ft.ft;
}

}  // namespace

StressResult run_stress_ft(const StressOptions& opts, bsp::heap::SealMode seal) {
  StressResult r;
  // Reset in place: `g_ft = FtShared{}` would build the megabytes of a
  // temporary on the stack first (instrumented builds keep it there and overflow).
  std::destroy_at(&g_ft);
  std::construct_at(&g_ft);
  std::destroy_at(&g_ft_nodes);
  std::construct_at(&g_ft_nodes);
  g_ft.opts = opts;
  g_ft.plan = detail::make_plan(opts);
  for (std::size_t t = 0; t < bsp::kMaxTiles; ++t) {
    g_arrived[t].assign(g_ft.plan.quota[t], 0U);
  }
  g_give_ups.clear();
  g_give_ups.reserve(kGiveUpRecords);
  bsp::NetConfig net{};
  net.max_in_flight_per_tile = bsp::kUdnMaxInFlightPerTile;
  net.queue_words = bsp::kUdnMaxQueueWords;
  if (g_ft.plan.sender_count == 0U || !build_map(opts) || !detail::boot_stress_board(opts, g_ft.plan, kFtTasks, net)) {
    return r;
  }
  detail::run_stress_board(opts, g_ft.plan, &ft_all_done, seal, r);
  collect(r);
  return r;
}

}  // namespace tools
