/**
 * @file ft_link.hpp
 * @brief Fault-tolerant messaging node of one tile: listener, reliable channels, virtual routing.
 *
 * Every packet is a Fig. 5 image (udn/ft_packet.hpp) with the CRC word, sent
 * with hardware tag kFtHwTag bound to demux queue kFtQueue. The channel word
 * (word 4, covered by the route code) is laid out by this layer:
 *   [31..24] source tile index | [23..16] sequence (mod 256) |
 *   [15..12] kind (FtKind) | [11..9] epoch | [8] resync | [7..0] channel
 * Application channels are 0..kFtChannels-1, then three system channels
 * (kFtChanFdir, kFtChanMap, kFtChanHealth) for fault management; channel kFtControlChannel
 * carries the unreliable control kinds (ACK, NACK, PING, PONG, SYNC,
 * SYNC-ACK) whose data word 0 names the stream's channel (ACK, NACK, SYNC,
 * SYNC-ACK; an answer's with the receiver's resync record above it) or the
 * nonce (PING/PONG);
 * PING and PONG carry the sender's fault-map version in word 1, so a tile
 * that missed a map update is noticed by its neighbours' probes.
 *
 * Listener (ft_poll): rebuilds hardware words 0 and 1 (own x,y, delivered
 * count, kFtHwTag), decodes with CrcPolicy::kRequired, then
 *  - kOk/kCorrected: dispatch by kind; data is accepted only in sequence per
 *    (source, channel) into that channel's bounded receive queue and ACKed
 *    (cumulative); duplicates are dropped and re-ACKed; a gap is dropped and
 *    NACKed once; a full receive queue drops without ACK and answers BUSY
 *    (the sender resends on its timeout, as flow control, not a recovery:
 *    no event, counted in resent_busy; the packets behind it are dropped
 *    without a NACK until it is taken);
 *  - kMisdelivered: forwarded to the next hop of the protected destination
 *    index through this tile's route table (paper Fig. 6 intermediates use the
 *    same path); while the network refuses, up to kFtFwdSlots packets wait in
 *    the node; beyond that they are dropped (forward_failed) and the sender's
 *    timeout recovers them. The listener never stops reading: two forwarders
 *    waiting for each other's queues would deadlock;
 *  - kUncorrectable/kCrcMismatch/kMalformed: counted; if the route code alone
 *    checks clean, the source and sequence in word 4 are trusted and a NACK is
 *    sent, else the sender's timeout recovers.
 * An ACK the network refuses is owed and resent by the next polls.
 * Sender: per destination at most kFtWindow unacknowledged packets (from a
 * pool of kFtTxSlots); a packet is retransmitted go-back-N from the oldest
 * unacknowledged one of its stream on timeout or NACK, each time re-routed
 * through the current table; a retransmission the local network interface
 * refuses (back-pressure) is not counted as a retry, as it never left the
 * tile; after max_retries counted retries the stream's outstanding packets
 * are given up (each logged, delivery unknown) and the stream resynchronises
 * at its next sequence number R. While R is less than half the sequence
 * space minus two windows ahead of what the receiver last confirmed, the
 * packet with R carries the resync flag and the receiver restarts there.
 * Beyond that the flag could look like a duplicate: the next packets wait in
 * the node while a SYNC (control, seq R) asks the receiver to expect R; its
 * SYNC-ACK lets them go, and a SYNC unanswered after its retries gives up the
 * packets waiting for it (they never left the tile: not delivered) and takes
 * their sequence numbers back, so R stays where the receiver can take it
 * however many packets are given up in a row.
 * Give-ups settled: the receiver that takes a resync point (a flagged
 * packet or a SYNC) on a stream it was following records what it expected
 * then; every answer of the stream (ACK, NACK, SYNC-ACK) carries that record
 * in its data word ([7..0] channel, [8] record, [23..16] resync point,
 * [31..24] expected before it). The sender that gets the record of its own
 * resync point reports each packet it gave up as delivered (its ACKs were
 * lost) or not delivered.
 *
 * Restarts: a node's epoch (3 bits, ft_set_epoch: the endpoint takes the
 * tile's boot count) is in every data packet and SYNC, and an ACK, NACK or
 * SYNC-ACK carries the epoch of the stream it answers. A receive stream
 * starts (again) only at a SYNC or at a packet with the resync flag: a
 * fresh sender flags the first packet of each stream until it is
 * acknowledged. A receiver with no stream from the source (it restarted, or
 * the source did, with another epoch) answers an unflagged packet with a
 * resync request (a NACK with the flag): the sender flags its oldest
 * outstanding packet of the stream and resends from it, so a restarted
 * receiver joins a stream in progress without a loss and a restarted sender
 * is followed at once. A sender ignores ACKs and NACKs of another epoch (they
 * answer its previous incarnation).
 *
 * Time is in kernel ticks, passed by the caller (k::now_ticks() on a task).
 * The node talks to the network through an FtPort so the same code runs in a
 * driver task (ft_task_port) and host-driven tests. Static storage: the caller
 * owns the FtNode (a namespace-scope object per tile). See docs/FT_MESSAGING.md.
 */
#pragma once

#include "bsp_tile64/api/udn_driver.hpp"
#include "udn/ft_event.hpp"
#include "udn/ft_packet.hpp"
#include "udn/route.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace udn {

inline constexpr std::uint32_t kFtHwTag = 0x4654'0001U;  ///< hardware tag of every FT packet
inline constexpr std::uint32_t kFtQueue = 3U;            ///< demux queue it is bound to
inline constexpr std::uint32_t kFtChannels = 5U;         ///< application channels 0..4
inline constexpr std::uint32_t kFtChanFdir = kFtChannels;       ///< system: reports to fault-management tasks
inline constexpr std::uint32_t kFtChanMap = kFtChannels + 1U;   ///< system: fault maps, taken by the tile's endpoint
inline constexpr std::uint32_t kFtChanHealth = kFtChannels + 2U;  ///< system: boot reports to the tile-health supervisor
inline constexpr std::uint32_t kFtAllChannels = kFtChannels + 3U;  ///< application and system channels
inline constexpr std::uint32_t kFtControlChannel = 0xFFU;
/** Largest round trip the estimator takes, ticks (a sample beyond it counts as this). */
inline constexpr std::uint32_t kMaxRttTicks = 1000U;
inline constexpr std::uint32_t kFtWindow = 8U;    ///< unacknowledged packets per destination
inline constexpr std::uint32_t kFtTxSlots = 16U;  ///< retransmit buffers per tile
inline constexpr std::uint32_t kFtRxDepth = 8U;   ///< messages per channel receive queue
inline constexpr std::uint32_t kFtFwdSlots = 8U;  ///< packets held for forwarding while the network refuses
inline constexpr std::uint32_t kFtSyncSlots = kFtTxSlots;  ///< streams resynchronising at once (SYNC sent, no SYNC-ACK yet)
/**
 * Send credits kept for replies (ACK, NACK, PONG): data, forwards and PINGs
 * leave only while the network interface shows more than this many. Packets
 * towards a tile that stopped reading (a hung core) wait in the network for
 * its queue; without the reserve they would take every credit and the sender,
 * alive, would stop answering its neighbours' probes and be blamed. One
 * credit is enough for that; two starve the detour forwarders of a congested
 * mesh (docs/FT_MESSAGING.md).
 */
inline constexpr std::uint32_t kFtReplyReserve = 1U;
inline constexpr std::uint32_t kFtMaxData = static_cast<std::uint32_t>(kFtMaxDataWords);

/**
 * Packet kinds. kSync (sender to receiver, seq R): expect R next on the stream
 * of channel word 0; kSyncAck (receiver to sender, seq R): the receiver took it.
 */
enum class FtKind : std::uint8_t {
  kData = 0,
  kAck = 1,
  kNack = 2,
  kPing = 3,
  kPong = 4,
  kSync = 5,
  kSyncAck = 6,
  kBusy = 7,  ///< the packet with this seq came in order, and its channel's receive queue was full
};

enum class FtError : std::uint8_t {
  kOk,
  kBadArgs,      ///< channel, destination or length out of range, node not initialised
  kWindowFull,   ///< kFtWindow packets to this destination (or all slots) unacknowledged: poll and retry
  kUnreachable,  ///< no route to the destination (an event is logged)
  kNetFull,      ///< the network refused for back-pressure; nothing was queued: retry
  kEmpty,        ///< ft_receive: nothing on the channel
};

/** Sends and receives of the node, through the network. Plain function pointers, no heap. */
struct FtPort {
  bsp::NetError (*send)(void* ctx, bsp::TileId self, std::span<const std::uint32_t> words) = nullptr;
  bsp::NetError (*receive)(void* ctx, bsp::TileId self, std::uint32_t queue, bsp::RxPacket& rx,
                           std::span<std::uint32_t> payload) = nullptr;
  void* ctx = nullptr;
  /** Send credits left (bsp::udn_net_send_credits); nullptr: no reserve is kept (host tests). */
  std::uint32_t (*credits)(void* ctx, bsp::TileId self) = nullptr;
};

/** The port of a task on the current tile: udn_net_send / udn_net_receive. */
FtPort ft_task_port() noexcept;

struct FtConfig {
  std::uint32_t timeout_ticks = 3U;  ///< least first retransmit timeout (> a two-leg round trip; FtNode::srtt8); doubles per retry, at most x16
  std::uint32_t max_retries = 8U;    ///< retransmissions before giving up
};

struct FtStats {
  std::uint64_t sent = 0U;            ///< first transmissions of data packets
  std::uint64_t delivered = 0U;       ///< data messages put into a receive queue
  std::uint64_t corrected = 0U;       ///< packets with 1+ corrected bit (any status that decoded)
  std::uint64_t forwarded = 0U;       ///< packets re-sent towards their destination index
  std::uint64_t retransmitted = 0U;
  std::uint64_t twin_copies = 0U;     ///< copies of packets sent through their twin intermediate (ft_send)
  std::uint64_t uncorrectable_detected = 0U;  ///< kUncorrectable, kCrcMismatch or kMalformed
  std::uint64_t duplicates_dropped = 0U;
  std::uint64_t out_of_order_dropped = 0U;
  std::uint64_t rx_full_dropped = 0U;  ///< in order, but the channel's receive queue was full (a BUSY answered)
  std::uint64_t busy_sent = 0U;        ///< BUSY answers sent (flow control: the packet waits for room)
  std::uint64_t resent_busy = 0U;      ///< streams resent after their timeout because the receiver was busy (not logged)
  std::uint64_t forward_failed = 0U;  ///< no route or network refused; the sender's timeout recovers
  std::uint64_t acks_sent = 0U;
  std::uint64_t nacks_sent = 0U;
  std::uint64_t gave_up = 0U;         ///< packets given up (each logged): after retries, or waiting for a SYNC that failed
  std::uint64_t gave_up_unknown = 0U;        ///< ... left the tile, no ACK came back: delivery unknown
  std::uint64_t gave_up_not_delivered = 0U;  ///< ... never left the tile (waiting for a SYNC)
  std::uint64_t settled_delivered = 0U;      ///< given up, then the receiver's record showed it delivered (ACKs lost)
  std::uint64_t settled_not_delivered = 0U;  ///< given up, then the receiver's record showed it skipped
  std::uint64_t unreachable = 0U;     ///< sends refused for lack of a route
};

/** A message handed to the application. */
struct FtMessage {
  bsp::TileId source = bsp::kNoTile;
  std::uint8_t channel = 0U;
  std::uint8_t seq = 0U;
  std::uint16_t data_words = 0U;
  std::array<std::uint32_t, kFtMaxDataWords> data{};
};

/**
 * True if @p w is exactly a message of @p words words whose first word is
 * @p tag: the first test of every decoder of received words.
 */
constexpr bool is_message(std::span<const std::uint32_t> w, std::uint32_t tag, std::size_t words) noexcept {
  return w.size() == words && words > 0U && w[0] == tag;
}

namespace detail {
struct TxSlot {
  bool used = false;
  bool held = false;  ///< not on its way: behind a resend the network refused, it leaves in order with the next polls
  std::uint8_t dest = 0U;
  std::uint8_t channel = 0U;
  std::uint8_t seq = 0U;
  std::uint32_t retries = 0U;
  std::uint32_t sent_tick = 0U;
  std::uint32_t words = 0U;
  std::uint8_t twin = 0xFFU;  ///< intermediate every transmission also goes through as a copy (0xFF: none)
  std::array<std::uint32_t, kFtMaxPacketWords> image{};
};
struct TxStream {
  std::uint8_t next_seq = 0U;
  std::uint8_t resync_seq = 0U;
  bool resync = true;  ///< the packet with resync_seq carries the resync flag (a new stream's first does)
  bool syncing = false;  ///< new packets wait in their slots until a SYNC is acknowledged
  std::uint8_t confirmed = 0U;  ///< what the receiver expected as last confirmed (an answer); it expects no less
  bool settle_pending = false;  ///< packets given up whose delivery the resync point's answer will tell
  std::uint8_t settle_from = 0U;   ///< the first of them
  std::uint8_t settle_point = 0U;  ///< the resync point that follows them
  bool busy = false;          ///< the receiver answered BUSY for busy_seq: its timeout resend is flow control
  std::uint8_t busy_seq = 0U;
  bool held = false;          ///< some of its slots are held (TxSlot::held): new packets queue behind them
  bool held_report = false;   ///< a resend the network refused whole: reported (held_why) when its first packet leaves
  std::uint8_t held_why = 0U; ///< the FtCause of that resend
};
/** A stream resynchronising after a give-up: its SYNC, resent on timeout like a data packet. */
struct SyncSlot {
  bool used = false;
  std::uint8_t dest = 0U;
  std::uint8_t channel = 0U;
  std::uint8_t start = 0U;  ///< R: the sequence number the receiver is asked to expect
  std::uint32_t retries = 0U;
  std::uint32_t sent_tick = 0U;
};
struct RxStream {
  bool synced = false;     ///< a packet was accepted since ft_init
  bool resync_asked = false;  ///< a resync request was sent for the stream not yet started
  std::uint8_t epoch = 0U; ///< the sender's epoch this stream follows
  std::uint8_t expected = 0U;
  std::uint8_t nacked = 0U;
  bool nack_sent = false;
  bool busy = false;  ///< `expected` came with the receive queue full (answered BUSY): no NACKs for the gap behind it
  bool busy_owed = false;  ///< the network refused that BUSY: resent by the next poll while the queue is still full
  bool ack_owed = false;  ///< the network refused the last ACK: resent by the next poll
  bool rec_valid = false;  ///< a resync point was taken while the stream ran: its record goes in every answer
  std::uint8_t rec_point = 0U;  ///< that resync point
  std::uint8_t rec_from = 0U;   ///< what the stream expected when it took it (the packets from there on were skipped)
};
struct FwdSlot {
  bool used = false;
  std::uint16_t dest = 0U;
  std::uint32_t words = 0U;
  std::uint8_t twin = 0xFFU;  ///< intermediate every transmission also goes through as a copy (0xFF: none)
  std::array<std::uint32_t, kFtMaxPacketWords> image{};
};
struct RxQueue {
  std::uint32_t head = 0U;
  std::uint32_t count = 0U;
  std::array<FtMessage, kFtRxDepth> msg{};
};
}  // namespace detail

/*
 * What an upset of a node does (bsp::ControlLayout): the node is the tile's
 * own state but for its port and event sink (host function pointers and
 * their contexts). Every index, count and length in it is checked before it
 * is used (ft_check_state): a value no valid state holds resets its part.
 */
inline constexpr std::array kFtConfigFields{BSP_CONTROL_STATE(FtConfig, timeout_ticks),
                                            BSP_CONTROL_STATE(FtConfig, max_retries)};
inline constexpr bsp::ControlLayout kFtConfigLayout{kFtConfigFields, sizeof(FtConfig), alignof(FtConfig)};
static_assert(bsp::control_layout_ok(kFtConfigLayout), "every member of FtConfig");

inline constexpr std::array kFtStatsFields{
    BSP_CONTROL_STATE(FtStats, sent),
    BSP_CONTROL_STATE(FtStats, delivered),
    BSP_CONTROL_STATE(FtStats, corrected),
    BSP_CONTROL_STATE(FtStats, forwarded),
    BSP_CONTROL_STATE(FtStats, retransmitted),
    BSP_CONTROL_STATE(FtStats, twin_copies),
    BSP_CONTROL_STATE(FtStats, uncorrectable_detected),
    BSP_CONTROL_STATE(FtStats, duplicates_dropped),
    BSP_CONTROL_STATE(FtStats, out_of_order_dropped),
    BSP_CONTROL_STATE(FtStats, rx_full_dropped),
    BSP_CONTROL_STATE(FtStats, busy_sent),
    BSP_CONTROL_STATE(FtStats, resent_busy),
    BSP_CONTROL_STATE(FtStats, forward_failed),
    BSP_CONTROL_STATE(FtStats, acks_sent),
    BSP_CONTROL_STATE(FtStats, nacks_sent),
    BSP_CONTROL_STATE(FtStats, gave_up),
    BSP_CONTROL_STATE(FtStats, gave_up_unknown),
    BSP_CONTROL_STATE(FtStats, gave_up_not_delivered),
    BSP_CONTROL_STATE(FtStats, settled_delivered),
    BSP_CONTROL_STATE(FtStats, settled_not_delivered),
    BSP_CONTROL_STATE(FtStats, unreachable),
};
inline constexpr bsp::ControlLayout kFtStatsLayout{kFtStatsFields, sizeof(FtStats), alignof(FtStats)};
static_assert(bsp::control_layout_ok(kFtStatsLayout), "every member of FtStats");

/** A received message: its source and length are checked when it is taken (ft_receive), its words are data. */
inline constexpr std::array kFtMessageFields{BSP_CONTROL_STATE(FtMessage, source), BSP_CONTROL_STATE(FtMessage, channel),
                                             BSP_CONTROL_STATE(FtMessage, seq), BSP_CONTROL_STATE(FtMessage, data_words),
                                             BSP_CONTROL_STATE(FtMessage, data)};
inline constexpr bsp::ControlLayout kFtMessageLayout{kFtMessageFields, sizeof(FtMessage), alignof(FtMessage)};
static_assert(bsp::control_layout_ok(kFtMessageLayout), "every member of FtMessage");

namespace detail {
inline constexpr std::array kTxSlotFields{
    BSP_CONTROL_STATE(TxSlot, used),    BSP_CONTROL_STATE(TxSlot, held),      BSP_CONTROL_STATE(TxSlot, dest),
    BSP_CONTROL_STATE(TxSlot, channel), BSP_CONTROL_STATE(TxSlot, seq),       BSP_CONTROL_STATE(TxSlot, retries),
    BSP_CONTROL_STATE(TxSlot, sent_tick), BSP_CONTROL_STATE(TxSlot, words),   BSP_CONTROL_STATE(TxSlot, twin),
    BSP_CONTROL_STATE(TxSlot, image),
};
inline constexpr bsp::ControlLayout kTxSlotLayout{kTxSlotFields, sizeof(TxSlot), alignof(TxSlot)};
static_assert(bsp::control_layout_ok(kTxSlotLayout), "every member of TxSlot");

inline constexpr std::array kTxStreamFields{
    BSP_CONTROL_STATE(TxStream, next_seq),     BSP_CONTROL_STATE(TxStream, resync_seq),
    BSP_CONTROL_STATE(TxStream, resync),       BSP_CONTROL_STATE(TxStream, syncing),
    BSP_CONTROL_STATE(TxStream, confirmed),    BSP_CONTROL_STATE(TxStream, settle_pending),
    BSP_CONTROL_STATE(TxStream, settle_from),  BSP_CONTROL_STATE(TxStream, settle_point),
    BSP_CONTROL_STATE(TxStream, busy),         BSP_CONTROL_STATE(TxStream, busy_seq),
    BSP_CONTROL_STATE(TxStream, held),         BSP_CONTROL_STATE(TxStream, held_report),
    BSP_CONTROL_STATE(TxStream, held_why),
};
inline constexpr bsp::ControlLayout kTxStreamLayout{kTxStreamFields, sizeof(TxStream), alignof(TxStream)};
static_assert(bsp::control_layout_ok(kTxStreamLayout), "every member of TxStream");

inline constexpr std::array kSyncSlotFields{BSP_CONTROL_STATE(SyncSlot, used),    BSP_CONTROL_STATE(SyncSlot, dest),
                                            BSP_CONTROL_STATE(SyncSlot, channel), BSP_CONTROL_STATE(SyncSlot, start),
                                            BSP_CONTROL_STATE(SyncSlot, retries), BSP_CONTROL_STATE(SyncSlot, sent_tick)};
inline constexpr bsp::ControlLayout kSyncSlotLayout{kSyncSlotFields, sizeof(SyncSlot), alignof(SyncSlot)};
static_assert(bsp::control_layout_ok(kSyncSlotLayout), "every member of SyncSlot");

inline constexpr std::array kRxStreamFields{
    BSP_CONTROL_STATE(RxStream, synced),    BSP_CONTROL_STATE(RxStream, resync_asked), BSP_CONTROL_STATE(RxStream, epoch),
    BSP_CONTROL_STATE(RxStream, expected),  BSP_CONTROL_STATE(RxStream, nacked),       BSP_CONTROL_STATE(RxStream, nack_sent),
    BSP_CONTROL_STATE(RxStream, busy),      BSP_CONTROL_STATE(RxStream, busy_owed),    BSP_CONTROL_STATE(RxStream, ack_owed),
    BSP_CONTROL_STATE(RxStream, rec_valid), BSP_CONTROL_STATE(RxStream, rec_point),    BSP_CONTROL_STATE(RxStream, rec_from),
};
inline constexpr bsp::ControlLayout kRxStreamLayout{kRxStreamFields, sizeof(RxStream), alignof(RxStream)};
static_assert(bsp::control_layout_ok(kRxStreamLayout), "every member of RxStream");

inline constexpr std::array kFwdSlotFields{BSP_CONTROL_STATE(FwdSlot, used), BSP_CONTROL_STATE(FwdSlot, dest),
                                           BSP_CONTROL_STATE(FwdSlot, words), BSP_CONTROL_STATE(FwdSlot, twin),
                                           BSP_CONTROL_STATE(FwdSlot, image)};
inline constexpr bsp::ControlLayout kFwdSlotLayout{kFwdSlotFields, sizeof(FwdSlot), alignof(FwdSlot)};
static_assert(bsp::control_layout_ok(kFwdSlotLayout), "every member of FwdSlot");

inline constexpr std::array kRxQueueFields{BSP_CONTROL_STATE(RxQueue, head), BSP_CONTROL_STATE(RxQueue, count),
                                           BSP_CONTROL_NESTED(RxQueue, msg, kFtMessageLayout)};
inline constexpr bsp::ControlLayout kRxQueueLayout{kRxQueueFields, sizeof(RxQueue), alignof(RxQueue)};
static_assert(bsp::control_layout_ok(kRxQueueLayout), "every member of RxQueue");
}  // namespace detail

struct FtNode {
  bsp::TileId self = bsp::kNoTile;
  /**
   * Where ft_poll has work, in the padding after `self` (the members after
   * it keep their offsets). A hint is true whenever a slot of its kind is
   * used: it is set where a slot is taken and cleared by the poll's scan
   * when that finds none, so an idle poll reads this word instead of every
   * slot. It may stay true a poll longer than a slot (the next scan clears it).
   */
  bool tx_hint = false;    ///< some TxSlot may be used
  bool fwd_hint = false;   ///< some FwdSlot may be used
  bool sync_hint = false;  ///< some SyncSlot may be used
  std::uint8_t rx_ready = 0U;  ///< bit c: rxq[c] holds a message (exact)
  static_assert(kFtAllChannels <= 8U, "rx_ready has a bit per channel");
  FtPort port{};
  FtConfig config{};
  RouteTable routes{};
  FtStats stats{};
  FtEventSink sink{};                ///< where events go (ft_set_event_sink); none: only counted
  std::uint8_t epoch = 0U;           ///< this incarnation of the node (ft_set_epoch), 0..7
  /** Parts of the node's (and its endpoint's) state found upset and reset (FtCause::kStateRepaired), mod 2^16; in padding. */
  std::uint16_t state_repairs = 0U;
  std::uint32_t map_version = 0U;    ///< version of the fault map the routes were built from
  std::array<std::uint32_t, kRouteMaxTiles> peer_map_version{};  ///< last version a PING or PONG carried, per tile
  std::array<std::uint8_t, kRouteMaxTiles> in_window{};  ///< unacknowledged packets per destination
  /**
   * Round trip to each destination, ticks (RFC 6298 with integer state):
   * srtt x 8 and rttvar x 4, from the ACKs of packets sent once (Karn); 0: no
   * sample yet. The first retransmit timeout is srtt + max(1, 4 rttvar), at
   * least config.timeout_ticks: a destination that answers slowly (its
   * network interface full, its listener behind) is not resent to in vain.
   */
  std::array<std::uint16_t, kRouteMaxTiles> srtt8{};
  std::array<std::uint16_t, kRouteMaxTiles> rttvar4{};
  /**
   * Doublings of that timeout since the destination's last sample (a timeout
   * resend adds one, at most 4): Karn's rule takes no sample from a resent
   * packet, so without them a round trip longer than the timeout would never be measured.
   */
  std::array<std::uint8_t, kRouteMaxTiles> rto_shift{};
  std::array<detail::TxSlot, kFtTxSlots> tx{};
  std::array<std::array<detail::TxStream, kFtAllChannels>, kRouteMaxTiles> tx_stream{};
  std::array<std::array<detail::RxStream, kFtAllChannels>, kRouteMaxTiles> rx_stream{};
  std::array<detail::RxQueue, kFtAllChannels> rxq{};
  std::array<detail::FwdSlot, kFtFwdSlots> fwd{};
  std::array<detail::SyncSlot, kFtSyncSlots> sync{};
  std::uint32_t acks_owed = 0U;
  std::uint32_t busies_owed = 0U;  ///< receive streams with busy_owed
  std::uint32_t held_streams = 0U;  ///< send streams with TxStream::held
  std::array<std::uint32_t, kRouteMaxTiles> pong_nonce{};  ///< last PONG nonce seen per source tile
  std::array<std::uint32_t, kRouteMaxTiles> pong_owed{};   ///< nonce of a PONG the network refused, per prober (0: none)
  std::uint32_t pongs_owed = 0U;
  std::array<std::uint32_t, kFtMaxPacketWords> scratch{};  ///< one packet image being decoded
};

/** An FtNode in a tile's RAM (bsp::ControlLayout): host state only its port and its sink. */
inline constexpr std::array kFtNodeFields{
    BSP_CONTROL_STATE(FtNode, self),
    BSP_CONTROL_STATE(FtNode, tx_hint),
    BSP_CONTROL_STATE(FtNode, fwd_hint),
    BSP_CONTROL_STATE(FtNode, sync_hint),
    BSP_CONTROL_STATE(FtNode, rx_ready),
    BSP_CONTROL_HOST(FtNode, port),
    BSP_CONTROL_NESTED(FtNode, config, kFtConfigLayout),
    BSP_CONTROL_NESTED(FtNode, routes, kRouteTableLayout),
    BSP_CONTROL_NESTED(FtNode, stats, kFtStatsLayout),
    BSP_CONTROL_HOST(FtNode, sink),
    BSP_CONTROL_STATE(FtNode, epoch),
    BSP_CONTROL_STATE(FtNode, state_repairs),
    BSP_CONTROL_STATE(FtNode, map_version),
    BSP_CONTROL_STATE(FtNode, peer_map_version),
    BSP_CONTROL_STATE(FtNode, in_window),
    BSP_CONTROL_STATE(FtNode, srtt8),
    BSP_CONTROL_STATE(FtNode, rttvar4),
    BSP_CONTROL_STATE(FtNode, rto_shift),
    BSP_CONTROL_NESTED(FtNode, tx, detail::kTxSlotLayout),
    BSP_CONTROL_NESTED(FtNode, tx_stream, detail::kTxStreamLayout),
    BSP_CONTROL_NESTED(FtNode, rx_stream, detail::kRxStreamLayout),
    BSP_CONTROL_NESTED(FtNode, rxq, detail::kRxQueueLayout),
    BSP_CONTROL_NESTED(FtNode, fwd, detail::kFwdSlotLayout),
    BSP_CONTROL_NESTED(FtNode, sync, detail::kSyncSlotLayout),
    BSP_CONTROL_STATE(FtNode, acks_owed),
    BSP_CONTROL_STATE(FtNode, busies_owed),
    BSP_CONTROL_STATE(FtNode, held_streams),
    BSP_CONTROL_STATE(FtNode, pong_nonce),
    BSP_CONTROL_STATE(FtNode, pong_owed),
    BSP_CONTROL_STATE(FtNode, pongs_owed),
    BSP_CONTROL_STATE(FtNode, scratch),
};
inline constexpr bsp::ControlLayout kFtNodeLayout{kFtNodeFields, sizeof(FtNode), alignof(FtNode)};
static_assert(bsp::control_layout_ok(kFtNodeLayout), "every member of FtNode");

/** Which part of a node's or an endpoint's state a check found upset (FtEvent::channel of kStateRepaired). */
enum class FtRepair : std::uint8_t {
  kRoutes = 1,     ///< the route table's grid or tile: the owner rebuilds it from its map (ft_routes_ok)
  kSelf = 2,       ///< the node's tile: set again, the routes rebuilt
  kEpoch = 3,      ///< the epoch beyond its 3 bits: taken mod kFtEpochs
  kTxSlot = 4,     ///< a send slot's destination, channel or length: freed (its stream recovers by give-up and resync)
  kWindow = 5,     ///< a destination's count of unacknowledged packets: counted again from the slots
  kRxQueue = 6,    ///< a receive queue's head or count: emptied (its messages lost)
  kRxReady = 7,    ///< the queues-ready bits: computed again from the counts
  kRxMessage = 8,  ///< a queued message's source or length: dropped when taken
  kFwdSlot = 9,    ///< a forward slot's length: dropped (the sender's timeout recovers the packet)
  kSyncSlot = 10,  ///< a SYNC slot's destination or channel: freed (its stream starts another SYNC)
  kMap = 11,       ///< the endpoint's fault map has another grid: the boot map again, newer ones catch up
  kPending = 12,   ///< the endpoint's count of reports to send: cleared (they are sent again every kReReportRounds)
  kTransit = 13,   ///< the endpoint's transit probes (count or target): planned again from its configuration
  kProbe = 14,     ///< the neighbour probe (a neighbour off the grid, its threshold): set up again
};

/**
 * Counts a repair of @p node's own state (FtNode::state_repairs) and reports it
 * to its sink (FtCause::kStateRepaired) with the part @p index and the @p value found.
 */
void ft_report_repair(FtNode& node, FtRepair what, std::uint32_t index, std::uint32_t value) noexcept;

/**
 * True if @p node's route table can be used: a grid of 1 to kRouteMaxTiles
 * tiles, whole rows, the node's own tile on it. An upset of the table's grid
 * makes every node operation refuse (ft_poll handles nothing, ft_send kBadArgs)
 * until the owner rebuilds it (ft_set_fault_map): the node holds no map.
 */
bool ft_routes_ok(const FtNode& node) noexcept;

/**
 * Resets @p node for tile @p self, builds its routes from @p map and binds
 * kFtHwTag to kFtQueue on the tile. Pre: udn_net_init() on the current board.
 * [task|host] @return kBadArgs for self off the map, a null port, or a failed bind.
 */
FtError ft_init(FtNode& node, bsp::TileId self, const FaultMap& map, const FtPort& port,
                const FtConfig& config) noexcept;

/** Number of distinct epochs (3 bits of the channel word). */
inline constexpr std::uint32_t kFtEpochs = 8U;

/**
 * Sets the node's epoch (taken mod kFtEpochs; ft_init sets 0). A node that
 * restarts must come back with another epoch than its previous incarnation
 * (the endpoint uses the tile's boot count), so its peers restart its streams.
 */
void ft_set_epoch(FtNode& node, std::uint32_t epoch) noexcept;

/** Sends the node's events to @p sink from now on (ft_init clears it). */
void ft_set_event_sink(FtNode& node, const FtEventSink& sink) noexcept;

/** Rebuilds the route table from a new fault map version; traffic in flight is recovered by retransmission. */
FtError ft_set_fault_map(FtNode& node, const FaultMap& map, bsp::Work& work) noexcept;

/**
 * Sends @p data (1..kFtMaxData words) reliably on @p channel to @p dest.
 * With @p twin a tile (route_twin_via), every transmission of the packet
 * (first, resends) also goes as a copy through that intermediate, which
 * forwards it: the receiver takes the first to arrive and drops the other as
 * a duplicate, so one fault on either way loses nothing (as IEC 62439-3 PRP
 * sends every frame over two networks). A copy the network refuses is not
 * waited for.
 * @return kOk (queued and sent), kWindowFull, kUnreachable, kNetFull, kBadArgs.
 */
FtError ft_send(FtNode& node, bsp::TileId dest, std::uint32_t channel, std::span<const std::uint32_t> data,
                std::uint32_t now_tick, bsp::TileId twin = bsp::kNoTile) noexcept;

/**
 * Sends one unreliable control packet (kind, seq, data word 0 = @p word; PING and PONG add the
 * node's map version as word 1) to @p dest, straight (one XY leg) or @p routed through the table.
 */
FtError ft_send_control(FtNode& node, bsp::TileId dest, FtKind kind, std::uint8_t seq, std::uint32_t word,
                        bool routed) noexcept;

/**
 * The listener and the timers: handles at most @p max_packets received packets
 * (FT queue, then the catch-all where header flips land), then retransmits or
 * gives up timed-out streams. Call it every tick or on Irq::kUdn.
 * @return packets handled.
 */
std::uint32_t ft_poll(FtNode& node, std::uint32_t now_tick, std::uint32_t max_packets) noexcept;

/**
 * Hands the listener one packet the caller already took from kFtQueue or the
 * catch-all queue (e.g. a driver task blocked in udn::receive to sleep until
 * traffic comes): @p payload is what followed the hardware tag word.
 * Packets longer than kFtMaxPacketWords - 2 words are counted as damaged.
 */
void ft_accept(FtNode& node, std::span<const std::uint32_t> payload, std::uint32_t now_tick) noexcept;

/** Pops the oldest message of @p channel. @return kOk, kEmpty, kBadArgs. */
FtError ft_receive(FtNode& node, std::uint32_t channel, FtMessage& out) noexcept;

/** Unacknowledged packets and unanswered SYNCs of the node (0 once everything is delivered or given up). */
std::uint32_t ft_outstanding(const FtNode& node) noexcept;

/**
 * True if the node's next ft_poll has work whatever arrives: packets in its
 * send window or held, SYNCs, forwards, or ACKs, BUSYs or PONGs still owed.
 * A node that is not busy needs a poll only when a packet arrives.
 */
[[nodiscard]] bool ft_busy(const FtNode& node) noexcept;

/** Channel word of a packet (see the file comment). */
constexpr std::uint32_t ft_channel_word(std::uint32_t source, std::uint8_t seq, FtKind kind, bool resync,
                                        std::uint32_t channel, std::uint32_t epoch = 0U) noexcept {
  return ((source & 0xFFU) << 24U) | (static_cast<std::uint32_t>(seq) << 16U) |
         (static_cast<std::uint32_t>(kind) << 12U) | ((epoch % kFtEpochs) << 9U) | ((resync ? 1U : 0U) << 8U) |
         (channel & 0xFFU);
}

}  // namespace udn
