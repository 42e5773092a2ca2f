/**
 * @file work.hpp
 * @brief A count of the work a piece of flight code did, for the cost model to charge.
 *
 * Algorithms count what they do (integer MACs, floating-point operations,
 * memory words moved) in a Work value; the task that ran them converts it to
 * cycles with the board's cost model and charges it. Counting, not timing:
 * emulated time never depends on host time.
 */
#pragma once

#include <cstdint>

namespace bsp {

struct Work {
  std::uint64_t int_ops = 0;    ///< integer ALU operations (add, compare, shift)
  std::uint64_t int_macs = 0;   ///< integer multiply-accumulates
  std::uint64_t flops = 0;      ///< floating-point operations (add, mul; soft-float on TILE64)
  std::uint64_t fdivs = 0;      ///< floating-point divisions and square roots
  std::uint64_t mem_words = 0;  ///< 32-bit words loaded or stored beyond the register file

  constexpr Work& operator+=(const Work& o) noexcept {
    int_ops += o.int_ops;
    int_macs += o.int_macs;
    flops += o.flops;
    fdivs += o.fdivs;
    mem_words += o.mem_words;
    return *this;
  }
};

constexpr Work operator+(Work a, const Work& b) noexcept { return a += b; }

}  // namespace bsp
