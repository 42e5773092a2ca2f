/**
 * @file ft_link.cpp
 * @brief Listener, reliable channels (sequence, ACK/NACK, go-back-N retransmission) and forwarding.
 */
#include "udn/ft_link.hpp"

#include "udn/ecc.hpp"

namespace udn {
namespace {

constexpr std::uint32_t kHalfSeq = 128U;

struct ChannelWord {
  std::uint32_t source;
  std::uint8_t seq;
  FtKind kind;
  bool resync;
  std::uint32_t channel;
  std::uint8_t epoch;
};

ChannelWord split(std::uint32_t w) noexcept {
  return ChannelWord{w >> 24U, static_cast<std::uint8_t>((w >> 16U) & 0xFFU),
                     static_cast<FtKind>((w >> 12U) & 0xFU), ((w >> 8U) & 1U) != 0U, w & 0xFFU,
                     static_cast<std::uint8_t>((w >> 9U) & (kFtEpochs - 1U))};
}

/**
 * A control packet (ACK, NACK, PING, PONG) with the epoch of the stream it
 * answers; a NACK with @p resync asks the sender to start the stream again.
 */
FtError send_control(FtNode& node, bsp::TileId dest, FtKind kind, std::uint8_t seq, std::uint32_t word, bool routed,
                     std::uint8_t epoch, bool resync = false) noexcept;

/** (a - b) mod 256: how far a is ahead of b. */
std::uint32_t seq_ahead(std::uint8_t a, std::uint8_t b) noexcept {
  return static_cast<std::uint32_t>(static_cast<std::uint8_t>(a - b));
}

bsp::NetError task_send(void* /*ctx*/, bsp::TileId /*self*/, std::span<const std::uint32_t> words) noexcept {
  return bsp::udn_net_send(words);
}

bsp::NetError task_receive(void* /*ctx*/, bsp::TileId /*self*/, std::uint32_t queue, bsp::RxPacket& rx,
                           std::span<std::uint32_t> payload) noexcept {
  return bsp::udn_net_receive(queue, rx, payload);
}

std::uint32_t task_credits(void* /*ctx*/, bsp::TileId self) noexcept { return bsp::udn_net_send_credits(self); }

/** True if a packet that is not a reply may leave now: more credits than kFtReplyReserve. */
bool room_beyond_reserve(const FtNode& n) noexcept {
  return n.port.credits == nullptr || n.port.credits(n.port.ctx, n.self) > kFtReplyReserve;
}

/**
 * Points the image at the next hop for its destination index and sends it.
 * Only a @p reply (ACK, NACK, PONG) may use the credits of the reserve.
 */
FtError route_and_send(FtNode& n, std::span<std::uint32_t> image, bsp::TileId dest, bool reply = false) noexcept {
  bsp::TileId next = bsp::kNoTile;
  if (route_next_hop(n.routes, dest, next) != RouteError::kOk) {
    return FtError::kUnreachable;
  }
  const auto x = static_cast<std::uint8_t>(next % n.routes.cols);
  const auto y = static_cast<std::uint8_t>(next / n.routes.cols);
  if (readdress_packet(image, x, y, kFtHwTag) != ReaddressStatus::kOk) {
    return FtError::kBadArgs;
  }
  if (!reply && !room_beyond_reserve(n)) {
    return FtError::kNetFull;
  }
  return (n.port.send(n.port.ctx, n.self, image) == bsp::NetError::kOk) ? FtError::kOk : FtError::kNetFull;
}

/**
 * Sends slot @p s's packet to @p dest by the route and, if it has a twin, a
 * copy through the twin (ft_send). @return the route's send.
 */
FtError send_slot(FtNode& n, detail::TxSlot& s, bsp::TileId dest) noexcept {
  const std::span<std::uint32_t> image(s.image.data(), s.words);
  const FtError e = route_and_send(n, image, dest);
  if (e == FtError::kOk && s.twin < n.routes.tiles && room_beyond_reserve(n)) {
    const auto x = static_cast<std::uint8_t>(s.twin % n.routes.cols);
    const auto y = static_cast<std::uint8_t>(s.twin / n.routes.cols);
    if (readdress_packet(image, x, y, kFtHwTag) == ReaddressStatus::kOk) {
      if (n.port.send(n.port.ctx, n.self, image) == bsp::NetError::kOk) {
        ++n.stats.twin_copies;
      }  // refused: the route's packet is on its way
    }
  }
  return e;
}

void log_event(FtNode& n, FtCause cause, bsp::TileId peer, std::uint32_t channel, std::uint8_t seq,
               std::uint32_t now, FtDelivery delivery = FtDelivery::kUnknown) noexcept {
  ft_event_emit(n.sink, n.self,
                FtEvent{now, cause, static_cast<std::uint8_t>(channel), seq, peer, static_cast<std::uint32_t>(delivery)});
}

/** Answers (ACK, NACK, SYNC-ACK) carry the stream's channel and, in the bits above, the receiver's resync record. */
constexpr std::uint32_t kAnswerRecord = 1U << 8U;

/** The data word of an answer of stream @p rs on @p channel. */
std::uint32_t answer_word(const detail::RxStream& rs, std::uint32_t channel) noexcept {
  return rs.rec_valid ? (channel | kAnswerRecord | (static_cast<std::uint32_t>(rs.rec_point) << 16U) |
                         (static_cast<std::uint32_t>(rs.rec_from) << 24U))
                      : channel;
}

/** An answer's data word, taken apart. */
struct AnswerWord {
  std::uint32_t channel;
  bool record;
  std::uint8_t point;  ///< the resync point the receiver took last
  std::uint8_t from;   ///< what it expected then
};

AnswerWord split_answer(std::uint32_t w) noexcept {
  return AnswerWord{w & 0xFFU, (w & kAnswerRecord) != 0U, static_cast<std::uint8_t>((w >> 16U) & 0xFFU),
                    static_cast<std::uint8_t>(w >> 24U)};
}

/** One round-trip sample @p rtt (ticks) to @p dest into its smoothed estimate (RFC 6298, integer). */
void sample_rtt(FtNode& n, bsp::TileId dest, std::uint32_t rtt) noexcept {
  const std::uint32_t r = rtt < kMaxRttTicks ? rtt : kMaxRttTicks;
  std::uint32_t srtt8 = n.srtt8[dest];
  std::uint32_t var4 = n.rttvar4[dest];
  if (srtt8 == 0U) {
    srtt8 = 8U * r + 1U;  // + 1: a first sample of 0 ticks still marks the estimate taken
    var4 = 2U * r;
  } else {
    const std::uint32_t srtt = srtt8 / 8U;
    const std::uint32_t dev = srtt > r ? srtt - r : r - srtt;
    var4 = var4 - var4 / 4U + dev;  // rttvar = 3/4 rttvar + 1/4 |srtt - r|, x4
    srtt8 = srtt8 - srtt8 / 8U + r;  // srtt = 7/8 srtt + 1/8 r, x8
  }
  n.srtt8[dest] = static_cast<std::uint16_t>(srtt8);
  n.rttvar4[dest] = static_cast<std::uint16_t>(var4);
  n.rto_shift[dest] = 0U;
}

/** The first retransmit timeout towards @p dest, ticks. */
std::uint32_t rto_ticks(const FtNode& n, bsp::TileId dest) noexcept {
  if (n.srtt8[dest] == 0U) {
    return n.config.timeout_ticks;
  }
  const std::uint32_t var = n.rttvar4[dest];  // 4 rttvar
  const std::uint32_t rto = n.srtt8[dest] / 8U + (var > 1U ? var : 1U);
  return rto > n.config.timeout_ticks ? rto : n.config.timeout_ticks;
}

/** Frees every slot of stream (dest, channel) that @p acked covers (cumulative); samples the round trip. */
void take_ack(FtNode& n, bsp::TileId dest, std::uint32_t channel, std::uint8_t acked, std::uint32_t now) noexcept {
  for (detail::TxSlot& s : n.tx) {
    if (s.used && s.dest == dest && s.channel == channel && seq_ahead(acked, s.seq) < kHalfSeq) {
      s.used = false;
      --n.in_window[dest];
      if (s.retries == 0U && !s.held) {
        sample_rtt(n, dest, now - s.sent_tick);  // sent once: its answer times the path (Karn)
      }
    }
  }
  detail::TxStream& st = n.tx_stream[dest][channel];
  if (st.resync && seq_ahead(acked, st.resync_seq) < kHalfSeq) {
    st.resync = false;
  }
  if (st.busy && seq_ahead(acked, st.busy_seq) < kHalfSeq) {
    st.busy = false;  // the packet that waited for room was taken
  }
  // The receiver expects acked + 1 or more; an answer beyond what was sent is not believed.
  const auto expects = static_cast<std::uint8_t>(acked + 1U);
  if (seq_ahead(expects, st.confirmed) <= seq_ahead(st.next_seq, st.confirmed)) {
    st.confirmed = expects;
  }
}

/** Marks stream (dest, channel) held or not, keeping the node's count of held streams. */
void hold_stream(FtNode& n, bsp::TileId dest, std::uint32_t channel, bool held) noexcept {
  detail::TxStream& st = n.tx_stream[dest][channel];
  if (st.held != held) {
    st.held = held;
    n.held_streams = held ? n.held_streams + 1U : n.held_streams - 1U;
  }
}

/** A resend of stream (dest, channel) from @p seq for @p why: flow control is counted, anything else logged. */
void report_resend(FtNode& n, FtCause why, bsp::TileId dest, std::uint32_t channel, std::uint8_t seq,
                   std::uint32_t now) noexcept {
  if (why == FtCause::kResentBusy) {
    ++n.stats.resent_busy;  // flow control, not a fault: counted, no event
  } else {
    log_event(n, why, dest, channel, seq, now);
  }
}

/**
 * Retransmits the stream's outstanding slots in sequence order from @p from; @p why is reported once.
 * @return whether any left the tile.
 */
bool resend_stream(FtNode& n, bsp::TileId dest, std::uint32_t channel, std::uint8_t from, std::uint32_t now,
                   FtCause why) noexcept {
  bool reported = false;
  bool refused = false;
  for (std::uint32_t k = 0U; k < kFtTxSlots; ++k) {
    const auto seq = static_cast<std::uint8_t>(from + k);
    for (detail::TxSlot& s : n.tx) {
      if (!s.used || s.dest != dest || s.channel != channel || s.seq != seq) {
        continue;
      }
      s.sent_tick = now;
      // A refused resend never left the tile: it and the ones after it (sent now, they would
      // arrive behind a gap) wait for the next timeout without using up a retry. An unroutable
      // one counts (it may never route).
      if (refused || send_slot(n, s, dest) == FtError::kNetFull) {
        refused = true;
        s.held = true;
        hold_stream(n, dest, channel, true);
      } else {
        s.held = false;
        ++s.retries;
        ++n.stats.retransmitted;
        if (!reported) {
          reported = true;
          report_resend(n, why, dest, channel, seq, now);
        }
      }
    }
  }
  detail::TxStream& st = n.tx_stream[dest][channel];
  if (!refused) {
    hold_stream(n, dest, channel, false);  // every outstanding packet left, in order
  }
  if (reported) {
    st.held_report = false;  // an earlier resend refused whole is reported by this one
  } else if (refused) {
    st.held_report = true;  // told when the held packets leave
    st.held_why = static_cast<std::uint8_t>(why);
  }
  return reported;
}

/** The oldest outstanding slot of a stream (nullptr if none). */
detail::TxSlot* oldest(FtNode& n, bsp::TileId dest, std::uint32_t channel) noexcept {
  detail::TxSlot* best = nullptr;
  const std::uint8_t next = n.tx_stream[dest][channel].next_seq;
  for (detail::TxSlot& s : n.tx) {
    if (s.used && s.dest == dest && s.channel == channel &&
        (best == nullptr || seq_ahead(next, s.seq) > seq_ahead(next, best->seq))) {
      best = &s;
    }
  }
  return best;
}

/**
 * Sends the held slots of stream (dest, channel) in sequence order, up to the
 * first the network refuses (it and those after it stay held). They never
 * left the tile: no retry is used up and nothing is logged.
 */
void send_held(FtNode& n, bsp::TileId dest, std::uint32_t channel, std::uint32_t now) noexcept {
  const detail::TxSlot* o = oldest(n, dest, channel);
  if (o == nullptr) {
    hold_stream(n, dest, channel, false);
    return;
  }
  const std::uint8_t from = o->seq;
  for (std::uint32_t k = 0U; k < kFtTxSlots; ++k) {
    const auto seq = static_cast<std::uint8_t>(from + k);
    for (detail::TxSlot& s : n.tx) {
      if (!s.used || !s.held || s.dest != dest || s.channel != channel || s.seq != seq) {
        continue;
      }
      if (send_slot(n, s, dest) == FtError::kNetFull) {
        return;
      }
      s.held = false;
      s.sent_tick = now;
      detail::TxStream& st = n.tx_stream[dest][channel];
      if (st.held_report) {
        st.held_report = false;
        auto why = static_cast<FtCause>(st.held_why);
        // A resend's cause only: an upset one is not reported as another event.
        why = why == FtCause::kResentNack || why == FtCause::kResentBusy ? why : FtCause::kResentTimeout;
        st.busy = st.busy && why != FtCause::kResentBusy;  // that resend answered the BUSY
        report_resend(n, why, dest, channel, seq, now);
      }
    }
  }
  hold_stream(n, dest, channel, false);
}

/** Every held stream's slots, in order, as far as the network takes them. */
void send_all_held(FtNode& n, std::uint32_t now) noexcept {
  for (std::uint32_t i = 0U; i < kFtTxSlots && n.held_streams > 0U; ++i) {
    const detail::TxSlot& s = n.tx[i];
    if (s.used && s.held && n.tx_stream[s.dest][s.channel].held) {
      send_held(n, s.dest, s.channel, now);
    }
  }
}

/** The cause a give-up towards @p dest is reported with: no route left, or retries used up. */
FtCause give_up_cause(const FtNode& n, bsp::TileId dest) noexcept {
  bsp::TileId next = bsp::kNoTile;
  return (route_next_hop(n.routes, dest, next) == RouteError::kOk) ? FtCause::kRetriesExhausted
                                                                     : FtCause::kUnreachable;
}

/** Gives up every packet of a stream, each logged with what is known of its delivery. @return how many. */
std::uint32_t drop_stream(FtNode& n, bsp::TileId dest, std::uint32_t channel, FtDelivery delivery,
                          std::uint32_t now) noexcept {
  const FtCause cause = give_up_cause(n, dest);
  std::uint32_t dropped = 0U;
  for (detail::TxSlot& s : n.tx) {
    if (s.used && s.dest == dest && s.channel == channel) {
      log_event(n, cause, dest, channel, s.seq, now, delivery);
      s.used = false;
      --n.in_window[dest];
      ++n.stats.gave_up;
      ++dropped;
    }
  }
  (delivery == FtDelivery::kUnknown ? n.stats.gave_up_unknown : n.stats.gave_up_not_delivered) += dropped;
  return dropped;
}

/**
 * The answer of stream (dest, channel) that tells what became of the packets
 * given up before its resync point: with the record of that very point, each
 * was delivered (before what the receiver expected then) or skipped. Any
 * other answer that covers the point (the receiver restarted since) tells
 * nothing: their events said "unknown" and stay so.
 */
void settle(FtNode& n, bsp::TileId dest, std::uint32_t channel, const AnswerWord& a, std::uint32_t now) noexcept {
  detail::TxStream& st = n.tx_stream[dest][channel];
  st.settle_pending = false;
  const std::uint32_t count = seq_ahead(st.settle_point, st.settle_from);
  const std::uint32_t delivered = seq_ahead(a.from, st.settle_from);
  if (!a.record || a.point != st.settle_point || delivered > count) {
    return;
  }
  for (std::uint32_t i = 0U; i < count; ++i) {
    const auto seq = static_cast<std::uint8_t>(st.settle_from + i);
    const FtDelivery d = i < delivered ? FtDelivery::kDelivered : FtDelivery::kNotDelivered;
    log_event(n, FtCause::kSettled, dest, channel, seq, now, d);
    ++(d == FtDelivery::kDelivered ? n.stats.settled_delivered : n.stats.settled_not_delivered);
  }
}

/** The SYNC slot of stream (dest, channel), or nullptr. */
detail::SyncSlot* find_sync(FtNode& n, bsp::TileId dest, std::uint32_t channel) noexcept {
  for (detail::SyncSlot& y : n.sync) {
    if (y.used && y.dest == dest && y.channel == channel) {
      return &y;
    }
  }
  return nullptr;
}

/** Sends (again) a stream's SYNC; one that left the tile, or found no route, uses up a retry after the first. */
void send_sync(FtNode& n, detail::SyncSlot& y, std::uint32_t now, bool first) noexcept {
  y.sent_tick = now;
  const FtError e = send_control(n, y.dest, FtKind::kSync, y.start, y.channel, true, n.epoch);
  if (!first && e != FtError::kNetFull) {
    ++y.retries;
  }
}

/**
 * Starts resynchronising a syncing stream: a SYNC asks the receiver to expect
 * the stream's next sequence number. With every SYNC slot taken the stream
 * waits (its packets stay queued); the next poll tries again.
 */
void start_sync(FtNode& n, bsp::TileId dest, std::uint32_t channel, std::uint32_t now) noexcept {
  if (find_sync(n, dest, channel) != nullptr) {
    return;
  }
  const detail::TxSlot* first = oldest(n, dest, channel);  // a packet waiting already: R is its sequence
  const std::uint8_t start = first != nullptr ? first->seq : n.tx_stream[dest][channel].next_seq;
  for (detail::SyncSlot& y : n.sync) {
    if (!y.used) {
      y = detail::SyncSlot{true, static_cast<std::uint8_t>(dest), static_cast<std::uint8_t>(channel), start, 0U, now};
      n.sync_hint = true;
      send_sync(n, y, now, true);
      return;
    }
  }
}

/**
 * Gives up every outstanding packet of a stream (each logged, delivery
 * unknown: they left the tile) and resynchronises it at its next sequence
 * number R, whose answer will tell what became of them. The receiver expects
 * at least `confirmed`: while R and the window after it stay within half
 * the sequence space of that, R goes as a flagged packet; beyond, a flag
 * could look like a duplicate, and the next packets wait for a SYNC.
 */
void give_up_stream(FtNode& n, bsp::TileId dest, std::uint32_t channel, std::uint32_t now) noexcept {
  detail::TxStream& st = n.tx_stream[dest][channel];
  const detail::TxSlot* first = oldest(n, dest, channel);
  if (first != nullptr && !st.settle_pending) {
    st.settle_from = first->seq;  // pending, the earlier ones and these are one run up to the new point
  }
  (void)drop_stream(n, dest, channel, FtDelivery::kUnknown, now);
  hold_stream(n, dest, channel, false);
  st.held_report = false;
  st.busy = false;
  st.settle_pending = true;
  st.settle_point = st.next_seq;
  if (seq_ahead(st.next_seq, st.confirmed) + 2U * kFtWindow < kHalfSeq) {
    st.resync = true;
    st.resync_seq = st.next_seq;
    return;
  }
  st.syncing = true;
  st.resync = false;  // the SYNC starts the receiver's stream
  start_sync(n, dest, channel, now);
}

/**
 * A SYNC unanswered after its retries: the packets waiting for it never left
 * the tile; they are given up (not delivered) and their sequence numbers
 * taken back, so the next SYNC asks for the same R, which the receiver can
 * still take however many SYNCs fail.
 */
void sync_failed(FtNode& n, detail::SyncSlot& y, std::uint32_t now) noexcept {
  (void)drop_stream(n, y.dest, y.channel, FtDelivery::kNotDelivered, now);
  hold_stream(n, y.dest, y.channel, false);
  n.tx_stream[y.dest][y.channel].next_seq = y.start;
  y.used = false;  // the stream stays syncing: its next packet starts another SYNC (which may still settle)
}

/** Rewrites a queued packet's channel word with the resync flag (its codes are computed again). */
void flag_resync(detail::TxSlot& s) noexcept {
  const std::span<std::uint32_t> image(s.image.data(), s.words);
  const std::uint32_t rd = image[kWordRouteData];
  const std::size_t n_data = rd & 0xFFU;
  const bool with_crc = (rd & kFlagCrc) != 0U;
  if (n_data == 0U || n_data > kFtMaxDataWords || kWordData + n_data > s.words) {
    return;
  }
  std::array<std::uint32_t, kFtMaxDataWords> data{};
  for (std::size_t i = 0U; i < n_data && i < data.size(); ++i) {
    data[i] = image[kWordData + i];
  }
  const FtFields f{0U, 0U, static_cast<std::uint16_t>(rd >> 16U), kFtHwTag, image[kWordChannel] | (1U << 8U), with_crc};
  std::size_t written = 0U;
  if (encode_packet(f, std::span<const std::uint32_t>(data.data(), n_data), s.image, written) == EncodeStatus::kOk) {
    s.words = static_cast<std::uint32_t>(written);
  }
}

/**
 * The receiver has no stream of ours (it restarted, or our first packet was
 * lost): the oldest outstanding packet of the stream is flagged and the
 * stream resent from it; with nothing outstanding the next packet is flagged.
 */
void restart_stream(FtNode& n, bsp::TileId dest, std::uint32_t channel, std::uint32_t now) noexcept {
  detail::TxStream& st = n.tx_stream[dest][channel];
  detail::TxSlot* o = oldest(n, dest, channel);
  st.settle_pending = false;  // the receiver lost its state: what it had taken before stays unknown
  st.busy = false;
  st.confirmed = o != nullptr ? o->seq : st.next_seq;  // it starts where the flagged packet is
  if (o == nullptr) {
    st.resync = true;
    st.resync_seq = st.next_seq;
    return;
  }
  if (!st.resync || st.resync_seq != o->seq) {
    flag_resync(*o);
    st.resync = true;
    st.resync_seq = o->seq;
  }
  (void)resend_stream(n, dest, channel, o->seq, now, FtCause::kResentNack);
}

/** Exponential back-off (x2 per retry, at most x16): a congested forwarder gets air instead of a storm of resends. */
bool due(std::uint32_t timeout, std::uint32_t sent_tick, std::uint32_t doublings, std::uint32_t now) noexcept {
  const std::uint32_t backoff = (doublings < 4U) ? doublings : 4U;
  return now - sent_tick >= (timeout << backoff);
}

/** SYNCs: resent on timeout, failed after max_retries; a syncing stream with packets and no SYNC slot starts one. */
void run_sync_timers(FtNode& n, std::uint32_t now) noexcept {
  const bool sync_scan = n.sync_hint;
  n.sync_hint = false;  // set again by every used slot the scan meets (and by a SYNC started meanwhile)
  for (std::uint32_t i = 0U; i < kFtSyncSlots && sync_scan; ++i) {
    detail::SyncSlot& y = n.sync[i];
    n.sync_hint = n.sync_hint || y.used;
    if (!y.used || !due(n.config.timeout_ticks, y.sent_tick, y.retries, now)) {
      continue;
    }
    if (y.retries >= n.config.max_retries) {
      sync_failed(n, y, now);
    } else {
      send_sync(n, y, now, false);
    }
  }
  for (std::uint32_t i = 0U; i < kFtTxSlots && n.tx_hint; ++i) {
    const detail::TxSlot& s = n.tx[i];
    if (s.used && n.tx_stream[s.dest][s.channel].syncing) {
      start_sync(n, s.dest, s.channel, now);
    }
  }
}

void run_timers(FtNode& n, std::uint32_t now) noexcept {
  run_sync_timers(n, now);
  const bool tx_scan = n.tx_hint;
  n.tx_hint = false;  // set again by every used slot the scan meets (slots are taken only by ft_send)
  for (std::uint32_t i = 0U; i < kFtTxSlots && tx_scan; ++i) {
    const detail::TxSlot& s = n.tx[i];
    n.tx_hint = n.tx_hint || s.used;
    if (!s.used || n.tx_stream[s.dest][s.channel].syncing || !due(rto_ticks(n, s.dest), s.sent_tick, s.retries + n.rto_shift[s.dest], now)) {
      continue;  // a syncing stream's packets wait for its SYNC-ACK
    }
    detail::TxSlot* first = oldest(n, s.dest, s.channel);
    if (first == nullptr) {
      continue;
    }
    const bsp::TileId dest = first->dest;
    const std::uint32_t channel = first->channel;
    if (first->retries >= n.config.max_retries) {
      give_up_stream(n, dest, channel, now);
    } else {
      detail::TxStream& st = n.tx_stream[dest][channel];
      const bool busy = st.busy && st.busy_seq == first->seq;
      if (resend_stream(n, dest, channel, first->seq, now, busy ? FtCause::kResentBusy : FtCause::kResentTimeout)) {
        st.busy = false;  // a BUSY answers one arrival: if the queue is still full, the resend gets another
      }
      if (!busy && n.rto_shift[dest] < 4U) {
        ++n.rto_shift[dest];  // the round trip may be longer than the estimate: wait longer until it is measured
      }
    }
  }
}

/** ACKs @p seq of (source, channel); if the network refuses, the ACK is owed to the next poll. */
void send_ack(FtNode& n, std::uint32_t source, std::uint32_t channel, std::uint8_t seq) noexcept {
  detail::RxStream& rs = n.rx_stream[source][channel];
  if (send_control(n, source, FtKind::kAck, seq, answer_word(rs, channel), true, rs.epoch) == FtError::kOk) {
    ++n.stats.acks_sent;
    if (rs.ack_owed) {
      rs.ack_owed = false;
      --n.acks_owed;
    }
  } else if (!rs.ack_owed) {
    rs.ack_owed = true;
    ++n.acks_owed;
  }
}

/**
 * Tells the sender of stream (source, channel) that its packet `expected`
 * came with the receive queue full; if the network refuses, the BUSY is owed
 * to the next polls (while the queue stays full).
 */
void send_busy(FtNode& n, std::uint32_t source, std::uint32_t channel) noexcept {
  detail::RxStream& rs = n.rx_stream[source][channel];
  const bool sent =
      send_control(n, source, FtKind::kBusy, rs.expected, answer_word(rs, channel), true, rs.epoch) == FtError::kOk;
  n.stats.busy_sent += sent ? 1U : 0U;
  if (sent == rs.busy_owed) {
    n.busies_owed = sent ? n.busies_owed - 1U : n.busies_owed + 1U;
    rs.busy_owed = !sent;
  }
}

/** Resends owed ACKs (the latest in-order sequence of each stream) and owed BUSYs. Bounded: tiles x channels. */
void pay_acks(FtNode& n) noexcept {
  for (std::uint32_t src = 0U; src < n.routes.tiles && (n.acks_owed > 0U || n.busies_owed > 0U); ++src) {
    for (std::uint32_t ch = 0U; ch < kFtAllChannels; ++ch) {
      detail::RxStream& rs = n.rx_stream[src][ch];
      if (rs.ack_owed) {
        send_ack(n, src, ch, static_cast<std::uint8_t>(rs.expected - 1U));
      }
      if (rs.busy_owed) {
        send_busy(n, src, ch);  // even with room now: the packet was dropped for the lack of it
      }
    }
  }
}

/** Puts a message into its channel's receive queue. @return false if the queue is full (dropped, not ACKed). */
bool enqueue(FtNode& n, const ChannelWord& cw, std::span<const std::uint32_t> data) noexcept {
  detail::RxQueue& q = n.rxq[cw.channel];
  if (q.count >= kFtRxDepth) {
    ++n.stats.rx_full_dropped;
    return false;
  }
  FtMessage& m = q.msg[(q.head + q.count) % kFtRxDepth];
  m.source = cw.source;
  m.channel = static_cast<std::uint8_t>(cw.channel);
  m.seq = cw.seq;
  m.data_words = static_cast<std::uint16_t>(data.size());
  for (std::size_t i = 0U; i < data.size(); ++i) {
    m.data[i] = data[i];
  }
  ++q.count;
  n.rx_ready = static_cast<std::uint8_t>(static_cast<std::uint32_t>(n.rx_ready) | (1U << cw.channel));
  ++n.stats.delivered;
  return true;
}

/** A resync point taken on a running stream: what it expected before, for every answer from now on. */
void record_resync(detail::RxStream& rs, std::uint8_t point) noexcept {
  rs.rec_valid = true;
  rs.rec_point = point;
  rs.rec_from = rs.expected;
}

/** Accepts or drops one data packet of (source, channel) in sequence; ACKs or NACKs. */
void on_data(FtNode& n, const ChannelWord& cw, std::span<const std::uint32_t> data) noexcept {
  detail::RxStream& rs = n.rx_stream[cw.source][cw.channel];
  const bool running = rs.synced && cw.epoch == rs.epoch;
  if (!running) {
    // Nothing taken since this node started, or the sender restarted: only a
    // flagged packet starts the stream (the sender's oldest outstanding one).
    // For any other, the sender is asked once to flag its oldest and resend.
    if (!cw.resync) {
      ++n.stats.out_of_order_dropped;
      if (!rs.resync_asked) {
        rs.resync_asked =
            send_control(n, cw.source, FtKind::kNack, cw.seq, cw.channel, true, cw.epoch, true) == FtError::kOk;
      }
      return;
    }
    rs.synced = true;
    rs.epoch = cw.epoch;
    rs.expected = cw.seq;
    rs.nack_sent = false;
    rs.busy = false;
    rs.resync_asked = false;
    rs.rec_valid = false;  // a new stream: nothing it took before is known here
  }
  const std::uint32_t ahead = seq_ahead(cw.seq, rs.expected);
  const bool resync = cw.resync && ahead != 0U && ahead < kHalfSeq;
  if (ahead >= kHalfSeq) {  // already delivered: the ACK was lost
    ++n.stats.duplicates_dropped;
    send_ack(n, cw.source, cw.channel, static_cast<std::uint8_t>(rs.expected - 1U));
    return;
  }
  if (ahead != 0U && !resync) {  // a gap: ask once for the missing one
    ++n.stats.out_of_order_dropped;
    if (rs.busy) {
      return;  // behind a packet that waits for room (BUSY): its sender resends them all on its timeout
    }
    if (!rs.nack_sent || rs.nacked != rs.expected) {
      rs.nack_sent = send_control(n, cw.source, FtKind::kNack, rs.expected, answer_word(rs, cw.channel), true,
                                  rs.epoch) == FtError::kOk;
      rs.nacked = rs.expected;
      n.stats.nacks_sent += rs.nack_sent ? 1U : 0U;
    }
    return;
  }
  if (!enqueue(n, cw, data)) {
    // Flow control, not a fault: the sender learns that this packet waits for room, at each arrival.
    rs.busy = rs.expected == cw.seq;
    send_busy(n, cw.source, cw.channel);
    return;
  }
  rs.busy = false;
  if (rs.busy_owed) {
    rs.busy_owed = false;
    --n.busies_owed;
  }
  if (cw.resync && running) {
    record_resync(rs, cw.seq);  // the packets from what it expected up to here were given up by the sender
  }
  rs.expected = static_cast<std::uint8_t>(cw.seq + 1U);
  rs.nack_sent = false;
  send_ack(n, cw.source, cw.channel, cw.seq);
}

/**
 * A SYNC from the sender of stream (source, channel): expect seq R next. A
 * SYNC behind what the stream expects is an old copy and dropped; a copy of
 * the SYNC taken last (its SYNC-ACK was lost) finds R expected already and is
 * answered again with the same record. Old data copies (behind R) are
 * duplicates from now on.
 */
void on_sync(FtNode& n, const ChannelWord& cw, std::uint32_t channel) noexcept {
  detail::RxStream& rs = n.rx_stream[cw.source][channel];
  const bool running = rs.synced && rs.epoch == cw.epoch;
  const std::uint32_t ahead = seq_ahead(cw.seq, rs.expected);
  if (running && ahead >= kHalfSeq) {
    return;
  }
  const bool copy = running && ahead == 0U && rs.rec_valid && rs.rec_point == cw.seq;
  if (running && !copy) {
    record_resync(rs, cw.seq);
  } else if (!running) {
    rs.rec_valid = false;  // it follows nothing of this sender: what it took before is not known here
  }
  rs.synced = true;
  rs.epoch = cw.epoch;
  rs.expected = cw.seq;
  rs.nack_sent = false;
  rs.resync_asked = false;
  // Lost: the SYNC comes again.
  (void)send_control(n, cw.source, FtKind::kSyncAck, cw.seq, answer_word(rs, channel), true, rs.epoch);
}

/** The receiver took the stream's SYNC: its waiting packets go, in sequence order. */
void on_sync_ack(FtNode& n, bsp::TileId dest, const AnswerWord& a, std::uint8_t start, std::uint32_t now) noexcept {
  const std::uint32_t channel = a.channel;
  detail::SyncSlot* y = find_sync(n, dest, channel);
  if (y == nullptr || y->start != start) {
    return;  // answers an older SYNC
  }
  detail::TxStream& st = n.tx_stream[dest][channel];
  if (st.settle_pending && st.settle_point == start) {
    settle(n, dest, channel, a, now);
  }
  y->used = false;
  st.syncing = false;
  st.confirmed = start;
  for (std::uint32_t k = 0U; k < kFtTxSlots; ++k) {
    const auto seq = static_cast<std::uint8_t>(start + k);
    for (detail::TxSlot& s : n.tx) {
      if (s.used && s.dest == dest && s.channel == channel && s.seq == seq) {
        s.sent_tick = now;  // refused here: its timeout resends it
        (void)send_slot(n, s, dest);
      }
    }
  }
}

/** Answers a PING; if the network refuses, the PONG is owed to the next polls (the prober scores it a round later). */
void answer_ping(FtNode& n, bsp::TileId prober, std::uint32_t nonce) noexcept {
  const bool sent = ft_send_control(n, prober, FtKind::kPong, 0U, nonce, false) == FtError::kOk;
  const bool was_owed = n.pong_owed[prober] != 0U;
  n.pong_owed[prober] = sent ? 0U : nonce;
  if (sent && was_owed) {
    --n.pongs_owed;
  } else if (!sent && !was_owed) {
    ++n.pongs_owed;
  }
}

/** Resends owed PONGs. Bounded: one per tile. */
void pay_pongs(FtNode& n) noexcept {
  for (std::uint32_t t = 0U; t < n.routes.tiles && n.pongs_owed > 0U; ++t) {
    if (n.pong_owed[t] != 0U) {
      answer_ping(n, static_cast<bsp::TileId>(t), n.pong_owed[t]);
    }
  }
}

/** The answer acknowledges up to @p covered, the stream's resync point included (and nothing not sent yet). */
bool covers_point(const detail::TxStream& st, std::uint8_t covered) noexcept {
  return seq_ahead(covered, st.settle_point) < seq_ahead(st.next_seq, st.settle_point);
}

/** A stream's answers (ACK, NACK, SYNC-ACK, their record) to the sender state. */
void on_answer(FtNode& n, const ChannelWord& cw, std::uint32_t word, std::uint32_t now) noexcept {
  const AnswerWord a = split_answer(word);
  if (cw.epoch != n.epoch || a.channel >= kFtAllChannels) {
    return;  // it answers this node's previous incarnation
  }
  detail::TxStream& st = n.tx_stream[cw.source][a.channel];
  if (st.syncing || cw.kind == FtKind::kSyncAck) {
    if (st.syncing && cw.kind == FtKind::kSyncAck) {
      on_sync_ack(n, cw.source, a, cw.seq, now);
    }
    return;  // syncing, nothing of the stream is in flight: an ACK or NACK is of a packet given up
  }
  if (cw.kind == FtKind::kNack && cw.resync) {
    restart_stream(n, cw.source, a.channel, now);
    return;
  }
  const auto covered = static_cast<std::uint8_t>(cw.kind == FtKind::kAck ? cw.seq : cw.seq - 1U);
  if (st.settle_pending && covers_point(st, covered)) {
    settle(n, cw.source, a.channel, a, now);
  }
  take_ack(n, cw.source, a.channel, covered, now);
  if (cw.kind == FtKind::kBusy) {
    st.busy = true;  // its timeout resends the stream from cw.seq, as flow control
    st.busy_seq = cw.seq;
  }
  if (cw.kind == FtKind::kNack) {
    (void)resend_stream(n, cw.source, a.channel, cw.seq, now, FtCause::kResentNack);
  }
}

/** Control packets: answers to the sender state, SYNC to the receive stream, PING answered, PONG recorded. */
void on_control(FtNode& n, const ChannelWord& cw, std::span<const std::uint32_t> data, std::uint32_t now) noexcept {
  if (cw.source >= n.routes.tiles) {
    return;
  }
  const std::uint32_t word = data[0];
  if ((cw.kind == FtKind::kPing || cw.kind == FtKind::kPong) && data.size() >= 2U) {
    n.peer_map_version[cw.source] = data[1];
  }
  switch (cw.kind) {
    case FtKind::kAck:
    case FtKind::kNack:
    case FtKind::kSyncAck:
    case FtKind::kBusy:
      on_answer(n, cw, word, now);
      break;
    case FtKind::kSync:
      if (word < kFtAllChannels) {
        on_sync(n, cw, word);
      }
      break;
    case FtKind::kPing:
      answer_ping(n, cw.source, word);
      break;
    case FtKind::kPong:
      n.pong_nonce[cw.source] = word;
      break;
    case FtKind::kData:
      break;
  }
}

/** The route code alone clean: word 4 (source, seq, channel) can be trusted for a NACK. */
void nack_if_identified(FtNode& n, std::span<const std::uint32_t> image, std::uint32_t now) noexcept {
  const std::array<std::uint32_t, kRouteCodeWords> route = {image[kWordHwHeader], image[kWordHwTag],
                                                            image[kWordRouteData], image[kWordChannel]};
  if (RouteCode::check(route, image[kWordEcc] & RouteCode::kCheckMask).status != EccStatus::kClean) {
    log_event(n, FtCause::kDamaged, bsp::kNoTile, 0U, 0U, now);
    return;
  }
  const ChannelWord cw = split(image[kWordChannel]);
  if (cw.kind != FtKind::kData || cw.channel >= kFtAllChannels || cw.source >= n.routes.tiles ||
      (image[kWordRouteData] >> 16U) != n.self) {
    log_event(n, FtCause::kDamaged, bsp::kNoTile, 0U, 0U, now);
    return;
  }
  // NACK what this receiver still needs, not the damaged packet's sequence: a
  // NACK also acknowledges everything before it.
  const detail::RxStream& rs = n.rx_stream[cw.source][cw.channel];
  if (!rs.synced || rs.epoch != cw.epoch) {
    log_event(n, FtCause::kDamaged, cw.source, cw.channel, 0U, now);  // no stream to NACK in: the timeout recovers
    return;
  }
  const std::uint8_t need = rs.expected;
  const bool nacked =
      send_control(n, cw.source, FtKind::kNack, need, answer_word(rs, cw.channel), true, rs.epoch) == FtError::kOk;
  n.stats.nacks_sent += nacked ? 1U : 0U;
  log_event(n, FtCause::kDamaged, cw.source, cw.channel, nacked ? 1U : 0U, now);
}

/** Forwards a packet for another tile now, or holds it while the network refuses. */
void forward(FtNode& n, std::span<std::uint32_t> image, std::uint16_t dest, std::uint32_t now) noexcept {
  const FtError e = route_and_send(n, image, dest);
  if (e == FtError::kOk) {
    ++n.stats.forwarded;
    return;
  }
  if (e == FtError::kNetFull) {
    for (detail::FwdSlot& f : n.fwd) {
      if (!f.used) {
        f.used = true;
        n.fwd_hint = true;
        f.dest = dest;
        f.words = static_cast<std::uint32_t>(image.size());
        for (std::size_t i = 0U; i < image.size(); ++i) {
          f.image[i] = image[i];
        }
        return;
      }
    }
  }
  ++n.stats.forward_failed;  // the sender's timeout recovers it
  if (e == FtError::kUnreachable) {
    log_event(n, FtCause::kForwardUnreachable, dest, 0U, 0U, now);
  }
}

/** Retries held forwards in order. @return true if every slot is free again. */
bool flush_forwards(FtNode& n, std::uint32_t now) noexcept {
  if (!n.fwd_hint) {
    return true;
  }
  bool all_free = true;
  for (detail::FwdSlot& f : n.fwd) {
    if (!f.used) {
      continue;
    }
    const FtError e = route_and_send(n, std::span<std::uint32_t>(f.image.data(), f.words), f.dest);
    if (e == FtError::kNetFull) {
      all_free = false;
      continue;
    }
    f.used = false;
    if (e == FtError::kOk) {
      ++n.stats.forwarded;
    } else {
      ++n.stats.forward_failed;
      log_event(n, FtCause::kForwardUnreachable, f.dest, 0U, 0U, now);
    }
  }
  n.fwd_hint = !all_free;  // nothing here takes a slot: the scan saw every one
  return all_free;
}

void handle_packet(FtNode& n, std::span<std::uint32_t> image, std::uint32_t now, bool tag_damaged) noexcept {
  const Decoded d = decode_packet(image, static_cast<std::uint16_t>(n.self), CrcPolicy::kRequired);
  if (d.status != DecodeStatus::kOk && d.status != DecodeStatus::kCorrected &&
      d.status != DecodeStatus::kMisdelivered) {
    ++n.stats.uncorrectable_detected;
    if (d.status != DecodeStatus::kMalformed) {
      nack_if_identified(n, image, now);
    } else {
      log_event(n, FtCause::kDamaged, bsp::kNoTile, 0U, 0U, now);
    }
    return;
  }
  n.stats.corrected += (d.fix_count > 0U) ? 1U : 0U;
  const ChannelWord cw = split(d.fields.channel);
  if (d.status == DecodeStatus::kMisdelivered) {
    if (d.fix_count > 0U) {  // a flipped header brought it here; a clean one is a detour leg passing through
      log_event(n, FtCause::kForwarded, cw.source, cw.channel, static_cast<std::uint8_t>(d.fields.dest_index), now);
    }
    forward(n, image, d.fields.dest_index, now);
    return;
  }
  if (d.fix_count > 0U || tag_damaged) {  // a damaged tag sent it to the catch-all queue: found and undone here
    log_event(n, FtCause::kCorrected, cw.source, cw.channel, cw.seq, now);
  }
  const std::span<const std::uint32_t> data = packet_data(image, d);
  if (cw.kind == FtKind::kData && cw.channel < kFtAllChannels && cw.source < n.routes.tiles) {
    on_data(n, cw, data);
  } else if (cw.channel == kFtControlChannel && !data.empty()) {
    on_control(n, cw, data, now);
  }
}

void take_image(FtNode& n, std::uint32_t payload_words, std::uint32_t now, bool tag_damaged) noexcept;

/** Receives one packet of @p queue into the scratch image. @return false if none. */
bool receive_one(FtNode& n, std::uint32_t queue, std::uint32_t now) noexcept {
  bsp::RxPacket rx{};
  const std::span<std::uint32_t> payload(n.scratch.data() + 2U, n.scratch.size() - 2U);
  if (n.port.receive(n.port.ctx, n.self, queue, rx, payload) != bsp::NetError::kOk) {
    return false;
  }
  take_image(n, rx.payload_words, now, queue != kFtQueue);
  return true;
}

/** Decodes the image whose payload (after the tag) is already in scratch[2 ..]. */
void take_image(FtNode& n, std::uint32_t payload_words, std::uint32_t now, bool tag_damaged) noexcept {
  if (payload_words > n.scratch.size() - 2U || payload_words < kFtMinPacketWords - 2U) {
    ++n.stats.uncorrectable_detected;  // cut or padded by a length flip beyond repair
    log_event(n, FtCause::kDamaged, bsp::kNoTile, 0U, 0U, now);
    return;
  }
  const auto x = static_cast<std::uint8_t>(n.self % n.routes.cols);
  const auto y = static_cast<std::uint8_t>(n.self / n.routes.cols);
  n.scratch[kWordHwHeader] = make_hw_header(x, y, static_cast<std::uint8_t>(payload_words + 1U));
  n.scratch[kWordHwTag] = kFtHwTag;
  handle_packet(n, std::span<std::uint32_t>(n.scratch.data(), payload_words + 2U), now, tag_damaged);
}

/**
 * Frees every send slot whose destination, channel or length no packet has
 * (an upset: they index the streams and bound the image), then counts each
 * destination's unacknowledged packets again from the slots (in_window is
 * that count whenever the node's state is whole). A freed slot's packet is
 * lost to the stream, which recovers by its timeout, give-up and resync.
 */
void check_tx(FtNode& n) noexcept {
  std::array<std::uint8_t, kRouteMaxTiles> window{};
  for (std::uint32_t i = 0U; i < kFtTxSlots; ++i) {
    detail::TxSlot& s = n.tx[i];
    if (!s.used) {
      continue;
    }
    if (s.dest >= n.routes.tiles || s.channel >= kFtAllChannels || s.words < kFtMinPacketWords ||
        s.words > kFtMaxPacketWords) {
      ft_report_repair(n, FtRepair::kTxSlot, i, (static_cast<std::uint32_t>(s.dest) << 24U) |
                                                    (static_cast<std::uint32_t>(s.channel) << 16U) | (s.words & 0xFFFFU));
      s.used = false;
      s.held = false;
      continue;
    }
    ++window[s.dest];
  }
  for (std::uint32_t d = 0U; d < kRouteMaxTiles; ++d) {
    if (n.in_window[d] != window[d]) {
      ft_report_repair(n, FtRepair::kWindow, d, n.in_window[d]);
      n.in_window[d] = window[d];
    }
  }
}

/** Empties every receive queue whose head or count is off its ring; sets the ready bits from the counts. */
void check_queues(FtNode& n) noexcept {
  std::uint32_t ready = 0U;
  for (std::uint32_t c = 0U; c < kFtAllChannels; ++c) {
    detail::RxQueue& q = n.rxq[c];
    if (q.head >= kFtRxDepth || q.count > kFtRxDepth) {
      ft_report_repair(n, FtRepair::kRxQueue, c, q.head >= kFtRxDepth ? q.head : q.count);
      q.head = 0U;
      q.count = 0U;
      n.rx_ready = static_cast<std::uint8_t>(static_cast<std::uint32_t>(n.rx_ready) & ~(1U << c));
    }
    ready |= (q.count != 0U ? 1U : 0U) << c;
  }
  if (ready != n.rx_ready) {
    ft_report_repair(n, FtRepair::kRxReady, 0U, n.rx_ready);
    n.rx_ready = static_cast<std::uint8_t>(ready);
  }
}

/** Frees every forward slot whose length no packet has, and every SYNC slot off the streams. */
void check_fwd_sync(FtNode& n) noexcept {
  for (std::uint32_t i = 0U; i < kFtFwdSlots; ++i) {
    detail::FwdSlot& f = n.fwd[i];
    if (f.used && (f.words < kFtMinPacketWords || f.words > kFtMaxPacketWords)) {
      ft_report_repair(n, FtRepair::kFwdSlot, i, f.words);
      f.used = false;
    }
  }
  for (std::uint32_t i = 0U; i < kFtSyncSlots; ++i) {
    detail::SyncSlot& y = n.sync[i];
    if (y.used && (y.dest >= n.routes.tiles || y.channel >= kFtAllChannels)) {
      ft_report_repair(n, FtRepair::kSyncSlot, i, (static_cast<std::uint32_t>(y.dest) << 8U) | y.channel);
      y.used = false;
    }
  }
}

/**
 * The node's state lives in its tile's RAM and can take an upset: every
 * index, count and length the node's operations follow is checked here, at
 * the start of each of them, and a value no valid state holds resets its part
 * (ft_report_repair). Whole state is left as it is, at no emulated cost.
 * @return false if the route table cannot be used (the owner rebuilds it):
 *         the operation does nothing.
 */
bool check_state(FtNode& n) noexcept {
  if (n.self == bsp::kNoTile || !ft_routes_ok(n)) {
    return false;
  }
  if (n.epoch >= kFtEpochs) {
    ft_report_repair(n, FtRepair::kEpoch, 0U, n.epoch);
    n.epoch = static_cast<std::uint8_t>(n.epoch % kFtEpochs);
  }
  check_tx(n);
  check_queues(n);
  check_fwd_sync(n);
  return true;
}

/** Clears a node member by member: a whole FtNode temporary would not fit a task's stack. */
void reset(FtNode& node) noexcept {
  node.stats = FtStats{};
  node.state_repairs = 0U;
  node.tx_hint = false;  // every slot is freed below
  node.fwd_hint = false;
  node.sync_hint = false;
  node.rx_ready = 0U;
  node.sink = FtEventSink{};
  node.map_version = 0U;
  node.epoch = 0U;
  node.peer_map_version.fill(0U);
  node.in_window.fill(0U);
  node.srtt8.fill(0U);
  node.rttvar4.fill(0U);
  node.rto_shift.fill(0U);
  for (detail::TxSlot& s : node.tx) {
    s.used = false;
    s.held = false;
  }
  for (auto& per_tile : node.tx_stream) {
    per_tile.fill(detail::TxStream{});
  }
  for (auto& per_tile : node.rx_stream) {
    per_tile.fill(detail::RxStream{});
  }
  for (detail::RxQueue& q : node.rxq) {
    q.head = 0U;
    q.count = 0U;
  }
  for (detail::FwdSlot& f : node.fwd) {
    f.used = false;
  }
  node.sync.fill(detail::SyncSlot{});
  node.acks_owed = 0U;
  node.busies_owed = 0U;
  node.held_streams = 0U;
  node.pong_owed.fill(0U);
  node.pongs_owed = 0U;
  node.pong_nonce.fill(0U);
}

}  // namespace

FtPort ft_task_port() noexcept { return FtPort{&task_send, &task_receive, nullptr, &task_credits}; }

FtError ft_init(FtNode& node, bsp::TileId self, const FaultMap& map, const FtPort& port,
                const FtConfig& config) noexcept {
  if (port.send == nullptr || port.receive == nullptr || self >= map.cols * map.rows) {
    return FtError::kBadArgs;
  }
  reset(node);
  node.self = self;
  node.port = port;
  node.config = config;
  bsp::Work work{};
  if (route_table_build(map, self, node.routes, work) != RouteError::kOk ||
      bsp::udn_net_bind(self, kFtHwTag, kFtQueue) != bsp::NetError::kOk) {
    return FtError::kBadArgs;
  }
  node.map_version = map.version;
  return FtError::kOk;
}

void ft_set_event_sink(FtNode& node, const FtEventSink& sink) noexcept { node.sink = sink; }

void ft_report_repair(FtNode& node, FtRepair what, std::uint32_t index, std::uint32_t value) noexcept {
  node.state_repairs = static_cast<std::uint16_t>(node.state_repairs + 1U);
  ft_event_emit(node.sink, node.self,
                FtEvent{0U, FtCause::kStateRepaired, static_cast<std::uint8_t>(what), 0U, index, value});
}

bool ft_routes_ok(const FtNode& node) noexcept {
  const RouteTable& r = node.routes;
  return r.tiles != 0U && r.tiles <= kRouteMaxTiles && r.cols != 0U && r.tiles % r.cols == 0U &&
         r.self == node.self && node.self < r.tiles;
}

void ft_set_epoch(FtNode& node, std::uint32_t epoch) noexcept {
  node.epoch = static_cast<std::uint8_t>(epoch % kFtEpochs);
}

FtError ft_set_fault_map(FtNode& node, const FaultMap& map, bsp::Work& work) noexcept {
  if (route_table_build(map, node.self, node.routes, work) != RouteError::kOk) {
    return FtError::kBadArgs;
  }
  node.map_version = map.version;
  return FtError::kOk;
}

FtError ft_send(FtNode& node, bsp::TileId dest, std::uint32_t channel, std::span<const std::uint32_t> data,
                std::uint32_t now_tick, bsp::TileId twin) noexcept {
  if (!check_state(node) || channel >= kFtAllChannels || dest >= node.routes.tiles || data.empty() ||
      data.size() > kFtMaxDataWords) {
    return FtError::kBadArgs;
  }
  bsp::TileId next = bsp::kNoTile;
  if (route_next_hop(node.routes, dest, next) != RouteError::kOk) {
    ++node.stats.unreachable;
    log_event(node, FtCause::kUnreachable, dest, channel, node.tx_stream[dest][channel].next_seq, now_tick,
              FtDelivery::kNotDelivered);  // refused: nothing was queued
    return FtError::kUnreachable;
  }
  detail::TxSlot* slot = nullptr;
  for (detail::TxSlot& s : node.tx) {
    slot = (slot == nullptr && !s.used) ? &s : slot;
  }
  if (slot == nullptr || node.in_window[dest] >= kFtWindow) {
    return FtError::kWindowFull;
  }
  detail::TxStream& st = node.tx_stream[dest][channel];
  const bool resync = st.resync && st.resync_seq == st.next_seq;
  const FtFields f{0U, 0U, static_cast<std::uint16_t>(dest), kFtHwTag,
                   ft_channel_word(node.self, st.next_seq, FtKind::kData, resync, channel, node.epoch), true};
  std::size_t written = 0U;
  if (encode_packet(f, data, slot->image, written) != EncodeStatus::kOk) {
    return FtError::kBadArgs;
  }
  // A resynchronising stream's packet waits in its slot for the SYNC-ACK; a held stream's
  // queues behind the held ones (sent now, it would arrive behind a gap).
  slot->words = static_cast<std::uint32_t>(written);
  slot->twin = twin < node.routes.tiles && twin != dest && twin != node.self ? static_cast<std::uint8_t>(twin) : 0xFFU;
  const FtError e = st.syncing || st.held ? FtError::kOk : send_slot(node, *slot, dest);
  if (e != FtError::kOk) {
    return e;  // nothing queued: the caller retries the same message
  }
  slot->used = true;
  node.tx_hint = true;
  slot->held = st.held && !st.syncing;
  slot->dest = static_cast<std::uint8_t>(dest);
  slot->channel = static_cast<std::uint8_t>(channel);
  slot->seq = st.next_seq;
  slot->retries = 0U;
  slot->sent_tick = now_tick;
  ++st.next_seq;
  ++node.in_window[dest];
  ++node.stats.sent;
  return FtError::kOk;
}

FtError ft_send_control(FtNode& node, bsp::TileId dest, FtKind kind, std::uint8_t seq, std::uint32_t word,
                        bool routed) noexcept {
  return send_control(node, dest, kind, seq, word, routed, 0U);
}

namespace {
FtError send_control(FtNode& node, bsp::TileId dest, FtKind kind, std::uint8_t seq, std::uint32_t word, bool routed,
                     std::uint8_t epoch, bool resync) noexcept {
  if (!ft_routes_ok(node) || dest >= node.routes.tiles) {
    return FtError::kBadArgs;
  }
  std::array<std::uint32_t, ft_packet_words(2U, true)> image{};
  const std::array<std::uint32_t, 2> words = {word, node.map_version};
  const bool versioned = kind == FtKind::kPing || kind == FtKind::kPong;
  const std::span<const std::uint32_t> data(words.data(), versioned ? 2U : 1U);
  const FtFields f{static_cast<std::uint8_t>(dest % node.routes.cols),
                   static_cast<std::uint8_t>(dest / node.routes.cols), static_cast<std::uint16_t>(dest), kFtHwTag,
                   ft_channel_word(node.self, seq, kind, resync, kFtControlChannel, epoch), true};
  std::size_t written = 0U;
  if (encode_packet(f, data, image, written) != EncodeStatus::kOk) {
    return FtError::kBadArgs;
  }
  const std::span<std::uint32_t> packet(image.data(), written);  // one or two data words
  const bool reply = kind != FtKind::kPing && kind != FtKind::kSync;
  if (routed) {
    return route_and_send(node, packet, dest, reply);
  }
  if (!reply && !room_beyond_reserve(node)) {
    return FtError::kNetFull;  // a probe is not a reply: the reserve stays for ACKs and PONGs
  }
  return (node.port.send(node.port.ctx, node.self, packet) == bsp::NetError::kOk) ? FtError::kOk
                                                                                    : FtError::kNetFull;
}
}  // namespace

std::uint32_t ft_poll(FtNode& node, std::uint32_t now_tick, std::uint32_t max_packets) noexcept {
  std::uint32_t handled = 0U;
  if (!check_state(node)) {
    return 0U;
  }
  (void)flush_forwards(node, now_tick);
  pay_acks(node);
  pay_pongs(node);
  send_all_held(node, now_tick);
  while (handled < max_packets &&
         (receive_one(node, kFtQueue, now_tick) || receive_one(node, bsp::kUdnCatchAll, now_tick))) {
    ++handled;
  }
  run_timers(node, now_tick);
  return handled;
}

void ft_accept(FtNode& node, std::span<const std::uint32_t> payload, std::uint32_t now_tick) noexcept {
  if (!check_state(node)) {
    return;
  }
  const std::size_t n = payload.size() < node.scratch.size() - 2U ? payload.size() : node.scratch.size() - 2U;
  for (std::size_t i = 0U; i < n; ++i) {
    node.scratch[2U + i] = payload[i];
  }
  take_image(node, static_cast<std::uint32_t>(payload.size()), now_tick, false);
}

FtError ft_receive(FtNode& node, std::uint32_t channel, FtMessage& out) noexcept {
  if (channel >= kFtAllChannels) {
    return FtError::kBadArgs;
  }
  if (((static_cast<std::uint32_t>(node.rx_ready) >> channel) & 1U) == 0U) {
    return FtError::kEmpty;  // the queue's count is 0: its line need not be read
  }
  check_queues(node);
  detail::RxQueue& q = node.rxq[channel];
  const auto ready = static_cast<std::uint8_t>(static_cast<std::uint32_t>(node.rx_ready) & ~(1U << channel));
  // A message whose source or length no message has (an upset of it in the queue) is dropped here.
  for (std::uint32_t i = 0U; i < kFtRxDepth && q.count > 0U; ++i) {
    out = q.msg[q.head];
    q.head = (q.head + 1U) % kFtRxDepth;
    --q.count;
    node.rx_ready = q.count == 0U ? ready : node.rx_ready;
    if (out.source < kRouteMaxTiles && out.data_words >= kFtMinDataWords && out.data_words <= kFtMaxDataWords) {
      out.channel = static_cast<std::uint8_t>(channel);
      return FtError::kOk;
    }
    ft_report_repair(node, FtRepair::kRxMessage, channel, (out.source << 16U) | out.data_words);
  }
  node.rx_ready = ready;
  return FtError::kEmpty;
}

bool ft_busy(const FtNode& node) noexcept {
  return node.tx_hint || node.fwd_hint || node.sync_hint || node.acks_owed != 0U || node.busies_owed != 0U ||
         node.held_streams != 0U || node.pongs_owed != 0U;
}

std::uint32_t ft_outstanding(const FtNode& node) noexcept {
  std::uint32_t n = 0U;
  for (const detail::TxSlot& s : node.tx) {
    n += s.used ? 1U : 0U;
  }
  for (const detail::SyncSlot& y : node.sync) {
    n += y.used ? 1U : 0U;
  }
  return n;
}

}  // namespace udn
