/**
 * @file truth_sim.hpp
 * @brief Test truth for the filter: a smooth descent with attitude oscillation, its IMU
 *        increments by fine integration, LN-200-class errors, landmark bearings, and NEES tools.
 *
 * Trajectory (map frame ENU): p(t) = p0 + v0 t + c t^2/2 + A sin(w t) per axis,
 * so velocity and acceleration are exact. Body rate: sinusoids of a few deg/s.
 * Attitude: integrated from the body rate with 1 ms exact-exponential substeps.
 * IMU increments over 10 ms: the integral of body rate and of body-frame
 * specific force R^T (a - g(h)), midpoint rule on the same 1 ms substeps.
 */
#pragma once

#include "bsp_tile64/api/camera_model.hpp"
#include "bsp_tile64/api/frames.hpp"
#include "bsp_tile64/api/imu_sample.hpp"
#include "bsp_tile64/emu/rng.hpp"
#include "trn/filter/ekf.hpp"
#include "trn/filter/filter_config.hpp"
#include "trn/filter/linalg.hpp"
#include "trn/match.hpp"

#include <cmath>
#include <cstdint>

namespace filter_test {

using trn::filter::Mat3;
using trn::filter::Quat;
using trn::filter::Vec3;

inline constexpr double kPi = 3.14159265358979323846;

/** Analytic translational motion. */
struct Motion {
  Vec3 p0{120.0, -250.0, 4200.0};
  Vec3 v0{18.0, 6.0, -70.0};
  Vec3 c{0.0, 0.0, 0.8};
  Vec3 amp{3.0, 2.0, 1.5};
  Vec3 w{0.4, 0.3, 0.5};
  [[nodiscard]] Vec3 pos(double t) const {
    return p0 + v0 * t + 0.5 * c * t * t + Vec3(amp.x() * std::sin(w.x() * t), amp.y() * std::sin(w.y() * t),
                                                amp.z() * std::sin(w.z() * t));
  }
  [[nodiscard]] Vec3 vel(double t) const {
    return v0 + c * t + Vec3(amp.x() * w.x() * std::cos(w.x() * t), amp.y() * w.y() * std::cos(w.y() * t),
                             amp.z() * w.z() * std::cos(w.z() * t));
  }
  [[nodiscard]] Vec3 acc(double t) const {
    return c - Vec3(amp.x() * w.x() * w.x() * std::sin(w.x() * t), amp.y() * w.y() * w.y() * std::sin(w.y() * t),
                    amp.z() * w.z() * w.z() * std::sin(w.z() * t));
  }
};

/** Body angular rate, rad/s: a parachute-like oscillation. */
inline Vec3 body_rate(double t) {
  return {0.06 * std::sin(2.0 * kPi * 0.3 * t), 0.05 * std::sin(2.0 * kPi * 0.25 * t + 1.0),
          0.02 * std::cos(2.0 * kPi * 0.1 * t)};
}

/** Initial attitude: camera (body z) down, heading 30 deg off east. */
inline Quat initial_attitude() {
  return Quat(Eigen::AngleAxisd(kPi / 6.0, Vec3::UnitZ())) * Quat(Eigen::AngleAxisd(kPi, Vec3::UnitX()));
}

/** Truth plus IMU model. noisy = false gives exact increments and zero biases. */
class TruthSim {
 public:
  TruthSim(std::uint64_t seed, bool noisy, const trn::filter::ImuSpec& spec)
      : rng_(seed, bsp::StreamId::kSensor, 0), noisy_(noisy), spec_(spec), q_(initial_attitude()) {
    if (noisy_) {
      for (int i = 0; i < 3; ++i) {
        bg_on_(i) = rng_.normal(0.0, spec.gyro_bias_on_rads);
        ba_on_(i) = rng_.normal(0.0, spec.accel_bias_on_mps2);
        bg_run_(i) = rng_.normal(0.0, spec.gyro_bias_run_rads);
        ba_run_(i) = rng_.normal(0.0, spec.accel_bias_run_mps2);
      }
    }
  }

  /** Advances the truth by one IMU interval and returns the sample the IMU reports. */
  bsp::ImuSample next_imu() {
    constexpr int kSub = 10;
    const double h = kDt / kSub;
    Vec3 dth = Vec3::Zero();
    Vec3 dv = Vec3::Zero();
    for (int k = 0; k < kSub; ++k) {
      const double tm = t_ + (k + 0.5) * h;
      const Vec3 w = body_rate(tm);
      const Quat q_mid = q_ * trn::filter::quat_exp(0.5 * h * w);
      const Vec3 pm = motion_.pos(tm);
      const Vec3 g(0.0, 0.0, -bsp::frames::gravity_mps2(pm.z()));
      dth += h * w;
      dv += h * (q_mid.conjugate() * (motion_.acc(tm) - g));
      q_ = (q_ * trn::filter::quat_exp(h * w)).normalized();
    }
    t_ += kDt;
    bsp::ImuSample s{};
    s.seq = seq_++;
    s.status = 0;
    s.t_s = t_;
    if (noisy_) {
      add_errors(dth, dv);
    }
    for (int i = 0; i < 3; ++i) {
      s.dtheta_rad[i] = dth(i);
      s.dv_mps[i] = dv(i);
    }
    return s;
  }

  [[nodiscard]] double t() const { return t_; }
  [[nodiscard]] Vec3 p() const { return motion_.pos(t_); }
  [[nodiscard]] Vec3 v() const { return motion_.vel(t_); }
  [[nodiscard]] const Quat& q() const { return q_; }
  [[nodiscard]] Vec3 bg() const { return bg_on_ + bg_run_; }
  [[nodiscard]] Vec3 ba() const { return ba_on_ + ba_run_; }

  /**
   * @p n bearings to landmarks at random pixels, on ground between -100 m and
   * +100 m height, with Gaussian pixel noise @p sigma_px (drawn from @p rng).
   */
  void make_matches(bsp::Rng& rng, const bsp::CameraModel& cam, int n, double sigma_px, trn::Match* out) const {
    const Mat3 r_mb = q_.toRotationMatrix();
    Mat3 r_bc;
    for (int i = 0; i < 9; ++i) {
      r_bc(i / 3, i % 3) = cam.r_bc[i];
    }
    for (int i = 0; i < n; ++i) {
      const double u = rng.uniform(20.0, cam.width_px - 20.0);
      const double v = rng.uniform(20.0, cam.height_px - 20.0);
      const Vec3 d_m = r_mb * r_bc * Vec3((u - cam.cx_px) / cam.fx_px, (v - cam.cy_px) / cam.fy_px, 1.0);
      const double h_lm = rng.uniform(-100.0, 100.0);
      const Vec3 lm = p() + ((h_lm - p().z()) / d_m.z()) * d_m;
      const double un = u + rng.normal(0.0, sigma_px);
      const double vn = v + rng.normal(0.0, sigma_px);
      const Vec3 w = Vec3((un - cam.cx_px) / cam.fx_px, (vn - cam.cy_px) / cam.fy_px, 1.0).normalized();
      trn::Match& m = out[i];
      m = trn::Match{};
      for (int k = 0; k < 3; ++k) {
        m.w_c[k] = w(k);
        m.p_m[k] = lm(k);
      }
      m.u_px = un;
      m.v_px = vn;
      m.sigma_px = sigma_px;
      m.quality = 0.9F;
      m.landmark = static_cast<std::uint16_t>(i);
      m.t_s = t_;  // the image is taken now
    }
  }

  static constexpr double kDt = 0.01;

 private:
  void add_errors(Vec3& dth, Vec3& dv) {
    const double fg = std::exp(-kDt / spec_.gyro_bias_tau_s);
    const double fa = std::exp(-kDt / spec_.accel_bias_tau_s);
    for (int i = 0; i < 3; ++i) {
      dth(i) += (bg_on_(i) + bg_run_(i)) * kDt + rng_.normal(0.0, spec_.gyro_arw_rad_sqrts * std::sqrt(kDt));
      dv(i) += (ba_on_(i) + ba_run_(i)) * kDt + rng_.normal(0.0, spec_.accel_vrw_mps_sqrts * std::sqrt(kDt));
      bg_run_(i) = fg * bg_run_(i) + rng_.normal(0.0, spec_.gyro_bias_run_rads * std::sqrt(1.0 - fg * fg));
      ba_run_(i) = fa * ba_run_(i) + rng_.normal(0.0, spec_.accel_bias_run_mps2 * std::sqrt(1.0 - fa * fa));
    }
  }

  bsp::Rng rng_;
  bool noisy_;
  trn::filter::ImuSpec spec_;
  Motion motion_{};
  double t_ = 0.0;
  std::uint32_t seq_ = 0;
  Quat q_;
  Vec3 bg_on_ = Vec3::Zero();
  Vec3 ba_on_ = Vec3::Zero();
  Vec3 bg_run_ = Vec3::Zero();
  Vec3 ba_run_ = Vec3::Zero();
};

/** Filter estimate drawn around the truth with the given sigmas (consistent initial error). */
inline trn::filter::InitialEstimate perturbed_estimate(const TruthSim& truth, bsp::Rng& rng, double sp, double sv,
                                                       double sth) {
  trn::filter::InitialEstimate e;
  e.t_s = truth.t();
  Vec3 dp;
  Vec3 dv;
  Vec3 dth;
  for (int i = 0; i < 3; ++i) {
    dp(i) = rng.normal(0.0, sp);
    dv(i) = rng.normal(0.0, sv);
    dth(i) = rng.normal(0.0, sth);
  }
  e.x.p_m = truth.p() - dp;
  e.x.v_mps = truth.v() - dv;
  e.x.q_mb = (truth.q() * trn::filter::quat_exp(-dth)).normalized();
  e.sigma_p_m = Vec3::Constant(sp);
  e.sigma_v_mps = Vec3::Constant(sv);
  e.sigma_th_rad = Vec3::Constant(sth);
  return e;
}

/** NEES of the position, velocity and attitude blocks: truth minus estimate against P. */
struct Nees3 {
  double p = 0.0;
  double v = 0.0;
  double th = 0.0;
};

inline Nees3 nees(const TruthSim& truth, const trn::filter::FilterState& s) {
  using trn::filter::kIdxP;
  using trn::filter::kIdxTh;
  using trn::filter::kIdxV;
  const Vec3 ep = truth.p() - s.x.p_m;
  const Vec3 ev = truth.v() - s.x.v_mps;
  const Vec3 eth = trn::filter::quat_log(s.x.q_mb.conjugate() * truth.q());
  Nees3 n;
  n.p = ep.dot(s.p.block<3, 3>(kIdxP, kIdxP).inverse() * ep);
  n.v = ev.dot(s.p.block<3, 3>(kIdxV, kIdxV).inverse() * ev);
  n.th = eth.dot(s.p.block<3, 3>(kIdxTh, kIdxTh).inverse() * eth);
  return n;
}

/** Regularized lower incomplete gamma P(a, x): series below a+1, continued fraction above. */
inline double gamma_p(double a, double x) {
  if (x <= 0.0) {
    return 0.0;
  }
  const double log_pre = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a;
    double sum = term;
    for (int n = 1; n < 1000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (term < sum * 1e-16) {
        break;
      }
    }
    return sum * std::exp(log_pre);
  }
  double b = x + 1.0 - a;
  double c = 1e300;
  double d = 1.0 / b;
  double h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    d = 1.0 / d;
    c = b + an / c;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-16) {
      break;
    }
  }
  return 1.0 - std::exp(log_pre) * h;
}

/** Quantile of the chi-square distribution with @p dof degrees of freedom, by bisection. */
inline double chi2_quantile(double prob, double dof) {
  double lo = 0.0;
  double hi = dof + 20.0 * std::sqrt(2.0 * dof) + 20.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (gamma_p(0.5 * dof, 0.5 * mid) < prob) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

}  // namespace filter_test
