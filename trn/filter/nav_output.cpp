/**
 * @file nav_output.cpp
 * @brief Navigation solution record and its byte form.
 */
#include "trn/filter/nav_output.hpp"

#include "trn/filter/byte_io.hpp"

#include <cmath>

namespace trn::filter {

namespace {

std::uint32_t solution_flags(const FilterState& s, const FilterConfig& cfg) noexcept {
  std::uint32_t f = 0;
  const bool finite = s.x.p_m.allFinite() && s.x.v_mps.allFinite() && s.x.q_mb.coeffs().allFinite() &&
                      s.p.allFinite();
  f |= s.initialized != 0U ? kNavInitialized : 0U;
  f |= finite ? kNavFinite : 0U;
  f |= (s.p.diagonal().minCoeff() > 0.0) ? kNavCovPositive : 0U;
  f |= s.last_imu_ok != 0U ? kNavImuOk : 0U;
  f |= (s.t_s - s.t_last_update_s <= cfg.stale_update_s) ? kNavFresh : 0U;
  const double var_p = s.p.diagonal().segment<3>(kIdxP).maxCoeff();
  f |= (var_p < cfg.max_sigma_pos_m * cfg.max_sigma_pos_m) ? kNavPosBounded : 0U;
  constexpr std::uint32_t kAll =
      kNavInitialized | kNavFinite | kNavCovPositive | kNavImuOk | kNavFresh | kNavPosBounded;
  f |= (f & kAll) == kAll ? kNavValid : 0U;
  return f;
}

}  // namespace

NavOutput make_nav_output(const FilterState& s, const FilterConfig& cfg) noexcept {
  NavOutput o;
  o.propagations = s.c.propagations;
  o.t_s = s.t_s;
  for (int i = 0; i < 3; ++i) {
    o.p_m[i] = s.x.p_m(i);
    o.v_mps[i] = s.x.v_mps(i);
  }
  o.q_mb_wxyz[0] = s.x.q_mb.w();
  o.q_mb_wxyz[1] = s.x.q_mb.x();
  o.q_mb_wxyz[2] = s.x.q_mb.y();
  o.q_mb_wxyz[3] = s.x.q_mb.z();
  for (int i = 0; i < kErrDim; ++i) {
    o.var_diag[i] = s.p(i, i);
  }
  for (int i = 0; i < 3; ++i) {
    o.pos_var_world[i] = o.var_diag[i] + cfg.map_tie_sigma_m[i] * cfg.map_tie_sigma_m[i];
  }
  o.flags = solution_flags(s, cfg);
  o.last_accepted = s.c.last_accepted;
  o.last_rejected = s.c.last_rejected;
  o.imu_gaps = s.c.imu_gaps;
  return o;
}

void write_nav_output(const NavOutput& o, NavOutputBytes& out) noexcept {
  ByteWriter w(out.data(), kNavOutputBytes);
  w.u32(kNavMagic);
  w.u32(kNavVersion);
  w.u64(o.propagations);
  w.f64(o.t_s);
  for (const double v : o.p_m) {
    w.f64(v);
  }
  for (const double v : o.v_mps) {
    w.f64(v);
  }
  for (const double v : o.q_mb_wxyz) {
    w.f64(v);
  }
  for (const double v : o.var_diag) {
    w.f64(v);
  }
  w.u32(o.flags);
  w.u32(o.last_accepted);
  w.u32(o.last_rejected);
  w.u32(o.imu_gaps);
  for (const double v : o.pos_var_world) {
    w.f64(v);
  }
  w.u32(crc32(out.data(), kNavOutputBytes - 4U));
}

}  // namespace trn::filter
