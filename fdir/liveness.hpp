/**
 * @file liveness.hpp
 * @brief Liveness of the workers a coordinator hands work to: a worker that misses its answers
 *        is isolated (gets no more work) and probed now and then; it comes back by answering.
 *
 * A coordinator (e.g. the vision coordinator with its 40 tiles) calls
 * liveness_answered() or liveness_missed() for each piece of work it handed
 * out, when the round (a frame) closes. After suspect_after_misses misses in a
 * row a worker is isolated: liveness_gets_work() is false for it except on
 * every probe_every-th round, when one piece of work tests it. The first
 * answer brings it back. Both transitions are flight events (kWorkerSilent,
 * kWorkerBack) written by the coordinator's tile. Plain data: the coordinator
 * keeps it in its own carved state.
 */
#pragma once

#include "bsp_tile64/api/port.hpp"

#include <array>
#include <cstdint>

namespace fdir {

inline constexpr std::uint32_t kMaxWorkers = 48U;

struct LivenessConfig {
  std::uint32_t suspect_after_misses = 2U;  ///< >= 1
  std::uint32_t probe_every = 5U;           ///< rounds between probes of an isolated worker (>= 1)
};

struct Liveness {
  LivenessConfig config{};
  std::uint32_t count = 0U;
  std::array<bsp::TileId, kMaxWorkers> tile{};
  std::array<std::uint32_t, kMaxWorkers> misses{};  ///< misses in a row per worker
};

enum class LivenessError : std::uint8_t { kOk, kBadConfig };

/** Starts tracking @p count workers (tiles @p tiles), all live. @return kBadConfig for a zero setting or too many. */
[[nodiscard]] LivenessError liveness_init(Liveness& l, const LivenessConfig& config, const bsp::TileId* tiles,
                                          std::uint32_t count) noexcept;

/** Whether worker @p i gets work in round @p round (isolated workers only on probe rounds). */
[[nodiscard]] bool liveness_gets_work(const Liveness& l, std::uint32_t i, std::uint32_t round) noexcept;

/** Worker @p i answered: back if it was isolated (event kWorkerBack). [task] */
void liveness_answered(Liveness& l, std::uint32_t i) noexcept;

/** Worker @p i missed: isolated at the threshold (event kWorkerSilent, once). [task] */
void liveness_missed(Liveness& l, std::uint32_t i) noexcept;

/** Workers isolated now. */
[[nodiscard]] std::uint32_t liveness_isolated(const Liveness& l) noexcept;

}  // namespace fdir
