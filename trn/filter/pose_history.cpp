/**
 * @file pose_history.cpp
 * @brief The pose history: recording the reference trajectory and reading the past pose of the nominal.
 */
#include "trn/filter/pose_history.hpp"

#include <cmath>

namespace trn::filter {

namespace {

Vec3 entry_p(const PoseEntry& e) noexcept { return {e.p_m[0], e.p_m[1], e.p_m[2]}; }

Quat entry_q(const PoseEntry& e) noexcept { return {e.q_wxyz[0], e.q_wxyz[1], e.q_wxyz[2], e.q_wxyz[3]}; }

void set_entry(PoseEntry& e, double t_s, const Vec3& p, const Quat& q) noexcept {
  e.t_s = t_s;
  for (int i = 0; i < 3; ++i) {
    e.p_m[i] = p(i);
  }
  e.q_wxyz[0] = q.w();
  e.q_wxyz[1] = q.x();
  e.q_wxyz[2] = q.y();
  e.q_wxyz[3] = q.z();
}

bool entry_finite_unit(const PoseEntry& e) noexcept {
  const Quat q = entry_q(e);
  return std::isfinite(e.t_s) && entry_p(e).allFinite() && q.coeffs().allFinite() &&
         std::abs(q.squaredNorm() - 1.0) < 1e-9;
}

}  // namespace

const PoseEntry& history_entry(const PoseHistory& h, std::uint32_t i) noexcept {
  // newest + 1 - count is the oldest; the added kHistoryLen keeps the sum non-negative.
  return h.e[(h.newest + kHistoryLen + 1U - h.count + i) % kHistoryLen];
}

void history_clear(PoseHistory& h) noexcept {
  h.newest = 0;
  h.count = 0;
  for (double& v : h.ref_v_mps) {
    v = 0.0;
  }
  for (PoseEntry& e : h.e) {
    e = PoseEntry{};
  }
}

void history_start(PoseHistory& h, double t_s, const NominalState& x) noexcept {
  history_clear(h);
  for (int i = 0; i < 3; ++i) {
    h.ref_v_mps[i] = x.v_mps(i);
  }
  set_entry(h.e[0], t_s, x.p_m, x.q_mb);
  h.count = 1;
}

void history_record(PoseHistory& h, double t_s, double dt_s, const Vec3& dv_mps, const Quat& dq,
                    const NominalState& x, bsp::Work& work) noexcept {
  work.flops += kFlopsHistoryRecord;
  work.fdivs += kFdivsHistoryRecord;
  work.mem_words += 2ULL * 11ULL;  // the previous entry and the velocity read, the new ones written
  if (h.count == 0U || !(t_s > h.e[h.newest].t_s + kHistoryTimeTolS)) {
    // Time went backwards or stood still: the past is no longer ordered; start again here.
    history_start(h, t_s, x);
    return;
  }
  const PoseEntry& prev = h.e[h.newest];
  const Vec3 wv_old(h.ref_v_mps[0], h.ref_v_mps[1], h.ref_v_mps[2]);
  const Vec3 wv_new = wv_old + dv_mps;
  // The same trapezoid as the strapdown, on the uncorrected velocity.
  const Vec3 wp = entry_p(prev) + (0.5 * dt_s) * (wv_old + wv_new);
  const Quat u = (entry_q(prev) * dq).normalized();
  h.newest = (h.newest + 1U) % kHistoryLen;
  h.count = h.count < kHistoryLen ? h.count + 1U : kHistoryLen;
  set_entry(h.e[h.newest], t_s, wp, u);
  for (int i = 0; i < 3; ++i) {
    h.ref_v_mps[i] = wv_new(i);
  }
}

namespace {

/** Logical indices lo, lo + 1 of the entries around @p t (oldest.t <= t < newest.t); false if not found. */
bool bracket(const PoseHistory& h, double t, std::uint32_t& lo, bsp::Work& work) noexcept {
  lo = 0;
  std::uint32_t hi = h.count - 1U;
  // Halving a span of at most kHistoryLen - 1 takes 8 steps; 16 bounds the loop.
  for (int k = 0; k < 16 && hi - lo > 1U; ++k) {
    const std::uint32_t mid = lo + (hi - lo) / 2U;
    if (history_entry(h, mid).t_s <= t) {
      lo = mid;
    } else {
      hi = mid;
    }
    work.int_ops += 4;
    work.mem_words += 2;
  }
  return hi - lo == 1U;
}

}  // namespace

HistoryStatus history_pose(const PoseHistory& h, double t_s, const NominalState& x_now, double max_gap_s,
                           PastPose& out, bsp::Work& work) noexcept {
  if (h.count == 0U) {
    return HistoryStatus::kTooOld;
  }
  const PoseEntry& now = h.e[h.newest];
  if (!(t_s <= now.t_s + kHistoryTimeTolS)) {
    return HistoryStatus::kFuture;
  }
  if (t_s >= now.t_s - kHistoryTimeTolS) {
    return HistoryStatus::kCurrent;
  }
  const PoseEntry& oldest = history_entry(h, 0);
  if (h.count < 2U || t_s < oldest.t_s - kHistoryTimeTolS) {
    return HistoryStatus::kTooOld;
  }
  const double t = t_s < oldest.t_s ? oldest.t_s : t_s;  // within the tolerance of the oldest
  std::uint32_t lo = 0;
  if (!bracket(h, t, lo, work)) {
    return HistoryStatus::kTooOld;  // unreachable for an ordered history
  }
  const PoseEntry& a = history_entry(h, lo);
  const PoseEntry& b = history_entry(h, lo + 1U);
  // On an entry (within the tolerance) nothing is interpolated, so a gap after it does not matter.
  const bool on_entry = t - a.t_s <= kHistoryTimeTolS || b.t_s - t <= kHistoryTimeTolS;
  if (!on_entry && !(b.t_s - a.t_s <= max_gap_s)) {
    return HistoryStatus::kGap;
  }
  work.flops += kFlopsHistoryPose;
  work.fdivs += kFdivsHistoryPose;
  work.mem_words += 3ULL * 16ULL;
  const double alpha = (t - a.t_s) / (b.t_s - a.t_s);
  const Vec3 pa = entry_p(a);
  const Vec3 wp = pa + alpha * (entry_p(b) - pa);
  const Quat qa = entry_q(a);
  Quat qb = entry_q(b);
  if (qa.dot(qb) < 0.0) {
    qb.coeffs() = -qb.coeffs();  // same hemisphere, so the blend is the short way round
  }
  const Quat u(qa.coeffs() + alpha * (qb.coeffs() - qa.coeffs()));
  const Quat u_t = u.normalized();
  out.lag_s = now.t_s - t;
  const Vec3 wv(h.ref_v_mps[0], h.ref_v_mps[1], h.ref_v_mps[2]);
  out.p_m = x_now.p_m - (entry_p(now) - wp) - out.lag_s * (x_now.v_mps - wv);
  out.q_rel = u_t.conjugate() * entry_q(now);
  out.q_mb = x_now.q_mb * out.q_rel.conjugate();
  return HistoryStatus::kOk;
}

bool history_valid(const PoseHistory& h, double t_s, bool initialized) noexcept {
  if (h.count > kHistoryLen || h.newest >= kHistoryLen) {
    return false;
  }
  if (!initialized || h.count == 0U) {
    return !initialized && h.count == 0U;
  }
  if (!std::isfinite(h.ref_v_mps[0]) || !std::isfinite(h.ref_v_mps[1]) || !std::isfinite(h.ref_v_mps[2])) {
    return false;
  }
  for (std::uint32_t i = 0; i < h.count; ++i) {
    const PoseEntry& e = history_entry(h, i);
    if (!entry_finite_unit(e) || (i > 0U && !(e.t_s > history_entry(h, i - 1U).t_s))) {
      return false;
    }
  }
  // The newest entry is the filter's own time: the back-propagation starts from it.
  return h.e[h.newest].t_s == t_s;
}

}  // namespace trn::filter
