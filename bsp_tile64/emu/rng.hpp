/**
 * @file rng.hpp
 * @brief Deterministic random streams: xoshiro256** with named, independent streams.
 *
 * Standard library distributions differ between library versions, so the
 * variates here are our own. A stream is identified by (seed, StreamId, index):
 * the same triple always yields the same sequence, and streams never share state,
 * so adding draws to one (say, sensor noise) never shifts another (faults).
 */
#pragma once

#include <cstdint>

namespace bsp {

/** Named stream families. Append only: reordering changes every run's bits. */
enum class StreamId : std::uint32_t {
  kWorld = 1,   ///< terrain, craters, boulders
  kSensor = 2,  ///< IMU and camera noise
  kFaults = 3,  ///< the fault injector's random faults
  kTraffic = 4, ///< synthetic network traffic (stress tools)
  kTest = 5,    ///< tests' own draws
};

/** SplitMix64 step: used to expand a seed into generator state. */
constexpr std::uint64_t splitmix64(std::uint64_t& x) noexcept {
  x += 0x9E3779B97F4A7C15ULL;
  std::uint64_t z = x;
  z = (z ^ (z >> 30U)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27U)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31U);
}

/** xoshiro256** (Blackman and Vigna): fast, 256-bit state, passes BigCrush. */
class Rng {
 public:
  /** A stream from a run seed, a family and an index within the family (e.g. a tile). */
  constexpr Rng(std::uint64_t seed, StreamId id, std::uint64_t index = 0) noexcept {
    std::uint64_t x = seed ^ (static_cast<std::uint64_t>(id) * 0xD1B54A32D192ED03ULL) ^
                      (index * 0x8CB92BA72F3D8DD7ULL);
    for (std::uint64_t& w : s_) {
      w = splitmix64(x);
    }
  }

  /** Next 64 random bits. */
  constexpr std::uint64_t next() noexcept {
    const std::uint64_t result = rotl(s_[1] * 5U, 7) * 9U;
    const std::uint64_t t = s_[1] << 17U;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  /** Uniform double in [0, 1) with 53 random bits. */
  constexpr double uniform() noexcept { return static_cast<double>(next() >> 11U) * 0x1.0p-53; }

  /** Uniform double in [lo, hi). */
  constexpr double uniform(double lo, double hi) noexcept { return lo + (hi - lo) * uniform(); }

  /**
   * Uniform integer in [0, bound) without modulo bias: masked rejection.
   * Each try is accepted with probability > 1/2, so 128 tries all failing has
   * probability < 2^-128; the bounded loop then falls back to a modulo.
   */
  constexpr std::uint64_t below(std::uint64_t bound) noexcept {
    if (bound <= 1U) {
      return 0U;
    }
    std::uint64_t mask = bound - 1U;
    mask |= mask >> 1U;
    mask |= mask >> 2U;
    mask |= mask >> 4U;
    mask |= mask >> 8U;
    mask |= mask >> 16U;
    mask |= mask >> 32U;
    for (int tries = 0; tries < 128; ++tries) {
      const std::uint64_t v = next() & mask;
      if (v < bound) {
        return v;
      }
    }
    return next() % bound;
  }

  /** Standard normal variate (Marsaglia polar method; uses log and sqrt). */
  double normal() noexcept;

  /** Normal variate with mean @p mu and standard deviation @p sigma. */
  double normal(double mu, double sigma) noexcept { return mu + sigma * normal(); }

  /** True with probability @p p. */
  constexpr bool bernoulli(double p) noexcept { return uniform() < p; }

 private:
  static constexpr std::uint64_t rotl(std::uint64_t x, int k) noexcept {
    return (x << static_cast<unsigned>(k)) | (x >> static_cast<unsigned>(64 - k));
  }
  std::uint64_t s_[4]{};
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace bsp
