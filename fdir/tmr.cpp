/**
 * @file tmr.cpp
 * @brief The 2-of-3 vote and the replicas' counts (see tmr.hpp).
 */
#include "fdir/tmr.hpp"

#include <bit>

namespace fdir {

bool tmr_same(const TmrRecord& a, const TmrRecord& b) noexcept {
  if (a.job != b.job || a.words != b.words || a.words > kTmrMaxWords) {
    return false;
  }
  std::uint32_t diff = 0U;
  for (std::uint32_t i = 0; i < a.words; ++i) {
    diff |= a.w[i] ^ b.w[i];
  }
  return diff == 0U;
}

TmrVote tmr_vote(const std::array<const TmrRecord*, kTmrReplicas>& records, std::uint32_t expected_mask,
                 std::uint32_t bad_mask) noexcept {
  TmrVote v{};
  std::array<const TmrRecord*, kTmrReplicas> r{};  // the good records present
  std::uint32_t bad = 0U;                           // the bad ones present
  for (std::uint32_t i = 0; i < kTmrReplicas; ++i) {
    if ((expected_mask & (1U << i)) == 0U) {
      continue;
    }
    if (records[i] == nullptr) {
      v.missing_mask |= 1U << i;
    } else if ((bad_mask & (1U << i)) != 0U) {
      bad |= 1U << i;
    } else {
      r[i] = records[i];
    }
  }
  // The first replica that agrees with another present one holds the vote.
  for (std::uint32_t i = 0; i < kTmrReplicas && v.winner == kTmrReplicas; ++i) {
    for (std::uint32_t j = i + 1U; j < kTmrReplicas; ++j) {
      if (r[i] != nullptr && r[j] != nullptr && tmr_same(*r[i], *r[j])) {
        v.winner = i;
        break;
      }
    }
  }
  if (v.winner == kTmrReplicas) {
    // Present records that differ from each other: each may be the wrong one. A record alone
    // differs from nothing: it is not named (the missing ones are).
    std::uint32_t present = 0U;
    for (std::uint32_t i = 0; i < kTmrReplicas; ++i) {
      present |= r[i] != nullptr ? (1U << i) : 0U;
    }
    v.differ_mask = bad | (std::popcount(present) >= 2 ? present : 0U);
    v.verdict = TmrVerdict::kNoMajority;
    return v;
  }
  v.differ_mask = bad;
  for (std::uint32_t i = 0; i < kTmrReplicas; ++i) {
    if (r[i] != nullptr && !tmr_same(*r[i], *r[v.winner])) {
      v.differ_mask |= 1U << i;
    }
  }
  v.verdict = (v.differ_mask | v.missing_mask) == 0U ? TmrVerdict::kAgree : TmrVerdict::kOutvoted;
  return v;
}

bool TmrGroup::configure(const TmrGroupConfig& cfg) noexcept {
  if (cfg.disagree_to_exclude == 0U || cfg.miss_to_exclude == 0U) {
    return false;
  }
  cfg_ = cfg;
  active_ = 0U;
  count_ = {};
  return true;
}

bool TmrGroup::set_thresholds(const TmrGroupConfig& cfg) noexcept {
  if (cfg.disagree_to_exclude == 0U || cfg.miss_to_exclude == 0U) {
    return false;
  }
  cfg_ = cfg;
  return true;
}

std::uint32_t TmrGroup::active_count() const noexcept {
  std::uint32_t n = 0U;
  for (std::uint32_t i = 0; i < kTmrReplicas; ++i) {
    n += (active_ >> i) & 1U;
  }
  return n;
}

const TmrReplicaCount& TmrGroup::count(std::uint32_t replica) const noexcept {
  return count_[replica < kTmrReplicas ? replica : 0U];
}

void TmrGroup::admit(std::uint32_t replica) noexcept {
  if (replica < kTmrReplicas) {
    active_ |= 1U << replica;
    count_[replica].disagree_in_row = 0U;
    count_[replica].miss_in_row = 0U;
  }
}

void TmrGroup::exclude(std::uint32_t replica) noexcept {
  if (replica < kTmrReplicas && (active_ & (1U << replica)) != 0U) {
    active_ &= ~(1U << replica);
    ++count_[replica].exclusions;
  }
}

std::uint32_t TmrGroup::account(const TmrVote& v) noexcept {
  if (v.verdict == TmrVerdict::kNoMajority) {
    return 0U;
  }
  std::uint32_t out = 0U;
  for (std::uint32_t i = 0; i < kTmrReplicas; ++i) {
    const std::uint32_t bit = 1U << i;
    if ((active_ & bit) == 0U) {
      continue;
    }
    TmrReplicaCount& c = count_[i];
    if ((v.differ_mask & bit) != 0U) {
      ++c.disagreements;
      ++c.disagree_in_row;
    } else if ((v.missing_mask & bit) == 0U) {
      c.disagree_in_row = 0U;
    }
    if ((v.missing_mask & bit) != 0U) {
      ++c.misses;
      ++c.miss_in_row;
    } else {
      c.miss_in_row = 0U;
    }
    if (c.disagree_in_row >= cfg_.disagree_to_exclude || c.miss_in_row >= cfg_.miss_to_exclude) {
      out |= bit;
    }
  }
  for (std::uint32_t i = 0; i < kTmrReplicas; ++i) {
    if ((out & (1U << i)) != 0U) {
      exclude(i);
    }
  }
  return out;
}

}  // namespace fdir
