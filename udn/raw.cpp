/**
 * @file raw.cpp
 * @brief The raw UDN API: kernel semaphores given from the UDN interrupt hook, bounded retry loops.
 */
#include "udn/raw.hpp"

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"
#include "kernel/kernel.hpp"

#include <array>

namespace udn {
namespace {

/** Per-tile state. Binary semaphores: a give means "look again", the queue itself holds the count. */
struct TileRaw {
  std::array<k::Semaphore, kQueues> rx{k::Semaphore{0U, 1U}, k::Semaphore{0U, 1U}, k::Semaphore{0U, 1U},
                                       k::Semaphore{0U, 1U}, k::Semaphore{0U, 1U}};
  k::Semaphore tx{0U, 1U};
  bool active = false;
  std::uint32_t generation = 0U;  ///< network generation at activate(): a new board deactivates
};

std::array<TileRaw, bsp::kMaxTiles> g_raw{};

/**
 * Every wait consumes a give or ends in a timeout, and gives come at most once
 * per barrier per semaphore, so this bound is only reached by a broken network.
 */
constexpr std::uint32_t kMaxAttempts = 1U << 20U;

/** Gives that the kernel refused (would mean a hook outside the kernel's handler). */
std::uint32_t g_give_errors = 0U;

/** Gives a binary semaphore if it is not already given. */
void signal(k::Semaphore& s) noexcept {
  if (s.count() == 0U) {
    const k::Status st = s.give_from_isr();
    if (st != k::Status::kOk && st != k::Status::kExhausted) {
      ++g_give_errors;
    }
  }
}

void on_udn_irq(bsp::TileId tile) noexcept {
  if (tile >= bsp::kMaxTiles || !g_raw[tile].active || g_raw[tile].generation != bsp::udn_net_generation()) {
    return;
  }
  TileRaw& r = g_raw[tile];
  for (std::uint32_t q = 0; q < kQueues; ++q) {
    if (bsp::udn_net_queue_packets(tile, q) > 0U) {
      signal(r.rx[q]);
    }
  }
  if (bsp::udn_net_can_send(tile)) {
    signal(r.tx);
  }
}

TileRaw* active_tile() noexcept {
  const bsp::TileId t = bsp::current_tile();
  const bool ok = t < bsp::kMaxTiles && g_raw[t].active && g_raw[t].generation == bsp::udn_net_generation();
  return ok ? &g_raw[t] : nullptr;
}

/** Ticks left before @p deadline (for kForever: kForever). */
k::Timeout remaining(k::Timeout to, k::Ticks deadline) noexcept {
  if (to.ticks == k::kForever.ticks) {
    return k::kForever;
  }
  const k::Ticks now = k::now_ticks();
  return k::Timeout{now >= deadline ? 0U : static_cast<std::uint32_t>(deadline - now)};
}

/** Waits on @p s until @p deadline. @return kOk (woken), kWouldBlock (no wait allowed), kTimeout, kKernel. */
RawError wait(k::Semaphore& s, k::Timeout to, k::Ticks deadline) noexcept {
  if (to.ticks == 0U) {
    return RawError::kWouldBlock;
  }
  const k::Timeout left = remaining(to, deadline);
  if (left.ticks == 0U) {
    return RawError::kTimeout;
  }
  const k::Status st = s.take(left);
  if (st == k::Status::kOk) {
    return RawError::kOk;
  }
  return st == k::Status::kTimeout ? RawError::kTimeout : RawError::kKernel;
}

RawError from_net(bsp::NetError e) noexcept {
  switch (e) {
    case bsp::NetError::kOk:
      return RawError::kOk;
    case bsp::NetError::kBadTile:
      return RawError::kBadTile;
    case bsp::NetError::kBadLength:
      return RawError::kBadLength;
    case bsp::NetError::kBadQueue:
      return RawError::kBadQueue;
    case bsp::NetError::kFull:
      return RawError::kFull;
    case bsp::NetError::kNotInit:
    case bsp::NetError::kBadConfig:
    case bsp::NetError::kEmpty:
      break;
  }
  return RawError::kNotActive;
}

}  // namespace

RawError header_for(bsp::TileId dest, std::uint32_t data_words, std::uint32_t& header) noexcept {
  const std::uint32_t cols = bsp::udn_grid_cols();
  if (cols == 0U || dest >= cols * bsp::udn_grid_rows()) {
    return RawError::kBadTile;
  }
  if (data_words == 0U || data_words > kMaxDataWords) {
    return RawError::kBadLength;
  }
  header = header_xy(dest % cols, dest / cols, data_words);
  return RawError::kOk;
}

RawError activate() noexcept {
  const bsp::TileId t = bsp::current_tile();
  if (t >= bsp::kMaxTiles) {
    return RawError::kKernel;
  }
  if (active_tile() != nullptr) {
    return RawError::kOk;  // already active on this board: a second task must not reset the semaphores it waits on
  }
  g_raw[t] = TileRaw{};
  if (k::set_isr(bsp::Irq::kUdn, on_udn_irq) != k::Status::kOk) {
    return RawError::kKernel;
  }
  g_raw[t].generation = bsp::udn_net_generation();
  g_raw[t].active = true;
  return RawError::kOk;
}

RawError send(bsp::TileId dest, std::uint32_t tag, std::span<const std::uint32_t> data, k::Timeout to) noexcept {
  TileRaw* r = active_tile();
  if (r == nullptr) {
    return RawError::kNotActive;
  }
  std::array<std::uint32_t, bsp::kUdnMaxPacketWords> words{};
  const auto n = static_cast<std::uint32_t>(data.size() < words.size() ? data.size() : 0U);
  const RawError h = header_for(dest, n, words[0]);
  if (h != RawError::kOk) {
    return h;
  }
  words[1] = tag;
  for (std::uint32_t i = 0; i < n; ++i) {
    words[2U + i] = data[i];
  }
  const std::span<const std::uint32_t> packet(words.data(), n + 2U);
  const k::Ticks deadline = k::now_ticks() + to.ticks;
  for (std::uint32_t attempt = 0; attempt < kMaxAttempts; ++attempt) {
    const RawError e = from_net(bsp::udn_net_send(packet));
    if (e != RawError::kFull) {
      return e;
    }
    const RawError w = wait(r->tx, to, deadline);
    if (w != RawError::kOk) {
      return w;
    }
  }
  return RawError::kTimeout;
}

RawError receive(std::uint32_t queue, RxInfo& info, std::span<std::uint32_t> data, k::Timeout to) noexcept {
  TileRaw* r = active_tile();
  if (r == nullptr) {
    return RawError::kNotActive;
  }
  if (queue >= kQueues) {
    return RawError::kBadQueue;
  }
  const k::Ticks deadline = k::now_ticks() + to.ticks;
  for (std::uint32_t attempt = 0; attempt < kMaxAttempts; ++attempt) {
    bsp::RxPacket rx{};
    const bsp::NetError e = bsp::udn_net_receive(queue, rx, data);
    if (e == bsp::NetError::kOk) {
      info = RxInfo{rx.source, rx.tag, rx.payload_words, rx.send_cycle, rx.arrival_cycle};
      return RawError::kOk;
    }
    if (e != bsp::NetError::kEmpty) {
      return from_net(e);
    }
    const RawError w = wait(r->rx[queue], to, deadline);
    if (w != RawError::kOk) {
      return w;
    }
  }
  return RawError::kTimeout;
}

RawError bind(std::uint32_t tag, std::uint32_t queue) noexcept {
  if (active_tile() == nullptr) {
    return RawError::kNotActive;
  }
  return from_net(bsp::udn_net_bind(bsp::current_tile(), tag, queue));
}

}  // namespace udn
