/**
 * @file state_block.cpp
 * @brief Serialization of the filter state to and from its byte block.
 */
#include "trn/filter/state_block.hpp"

#include "trn/filter/byte_io.hpp"

#include <bit>
#include <cmath>

namespace trn::filter {

namespace {

constexpr std::uint32_t kCrcOffset = kStateBlockBytes - 4U;

void write_vec3(ByteWriter& w, const Vec3& v) noexcept {
  w.f64(v.x());
  w.f64(v.y());
  w.f64(v.z());
}

Vec3 read_vec3(ByteReader& r) noexcept {
  const double x = r.f64();
  const double y = r.f64();
  const double z = r.f64();
  return {x, y, z};
}

void write_counters(ByteWriter& w, const FilterCounters& c) noexcept {
  w.u64(c.propagations);
  w.u32(c.last_imu_seq);
  w.u32(c.imu_rejected);
  w.u32(c.imu_gaps);
  w.u32(c.batches);
  w.u32(c.accepted);
  w.u32(c.rejected_gate);
  w.u32(c.rejected_invalid);
  w.u32(c.rejected_stale);
  w.u32(c.coarse_accepted);
  w.u32(c.last_accepted);
  w.u32(c.last_rejected);
  w.u32(c.numeric_faults);
}

void read_counters(ByteReader& r, FilterCounters& c) noexcept {
  c.propagations = r.u64();
  c.last_imu_seq = r.u32();
  c.imu_rejected = r.u32();
  c.imu_gaps = r.u32();
  c.batches = r.u32();
  c.accepted = r.u32();
  c.rejected_gate = r.u32();
  c.rejected_invalid = r.u32();
  c.rejected_stale = r.u32();
  c.coarse_accepted = r.u32();
  c.last_accepted = r.u32();
  c.last_rejected = r.u32();
  c.numeric_faults = r.u32();
}

// The fields after the header are read into a scratch state before any of it
// is accepted; it is static so the 18 KB state never lands on a task stack.
// Not reentrant: one filter task per tile uses it.
FilterState g_scratch;

/** The history, oldest entry first, then zeros up to kHistoryLen entries (canonical bytes). */
void write_history(ByteWriter& w, const PoseHistory& h) noexcept {
  w.u32(h.count);
  w.u32(0U);
  for (const double v : h.ref_v_mps) {
    w.f64(v);
  }
  for (std::uint32_t i = 0; i < kHistoryLen; ++i) {
    const PoseEntry e = i < h.count ? history_entry(h, i) : PoseEntry{0.0, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0, 0.0}};
    w.f64(e.t_s);
    for (const double v : e.p_m) {
      w.f64(v);
    }
    for (const double v : e.q_wxyz) {
      w.f64(v);
    }
  }
}

/**
 * Reads what write_history() wrote into ring slots 0..n-1; false on a bad
 * count or reserved word, or an entry from n on that is not all zero bits
 * (the layout's canonical bytes: one state has one block).
 */
bool read_history(ByteReader& r, PoseHistory& h) noexcept {
  const std::uint32_t n = r.u32();
  const std::uint32_t reserved = r.u32();
  for (double& v : h.ref_v_mps) {
    v = r.f64();
  }
  std::uint64_t unused_bits = 0U;
  for (std::uint32_t i = 0; i < kHistoryLen; ++i) {
    PoseEntry& e = h.e[i];
    e.t_s = r.f64();
    for (double& v : e.p_m) {
      v = r.f64();
    }
    for (double& v : e.q_wxyz) {
      v = r.f64();
    }
    if (i >= n) {
      unused_bits |= std::bit_cast<std::uint64_t>(e.t_s);
      for (const double v : e.p_m) {
        unused_bits |= std::bit_cast<std::uint64_t>(v);
      }
      for (const double v : e.q_wxyz) {
        unused_bits |= std::bit_cast<std::uint64_t>(v);
      }
    }
  }
  h.count = n;
  h.newest = n > 0U ? n - 1U : 0U;
  return n <= kHistoryLen && reserved == 0U && unused_bits == 0U;
}

}  // namespace

BlockError write_state_block(const FilterState& s, StateBlock& out) noexcept {
  ByteWriter w(out.data(), kStateBlockBytes);
  w.u32(kStateMagic);
  w.u32(kStateVersion);
  w.u32(kStateBlockBytes);
  w.u32(0U);
  w.u32(s.initialized);
  w.u32(s.last_imu_ok);
  w.f64(s.t_s);
  w.f64(s.t_last_update_s);
  write_counters(w, s.c);
  write_vec3(w, s.x.p_m);
  write_vec3(w, s.x.v_mps);
  w.f64(s.x.q_mb.w());
  w.f64(s.x.q_mb.x());
  w.f64(s.x.q_mb.y());
  w.f64(s.x.q_mb.z());
  write_vec3(w, s.x.bg_rads);
  write_vec3(w, s.x.ba_mps2);
  for (int i = 0; i < kErrDim; ++i) {
    for (int j = 0; j < kErrDim; ++j) {
      w.f64(s.p(i, j));
    }
  }
  write_history(w, s.hist);
  w.u32(crc32(out.data(), kCrcOffset));
  return (w.ok() && w.size() == kStateBlockBytes) ? BlockError::kOk : BlockError::kBadSize;
}

namespace {

BlockError read_body(ByteReader& r, FilterState& s) noexcept {
  s.initialized = r.u32();
  s.last_imu_ok = r.u32();
  s.t_s = r.f64();
  s.t_last_update_s = r.f64();
  read_counters(r, s.c);
  s.x.p_m = read_vec3(r);
  s.x.v_mps = read_vec3(r);
  const double qw = r.f64();
  const Vec3 qv = read_vec3(r);
  s.x.q_mb = Quat(qw, qv.x(), qv.y(), qv.z());
  s.x.bg_rads = read_vec3(r);
  s.x.ba_mps2 = read_vec3(r);
  for (int i = 0; i < kErrDim; ++i) {
    for (int j = 0; j < kErrDim; ++j) {
      s.p(i, j) = r.f64();
    }
  }
  const bool hist_read = read_history(r, s.hist);
  const bool finite = std::isfinite(s.t_s) && std::isfinite(s.t_last_update_s) && s.x.p_m.allFinite() &&
                      s.x.v_mps.allFinite() && s.x.q_mb.coeffs().allFinite() && s.x.bg_rads.allFinite() &&
                      s.x.ba_mps2.allFinite() && s.p.allFinite();
  const bool flags_ok = s.initialized <= 1U && s.last_imu_ok <= 1U;
  const bool unit_q = std::abs(s.x.q_mb.squaredNorm() - 1.0) < 1e-9;
  const bool hist_ok = hist_read && history_valid(s.hist, s.t_s, s.initialized != 0U);
  return (r.ok() && finite && flags_ok && unit_q && hist_ok) ? BlockError::kOk : BlockError::kBadContent;
}

}  // namespace

const FilterState* read_state_block_in_place(const std::uint8_t* data, std::uint32_t n, BlockError& err) noexcept {
  err = BlockError::kBadSize;
  if (data == nullptr || n != kStateBlockBytes) {
    return nullptr;
  }
  ByteReader r(data, n);
  const std::uint32_t magic = r.u32();
  const std::uint32_t version = r.u32();
  const std::uint32_t size = r.u32();
  const std::uint32_t reserved = r.u32();
  ByteReader crc_r(data + kCrcOffset, 4U);
  if (magic != kStateMagic) {
    err = BlockError::kBadMagic;
  } else if (version != kStateVersion) {
    err = BlockError::kBadVersion;
  } else if (crc_r.u32() != crc32(data, kCrcOffset)) {
    err = BlockError::kBadChecksum;
  } else if (size != kStateBlockBytes || reserved != 0U) {
    err = BlockError::kBadContent;
  } else {
    err = read_body(r, g_scratch);
  }
  return err == BlockError::kOk ? &g_scratch : nullptr;
}

BlockError read_state_block(const std::uint8_t* data, std::uint32_t n, FilterState& out) noexcept {
  BlockError e = BlockError::kOk;
  const FilterState* s = read_state_block_in_place(data, n, e);
  if (s != nullptr) {
    out = *s;
  }
  return e;
}

}  // namespace trn::filter
