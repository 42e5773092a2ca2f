/**
 * @file covariance.hpp
 * @brief Covariance operations of the error-state filter: process noise, propagation,
 *        gated 2D Joseph update with a sparse H, and the attitude reset.
 *
 * All 15x15 work matrices live in CovWork, owned by the filter object (static
 * storage), so no function here puts more than a few small matrices on the stack.
 */
#pragma once

#include "bsp_tile64/work.hpp"
#include "trn/filter/filter_config.hpp"
#include "trn/filter/linalg.hpp"

namespace trn::filter {

/** Work matrices of the covariance operations (about 5.4 KB; keep out of task stacks). */
struct CovWork {
  Mat15 fp = Mat15::Zero();      ///< F P during propagation; (I - K H) P during an update
  Mat15x2 pht = Mat15x2::Zero(); ///< P H^T
  Mat15x2 k = Mat15x2::Zero();   ///< Kalman gain
  Mat15x2 mht = Mat15x2::Zero(); ///< (I - K H) P H^T
};

/**
 * A 2D measurement whose Jacobian is non-zero only in the position and attitude
 * columns: H = [Hp, 0, Hth, 0, 0]. r is the residual, r_var the (diagonal) noise.
 */
struct Meas2 {
  Mat23 hp = Mat23::Zero();
  Mat23 hth = Mat23::Zero();
  Vec2 r = Vec2::Zero();
  Vec2 r_var = Vec2::Ones();
};

/**
 * Discrete process noise per interval dt (diagonal): velocity random walk and
 * angle random walk on v and theta, and for each bias the increment variance
 * of its in-run Gauss-Markov process, sigma^2 (1 - exp(-2 dt / tau)).
 * The bias states carry no decay (the turn-on part is a constant), so the
 * in-run part is a random walk with the Gauss-Markov step variance: its
 * variance never falls below the Gauss-Markov one (conservative).
 */
Vec15 process_noise_diag(const ImuSpec& imu, double dt_s) noexcept;

/**
 * P <- F P F^T + diag(q), then symmetrized. Pre: P symmetric; F has the
 * sparsity strapdown_step() writes (identity outside its documented blocks):
 * only those blocks are read.
 */
void propagate_covariance(Mat15& p, const Mat15& f, const Vec15& q, CovWork& w, bsp::Work& work) noexcept;

/** Outcome of one gated update. */
struct GateResult {
  double d2 = 0.0;          ///< Mahalanobis distance squared of the residual
  bool accepted = false;    ///< d2 <= gate and S invertible
};

/**
 * Gated Joseph-form update: S = H P H^T + R, d2 = r^T S^-1 r; if d2 <= gate,
 * K = P H^T S^-1, P <- (I-KH) P (I-KH)^T + K R K^T (computed in factored form,
 * never forming I-KH), symmetrized, and dx = K r. A rejected measurement
 * leaves P and dx untouched. Pre: P symmetric positive definite.
 */
GateResult joseph_update(Mat15& p, const Meas2& m, double gate_chi2, Vec15& dx, CovWork& w,
                         bsp::Work& work) noexcept;

/**
 * Covariance reset after injecting an attitude error dth into the nominal
 * quaternion: P <- G P G^T with G = I except G_thth = I - [dth/2]x, then symmetrized.
 */
void reset_attitude(Mat15& p, const Vec3& dth, bsp::Work& work) noexcept;

/** Makes P exactly symmetric: upper and lower triangles become their mean. */
void symmetrize(Mat15& p) noexcept;

/** Flops of one propagate_covariance call (the cost model charges these). */
// Per side: seven 3x3 by 3x15 block products (135 MAC each) and two scaled rows.
inline constexpr std::uint64_t kFlopsCovPropagate = 2ULL * (7 * 135 * 2 + 2 * 15 * 2) + 15 + 210;
/** Flops of one accepted joseph_update (a rejected one costs kFlopsGate). */
inline constexpr std::uint64_t kFlopsGate = 360 + 2 * 2 * 6 * 2 + 12 + 8;
inline constexpr std::uint64_t kFlopsJoseph = kFlopsGate + 120 + 900 + 360 + 60 + 900 + 210 + 60;
/** Flops of one reset_attitude call. */
inline constexpr std::uint64_t kFlopsReset = 2ULL * 15 * 3 * 5 + 6 + 210;

}  // namespace trn::filter
