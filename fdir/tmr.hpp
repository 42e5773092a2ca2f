/**
 * @file tmr.hpp
 * @brief Triple modular redundancy, generic: a bit-for-bit 2-of-3 vote over the replicas'
 *        records of one job, and the per-replica accounting that decides exclusion.
 *
 * Each replica of a TMR group produces, per job, a record of words (its output
 * and a digest of its whole state). The voter compares the records of the
 * replicas it expects word for word: three that agree, or two that agree
 * while the third differs or is missing, give the voted record; anything
 * else (two present that differ, fewer than two present) is "no majority",
 * which is never passed on as an output. A group with two replicas left is a
 * duplex comparator: it detects a difference but cannot say who is wrong.
 *
 * TmrGroup keeps, like COAST's TMR error counter, per replica the
 * disagreements and misses, in a row and in total; a replica is excluded
 * after `disagree_to_exclude` disagreements or `miss_to_exclude` misses in a
 * row (one odd output is outvoted and counted, a wrong state keeps
 * disagreeing and is excluded), and readmitted by its owner after it has been
 * re-synchronised. Plain data, no allocation; the owner reports the events.
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace fdir {

inline constexpr std::uint32_t kTmrReplicas = 3U;
/** Largest record voted (words). */
inline constexpr std::uint32_t kTmrMaxWords = 64U;
inline constexpr std::uint32_t kTmrAllReplicas = (1U << kTmrReplicas) - 1U;

struct TmrRecord {
  std::uint32_t job = 0U;
  std::uint32_t words = 0U;  ///< 1 .. kTmrMaxWords
  std::array<std::uint32_t, kTmrMaxWords> w{};
};

/** A record kept in a voter's state is emulated state through and through (bsp::ControlLayout). */
inline constexpr std::array kTmrRecordFields{BSP_CONTROL_STATE(TmrRecord, job), BSP_CONTROL_STATE(TmrRecord, words),
                                             BSP_CONTROL_STATE(TmrRecord, w)};
inline constexpr bsp::ControlLayout kTmrRecordLayout{kTmrRecordFields, sizeof(TmrRecord), alignof(TmrRecord)};
static_assert(bsp::control_layout_ok(kTmrRecordLayout), "every member of TmrRecord");

enum class TmrVerdict : std::uint8_t {
  kAgree,       ///< every expected replica present and equal (3 of 3, or 2 of 2 in duplex)
  kOutvoted,    ///< two agree; the others expected are different or missing (odd_mask)
  kNoMajority,  ///< no two expected replicas agree: nothing may be passed on
};

struct TmrVote {
  TmrVerdict verdict = TmrVerdict::kNoMajority;
  std::uint32_t winner = kTmrReplicas;  ///< a replica holding the voted record (not for kNoMajority)
  /// Expected replicas present whose record differs from the vote; without a majority, the present
  /// ones when two or more are (they differ from each other), none when one is alone.
  std::uint32_t differ_mask = 0U;
  std::uint32_t missing_mask = 0U;      ///< expected replicas with no record for the job
};

/** True if @p a and @p b are the same job with the same words. */
bool tmr_same(const TmrRecord& a, const TmrRecord& b) noexcept;

/**
 * Votes the records of the replicas in @p expected_mask (bit i: replica i);
 * records[i] == nullptr means replica i's record is missing. Records of
 * replicas not expected are ignored. A record in @p bad_mask is one its
 * receiver found corrupted (its own check failed): present and different,
 * never the vote, even when another bad record equals it.
 */
TmrVote tmr_vote(const std::array<const TmrRecord*, kTmrReplicas>& records, std::uint32_t expected_mask,
                 std::uint32_t bad_mask = 0U) noexcept;

struct TmrReplicaCount {
  std::uint32_t disagree_in_row = 0U;
  std::uint32_t disagreements = 0U;
  std::uint32_t miss_in_row = 0U;
  std::uint32_t misses = 0U;
  std::uint32_t exclusions = 0U;
};

struct TmrGroupConfig {
  std::uint32_t disagree_to_exclude = 2U;  ///< disagreements in a row (>= 1)
  std::uint32_t miss_to_exclude = 3U;      ///< missed jobs in a row (>= 1)
};

/** A group's counts and thresholds are emulated state through and through (bsp::ControlLayout). */
inline constexpr std::array kTmrReplicaCountFields{
    BSP_CONTROL_STATE(TmrReplicaCount, disagree_in_row), BSP_CONTROL_STATE(TmrReplicaCount, disagreements),
    BSP_CONTROL_STATE(TmrReplicaCount, miss_in_row),     BSP_CONTROL_STATE(TmrReplicaCount, misses),
    BSP_CONTROL_STATE(TmrReplicaCount, exclusions)};
inline constexpr bsp::ControlLayout kTmrReplicaCountLayout{kTmrReplicaCountFields, sizeof(TmrReplicaCount),
                                                           alignof(TmrReplicaCount)};
static_assert(bsp::control_layout_ok(kTmrReplicaCountLayout), "every member of TmrReplicaCount");
inline constexpr std::array kTmrGroupConfigFields{BSP_CONTROL_STATE(TmrGroupConfig, disagree_to_exclude),
                                                  BSP_CONTROL_STATE(TmrGroupConfig, miss_to_exclude)};
inline constexpr bsp::ControlLayout kTmrGroupConfigLayout{kTmrGroupConfigFields, sizeof(TmrGroupConfig),
                                                          alignof(TmrGroupConfig)};
static_assert(bsp::control_layout_ok(kTmrGroupConfigLayout), "every member of TmrGroupConfig");

class TmrGroup {
 public:
  /** Starts with no replica active. False (and nothing changed) for a zero threshold. */
  bool configure(const TmrGroupConfig& cfg) noexcept;

  /** The thresholds as the group holds them (in its owner's RAM). */
  [[nodiscard]] const TmrGroupConfig& config() const noexcept { return cfg_; }
  /**
   * Sets the thresholds again and keeps the replicas voted on and their counts: the owner's
   * check found them changed in RAM. False (nothing changed) for a zero threshold.
   */
  bool set_thresholds(const TmrGroupConfig& cfg) noexcept;

  /** Replicas voted on (bit i: replica i). */
  [[nodiscard]] std::uint32_t active_mask() const noexcept { return active_; }
  [[nodiscard]] std::uint32_t active_count() const noexcept;
  [[nodiscard]] const TmrReplicaCount& count(std::uint32_t replica) const noexcept;

  /** Makes @p replica a voter again (after it was re-synchronised); counts in a row restart. */
  void admit(std::uint32_t replica) noexcept;
  /** Stops voting on @p replica (its owner resets or replaces it). */
  void exclude(std::uint32_t replica) noexcept;

  /**
   * Counts a vote's outcome for every active replica and returns the replicas
   * to exclude now (reached a threshold); they are excluded already. A
   * no-majority vote counts nobody: it cannot say who is wrong.
   */
  std::uint32_t account(const TmrVote& v) noexcept;

 private:
  TmrGroupConfig cfg_{};
  std::uint32_t active_ = 0U;
  std::array<TmrReplicaCount, kTmrReplicas> count_{};
  friend struct TmrGroupLayout;
};

/**
 * A group in a control struct is emulated state (bsp::ControlLayout): every
 * index it takes from a replica number is bounded (count(), admit(), exclude()).
 */
struct TmrGroupLayout {
  static constexpr std::array kFields{BSP_CONTROL_NESTED(TmrGroup, cfg_, kTmrGroupConfigLayout),
                                      BSP_CONTROL_STATE(TmrGroup, active_),
                                      BSP_CONTROL_NESTED(TmrGroup, count_, kTmrReplicaCountLayout)};
  static constexpr bsp::ControlLayout kLayout{kFields, sizeof(TmrGroup), alignof(TmrGroup)};
  static_assert(bsp::control_layout_ok(kLayout), "every member of TmrGroup");
};

}  // namespace fdir
