/**
 * @file trace.cpp
 * @brief Running trace hash (a multiply-xorshift mixer per field) and the recent-event ring.
 */
#include "bsp_tile64/emu/trace.hpp"

#include <array>

namespace bsp {
namespace {

struct TraceState {
  std::uint64_t hash;
  std::uint64_t count;
  std::array<TraceEvent, kTraceRingSize> ring;
  TraceSink sink;
};

constexpr std::uint64_t kHashSeed = 0xCBF29CE484222325ULL;  // FNV offset basis: any odd start works

TraceState g_trace{kHashSeed, 0U, {}, nullptr};

/** One field into the hash: xor, then a full-avalanche multiply-xorshift (Murmur3 finalizer). */
constexpr std::uint64_t mix(std::uint64_t h, std::uint64_t v) noexcept {
  h ^= v;
  h *= 0xFF51AFD7ED558CCDULL;
  h ^= h >> 33U;
  h *= 0xC4CEB9FE1A85EC53ULL;
  h ^= h >> 29U;
  return h;
}

}  // namespace

std::uint64_t trace_fold(std::uint64_t h, const TraceEvent& ev) noexcept {
  h = mix(h, ev.time);
  h = mix(h, (static_cast<std::uint64_t>(ev.tile) << 16U) | ev.kind);
  h = mix(h, ev.a);
  return mix(h, ev.b);
}

void trace_record(Cycles time, TileId tile, std::uint16_t kind, std::uint64_t a, std::uint64_t b) noexcept {
  const TraceEvent ev{time, tile, kind, a, b};
  g_trace.hash = trace_fold(g_trace.hash, ev);
  g_trace.ring[g_trace.count % kTraceRingSize] = ev;
  ++g_trace.count;
  if (g_trace.sink != nullptr) {
    g_trace.sink(ev);
  }
}

void trace_reset() noexcept {
  g_trace.hash = kHashSeed;
  g_trace.count = 0U;
}

std::uint64_t trace_hash() noexcept { return g_trace.hash; }

std::uint64_t trace_initial_hash() noexcept { return kHashSeed; }

std::uint64_t trace_count() noexcept { return g_trace.count; }

std::size_t trace_recent(std::span<TraceEvent> out) noexcept {
  const std::uint64_t held = g_trace.count < kTraceRingSize ? g_trace.count : kTraceRingSize;
  const std::size_t n = out.size() < held ? out.size() : static_cast<std::size_t>(held);
  const std::uint64_t first = g_trace.count - n;
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = g_trace.ring[(first + i) % kTraceRingSize];
  }
  return n;
}

void set_trace_sink(TraceSink sink) noexcept { g_trace.sink = sink; }

}  // namespace bsp
