/**
 * @file udn_net.cpp
 * @brief The UDN mesh model: in-flight pool, barrier-time routing with link contention, demux queues.
 */
#include "bsp_tile64/emu/udn_net.hpp"

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/faults/fault_injector.hpp"
#include "bsp_tile64/emu/rng.hpp"
#include "bsp_tile64/emu/trace.hpp"

#include <algorithm>
#include <array>

namespace bsp {
namespace {

/** Stream index of the network's own fault draws inside StreamId::kFaults. */
constexpr std::uint64_t kNetRngIndex = 0x0DEU;
/** Port slots per tile: 4 output links and the ejection port into the tile. */
constexpr std::uint32_t kPorts = kUdnDirs + 1U;
constexpr std::uint32_t kEject = kUdnDirs;
/** Descriptors per demux queue: a queue is full when its words or its descriptors run out. */
constexpr std::uint32_t kQueueDescs = 32U;
constexpr std::uint32_t kArmedPerTile = 4U;
constexpr std::size_t kPoolSlots = std::size_t{kMaxTiles} * kUdnMaxInFlightPerTile;
/** Longest X-then-Y path in tiles on the largest grid. */
constexpr std::size_t kMaxPathTiles = std::size_t{2U} * kMaxTiles;

enum class Slot : std::uint8_t { kFree, kSent, kRouted };

struct Flight {
  Cycles send;
  Cycles arrival;
  std::uint64_t seq;
  TileId src;
  TileId dst;
  std::uint32_t words;  ///< header included, after any length corruption
  Slot state;
  std::array<std::uint32_t, kUdnMaxPacketWords> w;
};

struct Desc {
  TileId src;
  std::uint32_t tag;
  std::uint32_t payload;
  std::uint32_t start;  ///< index of the first payload word in the ring
  Cycles send;
  Cycles arrival;
  Cycles delivered;
};

struct Queue {
  std::array<std::uint32_t, kUdnMaxQueueWords> ring;
  std::array<Desc, kQueueDescs> desc;
  std::uint32_t desc_head;
  std::uint32_t desc_count;
  std::uint32_t word_tail;  ///< where the next payload word goes
  std::uint32_t words_used; ///< length words (tag + payload) held
};

struct Binding {
  std::uint32_t tag;
  std::uint32_t queue;
  bool used;
};

struct TileNet {
  std::array<Flight, kUdnMaxInFlightPerTile> pool;
  std::array<Queue, kUdnQueues> queue;
  std::array<Binding, kUdnTagBindings> bind;
  std::array<Cycles, kPorts> link_free;
  std::array<Cycles, kPorts> link_busy;
  std::array<bool, kUdnDirs> link_failed;
  std::array<FaultRecord*, kArmedPerTile> armed;
  std::uint32_t armed_count;
  std::uint32_t in_flight;
  std::uint64_t next_seq;
  bool switch_failed;
  bool refused;  ///< a send was refused: raise Irq::kUdn when a slot frees
};

struct Net {
  bool ready;
  std::uint32_t generation;
  std::uint32_t in_flight;  ///< over all tiles: an empty network costs a barrier nothing
  Cycles last_barrier;      ///< a second hook from a repeated init sees the same cycle and does nothing
  bool barrier_seen;
  NetConfig config;
  std::uint32_t cols;
  std::uint32_t rows;
  Cycles hop_cycles;
  double ber;
  Rng rng{1U, StreamId::kFaults, kNetRngIndex};
  NetStats stats;
  std::array<TileNet, kMaxTiles> tile;
  std::array<std::uint32_t, kPoolSlots> order;  ///< scratch: pool indices sorted at a barrier
  std::array<bool, std::size_t{kMaxTiles} * kUdnQueues> blocked;
  std::array<TileId, kMaxPathTiles> path;
};

Net g_net{};

Flight& flight_at(std::uint32_t index) noexcept {
  return g_net.tile[index / kUdnMaxInFlightPerTile].pool[index % kUdnMaxInFlightPerTile];
}

bool on_grid(TileId t) noexcept { return t < g_net.cols * g_net.rows; }

// ------------------------------------------------------------------ ordering

/** A pool index with its sort key: (key cycle, source, sequence), unique since sequences are per source. */
struct Keyed {
  Cycles key;
  std::uint64_t seq;
  std::uint32_t src;
  std::uint32_t index;
};

bool before(const Keyed& a, const Keyed& b) noexcept {
  if (a.key != b.key) {
    return a.key < b.key;
  }
  if (a.src != b.src) {
    return a.src < b.src;
  }
  return a.seq < b.seq;
}

/** Scratch of sort_order() (static: up to every pool slot). */
std::array<Keyed, kPoolSlots> g_keyed{};

/**
 * Orders the first @p n pool indices of g_net.order by (key cycle, source,
 * sequence). The keys are distinct, so any correct sort gives the one order;
 * std::sort because packets held back by full queues stay in the pool and
 * the lists reach a few hundred.
 */
void sort_order(std::uint32_t n, bool by_arrival) noexcept {
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t v = g_net.order[i];
    const Flight& f = flight_at(v);
    g_keyed[i] = Keyed{by_arrival ? f.arrival : f.send, f.seq, f.src, v};
  }
  // A lambda, not &before: std::sort inlines it (a function pointer costs an indirect call per compare).
  std::sort(g_keyed.begin(), g_keyed.begin() + n, [](const Keyed& a, const Keyed& b) noexcept { return before(a, b); });
  for (std::uint32_t i = 0; i < n; ++i) {
    g_net.order[i] = g_keyed[i].index;
  }
}

/** Collects the pool indices in @p state (and, for kRouted, arrived by @p barrier). */
std::uint32_t collect(Slot state, Cycles barrier) noexcept {
  std::uint32_t n = 0U;
  const std::uint32_t tiles = g_net.cols * g_net.rows;
  for (std::uint32_t t = 0; t < tiles; ++t) {
    const TileNet& tn = g_net.tile[t];
    if (tn.in_flight == 0U) {
      continue;  // no used slot: nothing to collect (a host shortcut, the same order)
    }
    for (std::uint32_t s = 0; s < g_net.config.max_in_flight_per_tile; ++s) {
      const Flight& f = tn.pool[s];
      if (f.state == state && (state != Slot::kRouted || f.arrival <= barrier)) {
        g_net.order[n++] = t * kUdnMaxInFlightPerTile + s;
      }
    }
  }
  return n;
}

// ------------------------------------------------------------------ leaving the network

void release(Flight& f) noexcept {
  f.state = Slot::kFree;
  TileNet& src = g_net.tile[f.src];
  --src.in_flight;
  --g_net.in_flight;
  if (src.refused) {
    src.refused = false;
    raise_irq(f.src, Irq::kUdn);  // the driver retries its refused send
  }
}

void lose(Flight& f, UdnLoss cause, Cycles barrier) noexcept {
  ++g_net.stats.lost[static_cast<std::size_t>(cause)];
  const std::uint64_t dst = on_grid(f.dst) ? f.dst : 0xFFU;
  trace_record(barrier, f.src, static_cast<std::uint16_t>(UdnTrace::kLost), static_cast<std::uint64_t>(cause),
               (f.seq << 8U) | dst);
  release(f);
}

// ------------------------------------------------------------------ faults in transit

void flip(Flight& f, std::uint32_t word, std::uint32_t bit, Cycles barrier) noexcept {
  f.w[word] ^= 1U << bit;
  ++g_net.stats.bit_flips;
  trace_record(barrier, f.src, static_cast<std::uint16_t>(UdnTrace::kBitFlip), word, bit);
}

/** An armed kPacketBitFlip of the source tile hits this packet (the next one it sends). */
void apply_armed(Flight& f, Cycles barrier) noexcept {
  TileNet& tn = g_net.tile[f.src];
  if (tn.armed_count == 0U) {
    return;
  }
  FaultRecord& r = *tn.armed[0];
  for (std::uint32_t i = 1; i < tn.armed_count; ++i) {
    tn.armed[i - 1U] = tn.armed[i];
  }
  --tn.armed_count;
  const std::uint32_t word = r.spec.offset == kRandomOffset ? static_cast<std::uint32_t>(g_net.rng.below(f.words))
                                                            : static_cast<std::uint32_t>(r.spec.offset % f.words);
  const std::uint32_t bit =
      r.spec.bit == kRandomBit ? static_cast<std::uint32_t>(g_net.rng.below(32U)) : r.spec.bit % 32U;
  flip(f, word, bit, barrier);
  r.status = FaultStatus::kApplied;
  r.applied_cycle = barrier;
  r.offset = word;
  r.bit = bit;
}

void apply_ber(Flight& f, Cycles barrier) noexcept {
  if (g_net.ber <= 0.0) {
    return;
  }
  for (std::uint32_t i = 0; i < f.words; ++i) {
    if (g_net.rng.bernoulli(g_net.ber)) {
      flip(f, i, static_cast<std::uint32_t>(g_net.rng.below(32U)), barrier);
    }
  }
}

/** Reads the (possibly corrupted) header: destination and resized length. @return false if lost. */
bool read_header(Flight& f, Cycles barrier) noexcept {
  const std::uint32_t h = f.w[0];
  const std::uint32_t x = udn_header_x(h);
  const std::uint32_t y = udn_header_y(h);
  f.dst = (x < g_net.cols && y < g_net.rows) ? y * g_net.cols + x : kNoTile;
  if (f.dst == kNoTile) {
    lose(f, UdnLoss::kOffGrid, barrier);
    return false;
  }
  const std::uint32_t len = udn_header_length(h);
  if (len < kUdnMinLength || len > kUdnMaxLength) {
    lose(f, UdnLoss::kBadLength, barrier);
    return false;
  }
  const std::uint32_t sent_len = f.words - 1U;
  if (len != sent_len) {
    // The switch forwards exactly `len` words: extra words stay behind, missing ones read as zero.
    if (len < sent_len) {
      g_net.stats.words_truncated += sent_len - len;
    } else {
      g_net.stats.words_padded += len - sent_len;
      for (std::uint32_t i = sent_len + 1U; i <= len; ++i) {
        f.w[i] = 0U;
      }
    }
    trace_record(barrier, f.src, static_cast<std::uint16_t>(UdnTrace::kResized), sent_len, len);
    f.words = len + 1U;
  }
  return true;
}

// ------------------------------------------------------------------ routing and timing

/** The loss cause of a path, or kCount if it is intact. */
UdnLoss path_fault(std::size_t tiles) noexcept {
  for (std::size_t k = 0; k < tiles; ++k) {
    const TileNet& tn = g_net.tile[g_net.path[k]];
    if (tn.switch_failed) {
      return UdnLoss::kFailedSwitch;
    }
    if (k + 1U < tiles && tn.link_failed[static_cast<std::size_t>(udn_dir(g_net.cols, g_net.path[k], g_net.path[k + 1U]))]) {
      return UdnLoss::kFailedLink;
    }
  }
  return UdnLoss::kCount;
}

/** Reserves the path's links and the ejection port in turn; sets the arrival cycle. */
void reserve(Flight& f, std::size_t tiles) noexcept {
  const Cycles w = f.words;
  Cycles t = f.send;
  for (std::size_t k = 0; k < tiles; ++k) {
    TileNet& tn = g_net.tile[g_net.path[k]];
    const std::size_t port =
        (k + 1U < tiles) ? static_cast<std::size_t>(udn_dir(g_net.cols, g_net.path[k], g_net.path[k + 1U])) : kEject;
    const Cycles head = t + g_net.hop_cycles;
    t = head > tn.link_free[port] ? head : tn.link_free[port];
    tn.link_free[port] = t + w;
    tn.link_busy[port] += w;
  }
  f.arrival = t + w;
}

void route_one(Flight& f, Cycles barrier) noexcept {
  apply_armed(f, barrier);
  apply_ber(f, barrier);
  if (!read_header(f, barrier)) {
    return;
  }
  const std::size_t tiles = udn_route(g_net.cols, g_net.rows, f.src, f.dst, g_net.path);
  const UdnLoss cause = path_fault(tiles);
  if (cause != UdnLoss::kCount) {
    lose(f, cause, barrier);
    return;
  }
  reserve(f, tiles);
  f.state = Slot::kRouted;
}

// ------------------------------------------------------------------ delivery

std::uint32_t queue_for(const TileNet& tn, std::uint32_t tag) noexcept {
  for (const Binding& b : tn.bind) {
    if (b.used && b.tag == tag) {
      return b.queue;
    }
  }
  return kUdnCatchAll;
}

bool has_room(const Queue& q, std::uint32_t length) noexcept {
  return q.desc_count < kQueueDescs && q.words_used + length <= g_net.config.queue_words;
}

void enqueue(Queue& q, const Flight& f, Cycles barrier) noexcept {
  const std::uint32_t cap = g_net.config.queue_words;
  const std::uint32_t payload = f.words - 2U;
  Desc& d = q.desc[(q.desc_head + q.desc_count) % kQueueDescs];
  d = Desc{f.src, f.w[1], payload, q.word_tail, f.send, f.arrival, barrier};
  // The ring wraps at most once (payload <= cap, word_tail < cap): two straight copies, no division per word.
  const std::uint32_t before_wrap = payload < cap - q.word_tail ? payload : cap - q.word_tail;
  for (std::uint32_t i = 0; i < before_wrap; ++i) {
    q.ring[q.word_tail + i] = f.w[2U + i];
  }
  for (std::uint32_t i = before_wrap; i < payload; ++i) {
    q.ring[i - before_wrap] = f.w[2U + i];
  }
  q.word_tail = (q.word_tail + payload) % cap;
  q.words_used += payload + 1U;
  ++q.desc_count;
}

void account_latency(const Flight& f) noexcept {
  NetStats& s = g_net.stats;
  const Cycles lat = f.arrival - f.send;
  s.latency_min = (s.delivered == 0U || lat < s.latency_min) ? lat : s.latency_min;
  s.latency_max = lat > s.latency_max ? lat : s.latency_max;
  s.latency_sum += lat;
  ++s.delivered;
}

void deliver(Cycles barrier) noexcept {
  const std::uint32_t n = collect(Slot::kRouted, barrier);
  sort_order(n, true);
  g_net.blocked.fill(false);
  for (std::uint32_t i = 0; i < n; ++i) {
    Flight& f = flight_at(g_net.order[i]);
    TileNet& dst = g_net.tile[f.dst];
    const std::uint32_t qi = queue_for(dst, f.w[1]);
    const std::size_t bi = static_cast<std::size_t>(f.dst) * kUdnQueues + qi;
    Queue& q = dst.queue[qi];
    if (g_net.blocked[bi] || !has_room(q, f.words - 1U)) {
      g_net.blocked[bi] = true;  // later packets for this queue wait too: order is kept
      ++g_net.stats.queue_full_retries;
      continue;
    }
    enqueue(q, f, barrier);
    account_latency(f);
    raise_irq(f.dst, Irq::kUdn);
    release(f);
  }
}

void on_barrier(Cycles barrier) noexcept {
  if (!g_net.ready || (g_net.barrier_seen && barrier == g_net.last_barrier)) {
    return;
  }
  g_net.barrier_seen = true;
  g_net.last_barrier = barrier;
  if (g_net.in_flight == 0U) {
    return;
  }
  const std::uint32_t n = collect(Slot::kSent, barrier);
  sort_order(n, false);
  for (std::uint32_t i = 0; i < n; ++i) {
    route_one(flight_at(g_net.order[i]), barrier);
  }
  deliver(barrier);
}

// ------------------------------------------------------------------ fault handlers

FaultStatus on_bit_flip(FaultRecord& rec, Rng& /*rng*/) noexcept {
  if (!on_grid(rec.spec.tile)) {
    return FaultStatus::kSkipped;
  }
  TileNet& tn = g_net.tile[rec.spec.tile];
  if (tn.armed_count >= kArmedPerTile) {
    return FaultStatus::kSkipped;
  }
  tn.armed[tn.armed_count++] = &rec;
  return FaultStatus::kArmed;
}

FaultStatus on_switch_fail(FaultRecord& rec, Rng& /*rng*/) noexcept {
  return udn_net_fail_switch(rec.spec.tile) == NetError::kOk ? FaultStatus::kApplied : FaultStatus::kSkipped;
}

FaultStatus on_link_fail(FaultRecord& rec, Rng& /*rng*/) noexcept {
  if (rec.spec.param >= kUdnDirs) {
    return FaultStatus::kSkipped;
  }
  const auto dir = static_cast<UdnDir>(rec.spec.param);
  return udn_net_fail_link(rec.spec.tile, dir) == NetError::kOk ? FaultStatus::kApplied : FaultStatus::kSkipped;
}

NetError reset_state(const NetConfig& config) noexcept {
  const ChipProfile& p = board_config().profile;
  g_net.config = config;
  g_net.cols = p.cols;
  g_net.rows = p.rows;
  g_net.hop_cycles = p.cost.hop_x16 / kCostScale + ((p.cost.hop_x16 % kCostScale) != 0U ? 1U : 0U);
  g_net.ber = 0.0;
  g_net.rng = Rng(board_config().seed, StreamId::kFaults, kNetRngIndex);
  g_net.stats = NetStats{};
  g_net.in_flight = 0U;
  g_net.barrier_seen = false;
  g_net.last_barrier = 0U;
  for (TileNet& tn : g_net.tile) {
    tn.pool.fill(Flight{});
    for (Queue& q : tn.queue) {  // the words need no clearing: only descriptors make them visible
      q.desc_head = 0U;
      q.desc_count = 0U;
      q.word_tail = 0U;
      q.words_used = 0U;
    }
    tn.bind.fill(Binding{});
    tn.link_free.fill(0U);
    tn.link_busy.fill(0U);
    tn.link_failed.fill(false);
    tn.armed_count = 0U;
    tn.in_flight = 0U;
    tn.next_seq = 0U;
    tn.switch_failed = false;
    tn.refused = false;
  }
  return NetError::kOk;
}

NetError send_at(TileId src, Cycles at, std::span<const std::uint32_t> words) noexcept {
  if (!g_net.ready) {
    return NetError::kNotInit;
  }
  if (!on_grid(src)) {
    return NetError::kBadTile;
  }
  if (words.size() < 1U + kUdnMinLength || words.size() > kUdnMaxPacketWords ||
      udn_header_length(words[0]) != words.size() - 1U) {
    return NetError::kBadLength;
  }
  TileNet& tn = g_net.tile[src];
  if (tn.in_flight >= g_net.config.max_in_flight_per_tile) {
    tn.refused = true;
    ++g_net.stats.refused_full;
    return NetError::kFull;
  }
  for (Flight& f : tn.pool) {
    if (f.state == Slot::kFree) {
      f.state = Slot::kSent;
      f.send = at;
      f.arrival = 0U;
      f.seq = tn.next_seq++;
      f.src = src;
      f.dst = kNoTile;
      f.words = static_cast<std::uint32_t>(words.size());
      for (std::size_t i = 0; i < words.size(); ++i) {
        f.w[i] = words[i];
      }
      ++tn.in_flight;
      ++g_net.in_flight;
      ++g_net.stats.sent;
      return NetError::kOk;
    }
  }
  return NetError::kFull;  // unreachable: in_flight counts the used slots
}

NetError pop(TileId tile, std::uint32_t queue, RxPacket& out, std::span<std::uint32_t> payload) noexcept {
  if (!g_net.ready) {
    return NetError::kNotInit;
  }
  if (!on_grid(tile)) {
    return NetError::kBadTile;
  }
  if (queue >= kUdnQueues) {
    return NetError::kBadQueue;
  }
  Queue& q = g_net.tile[tile].queue[queue];
  if (q.desc_count == 0U) {
    return NetError::kEmpty;
  }
  const Desc& d = q.desc[q.desc_head];
  const std::uint32_t cap = g_net.config.queue_words;
  const std::uint32_t n = d.payload < payload.size() ? d.payload : static_cast<std::uint32_t>(payload.size());
  const std::uint32_t before_wrap = n < cap - d.start ? n : cap - d.start;  // wraps at most once, as in enqueue()
  for (std::uint32_t i = 0; i < before_wrap; ++i) {
    payload[i] = q.ring[d.start + i];
  }
  for (std::uint32_t i = before_wrap; i < n; ++i) {
    payload[i] = q.ring[i - before_wrap];
  }
  out = RxPacket{d.src, d.tag, d.payload, d.send, d.arrival, d.delivered};
  q.words_used -= d.payload + 1U;
  q.desc_head = (q.desc_head + 1U) % kQueueDescs;
  --q.desc_count;
  return NetError::kOk;
}

}  // namespace

// ------------------------------------------------------------------ public API

NetError udn_net_init(const NetConfig& config) noexcept {
  g_net.ready = false;
  if (config.max_in_flight_per_tile == 0U || config.max_in_flight_per_tile > kUdnMaxInFlightPerTile ||
      config.queue_words < kUdnMaxLength || config.queue_words > kUdnMaxQueueWords) {
    return NetError::kBadConfig;
  }
  const ChipProfile& p = board_config().profile;
  if (p.cols > 0xFFU || p.rows > 0xFFU || p.tiles() > kMaxTiles || p.tiles() == 0U) {
    return NetError::kBadConfig;
  }
  if (reset_state(config) != NetError::kOk) {
    return NetError::kBadConfig;
  }
  if (add_barrier_hook(on_barrier) != BoardError::kOk) {
    return NetError::kFull;
  }
  const bool handlers_ok = fault_register_handler(FaultKind::kPacketBitFlip, on_bit_flip) == FaultError::kOk &&
                           fault_register_handler(FaultKind::kSwitchFail, on_switch_fail) == FaultError::kOk &&
                           fault_register_handler(FaultKind::kLinkFail, on_link_fail) == FaultError::kOk;
  if (!handlers_ok) {
    return NetError::kBadConfig;
  }
  ++g_net.generation;
  g_net.ready = true;
  return NetError::kOk;
}

Cycles udn_hop_cycles() noexcept { return g_net.hop_cycles; }

std::uint32_t udn_net_generation() noexcept { return g_net.generation; }

std::uint32_t udn_grid_cols() noexcept { return g_net.cols; }
std::uint32_t udn_grid_rows() noexcept { return g_net.rows; }

std::size_t udn_route(std::uint32_t cols, std::uint32_t rows, TileId src, TileId dst, std::span<TileId> out) noexcept {
  const std::uint32_t tiles = cols * rows;
  if (src >= tiles || dst >= tiles) {
    return 0U;
  }
  std::uint32_t x = src % cols;
  std::uint32_t y = src / cols;
  const std::uint32_t dx = dst % cols;
  const std::uint32_t dy = dst / cols;
  const std::size_t hops = (x > dx ? x - dx : dx - x) + (y > dy ? y - dy : dy - y);
  if (out.size() < hops + 1U) {
    return 0U;
  }
  std::size_t n = 0U;
  out[n++] = src;
  for (; x != dx; x = (x < dx) ? x + 1U : x - 1U) {  // X first ...
    out[n++] = y * cols + ((x < dx) ? x + 1U : x - 1U);
  }
  for (; y != dy; y = (y < dy) ? y + 1U : y - 1U) {  // ... then Y
    out[n++] = ((y < dy) ? y + 1U : y - 1U) * cols + x;
  }
  return n;
}

UdnDir udn_dir(std::uint32_t cols, TileId from, TileId to) noexcept {
  if (to == from + cols) {
    return UdnDir::kSouth;
  }
  if (to + cols == from) {
    return UdnDir::kNorth;
  }
  return to > from ? UdnDir::kEast : UdnDir::kWest;
}

NetError udn_net_send(std::span<const std::uint32_t> words) noexcept { return send_at(current_tile(), now(), words); }

NetError udn_net_send_from(TileId src, Cycles at, std::span<const std::uint32_t> words) noexcept {
  return send_at(src, at, words);
}

NetError udn_net_receive(std::uint32_t queue, RxPacket& out, std::span<std::uint32_t> payload) noexcept {
  return pop(current_tile(), queue, out, payload);
}

NetError udn_net_receive_on(TileId tile, std::uint32_t queue, RxPacket& out, std::span<std::uint32_t> payload) noexcept {
  return pop(tile, queue, out, payload);
}

std::uint32_t udn_net_queue_packets(TileId tile, std::uint32_t queue) noexcept {
  return (on_grid(tile) && queue < kUdnQueues) ? g_net.tile[tile].queue[queue].desc_count : 0U;
}

bool udn_net_can_send(TileId tile) noexcept {
  return on_grid(tile) && g_net.tile[tile].in_flight < g_net.config.max_in_flight_per_tile;
}

std::uint32_t udn_net_send_credits(TileId tile) noexcept {
  return (on_grid(tile) && g_net.tile[tile].in_flight < g_net.config.max_in_flight_per_tile)
             ? g_net.config.max_in_flight_per_tile - g_net.tile[tile].in_flight
             : 0U;
}

NetError udn_net_bind(TileId tile, std::uint32_t tag, std::uint32_t queue) noexcept {
  if (!on_grid(tile)) {
    return NetError::kBadTile;
  }
  if (queue >= kUdnDemuxQueues) {
    return NetError::kBadQueue;
  }
  TileNet& tn = g_net.tile[tile];
  for (Binding& b : tn.bind) {
    if (b.used && b.tag == tag) {
      b.queue = queue;
      return NetError::kOk;
    }
  }
  for (Binding& b : tn.bind) {
    if (!b.used) {
      b = Binding{tag, queue, true};
      return NetError::kOk;
    }
  }
  return NetError::kFull;
}

void udn_net_set_ber(double per_word_probability) noexcept {
  g_net.ber = per_word_probability < 0.0 ? 0.0 : (per_word_probability > 1.0 ? 1.0 : per_word_probability);
}

NetError udn_net_fail_switch(TileId tile) noexcept {
  if (!on_grid(tile)) {
    return NetError::kBadTile;
  }
  g_net.tile[tile].switch_failed = true;
  trace_record(board_time(), tile, static_cast<std::uint16_t>(UdnTrace::kSwitchFail), tile, 0U);
  return NetError::kOk;
}

NetError udn_net_fail_link(TileId tile, UdnDir dir) noexcept {
  if (!on_grid(tile) || static_cast<std::uint32_t>(dir) >= kUdnDirs) {
    return NetError::kBadTile;
  }
  // A physical link carries both directions: fail both halves.
  g_net.tile[tile].link_failed[static_cast<std::size_t>(dir)] = true;
  const std::uint32_t x = tile % g_net.cols;
  const std::uint32_t y = tile / g_net.cols;
  const bool has_peer = (dir == UdnDir::kEast && x + 1U < g_net.cols) || (dir == UdnDir::kWest && x > 0U) ||
                        (dir == UdnDir::kNorth && y > 0U) || (dir == UdnDir::kSouth && y + 1U < g_net.rows);
  if (has_peer) {
    static constexpr std::array<std::int32_t, kUdnDirs> kStepX{1, -1, 0, 0};
    static constexpr std::array<std::int32_t, kUdnDirs> kStepY{0, 0, -1, 1};
    static constexpr std::array<UdnDir, kUdnDirs> kOpposite{UdnDir::kWest, UdnDir::kEast, UdnDir::kSouth,
                                                            UdnDir::kNorth};
    const auto d = static_cast<std::size_t>(dir);
    const auto px = static_cast<std::uint32_t>(static_cast<std::int32_t>(x) + kStepX[d]);
    const auto py = static_cast<std::uint32_t>(static_cast<std::int32_t>(y) + kStepY[d]);
    g_net.tile[py * g_net.cols + px].link_failed[static_cast<std::size_t>(kOpposite[d])] = true;
  }
  trace_record(board_time(), tile, static_cast<std::uint16_t>(UdnTrace::kLinkFail), tile, static_cast<std::uint64_t>(dir));
  return NetError::kOk;
}

NetStats udn_net_stats() noexcept { return g_net.stats; }

Cycles udn_link_busy_cycles(TileId tile, UdnDir dir) noexcept {
  return on_grid(tile) ? g_net.tile[tile].link_busy[static_cast<std::size_t>(dir)] : 0U;
}

std::uint32_t udn_net_in_flight() noexcept { return g_net.in_flight; }

}  // namespace bsp
