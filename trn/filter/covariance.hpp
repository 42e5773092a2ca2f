/**
 * @file covariance.hpp
 * @brief Covariance operations of the error-state filter: process noise, propagation,
 *        gated 2D Kalman update with a sparse H, and the attitude reset.
 *
 * All 15x15 work matrices live in CovWork, owned by the filter object (static
 * storage), so no function here puts more than a few small matrices on the stack.
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "fdir/abft.hpp"
#include "trn/filter/filter_config.hpp"
#include "trn/filter/linalg.hpp"

#include <array>
#include <cstdint>

namespace trn::filter {

/**
 * Publication channel (bsp::publish_filter) of the covariance propagation's
 * two products, F P and (F P) F^T, each before its checksums are checked:
 * where an `sdc` corrupts a product inside the filter (trn/tasks/sdc_points.hpp).
 */
inline constexpr std::uint32_t kFilterProductChannel = 5;
/** Sites of the checked products (fdir::AbftSite::id, the abft events' subject). */
inline constexpr std::uint32_t kAbftSiteFp = 1;    ///< F P
inline constexpr std::uint32_t kAbftSiteFpft = 2;  ///< (F P) F^T

/**
 * Publication channel of the update's three checked products, each before
 * its row checksums are checked (`filter_update_product`). One channel for
 * the three: a fault armed there corrupts the next one computed, in flight
 * P H^T of the next measurement.
 */
inline constexpr std::uint32_t kFilterUpdateProductChannel = 8;
/** Sites of the update's checked products, in the order kalman_update computes them. */
inline constexpr std::uint32_t kAbftSitePht = 3;     ///< P H^T (15x2)
inline constexpr std::uint32_t kAbftSiteGain = 4;    ///< the gain K = (P H^T) S^-1 (15x2)
inline constexpr std::uint32_t kAbftSiteKpht = 5;    ///< K (P H^T)^T (15x15, symmetric: its upper triangle)
/** Number of the update's sites (kAbftSitePht + i, i < this). */
inline constexpr std::uint32_t kUpdateSites = 3;
/** CovWork::update_sdc_sites with every update site publishing (flight). */
inline constexpr std::uint32_t kAllUpdateSites = (1U << kUpdateSites) - 1U;
/** Columns of the error state H reads (position, velocity, attitude): the dense operand of X H^T's checks. */
inline constexpr int kHtRows = kIdxBg;

/** Work matrices of the covariance operations (about 7.6 KB; keep out of task stacks). */
struct CovWork {
  Mat15 fp = Mat15::Zero();      ///< F P during propagation
  Mat15 kx = Mat15::Zero();      ///< K (P H^T)^T during an update (its upper triangle only)
  Mat15x2 pht = Mat15x2::Zero(); ///< P H^T (then (P - D) H^T for a lagged match)
  Mat15x2 k = Mat15x2::Zero();   ///< Kalman gain
  Eigen::Matrix<double, kHtRows, 2> ht = Eigen::Matrix<double, kHtRows, 2>::Zero();  ///< H^T's non-zero rows
  fdir::AbftSums<kErrDim, kErrDim, kErrDim> abft{};  ///< checksums of the propagation's products
  fdir::AbftSums<kErrDim, kHtRows, 2> abft_ht{};     ///< row checksums of P H^T
  fdir::AbftSums<kErrDim, 2, 2> abft_gain{};         ///< of the gain
  fdir::AbftUpperSums<kErrDim, 2> abft_kt{};         ///< of K (P H^T)^T's upper triangle
  fdir::AbftResult last_fp{};    ///< the last propagation's checks (kClean unless a product was wrong)
  fdir::AbftResult last_fpft{};
  /** The last kalman_update's checks, by site - kAbftSitePht (kClean for a product not reached). */
  std::array<fdir::AbftResult, kUpdateSites> last_update{};
  /**
   * Bit i set: site kAbftSitePht + i publishes its product on
   * kFilterUpdateProductChannel. All in flight; a test opens one site at a
   * time to corrupt a product other than the first.
   */
  std::uint32_t update_sdc_sites = kAllUpdateSites;
};

/**
 * Process noise the filter added between a lagged measurement's time and now,
 * isotropic per block (D = [q_pp I, q_pv I, 0; q_pv I, q_vv I, 0; 0, 0, q_th I]
 * on position, velocity, attitude). The measurement saw the state before that
 * noise, so it is weighed against P - D, and D is added back after the update
 * (the noise is independent of the measurement). Zero for a current match.
 */
struct LagNoise {
  double q_pp = 0.0;
  double q_pv = 0.0;
  double q_vv = 0.0;
  double q_th = 0.0;
};

/**
 * A 2D measurement whose Jacobian is non-zero only in the position, velocity and
 * attitude columns: H = [Hp, -lag Hp, Hth, 0, 0]. r is the residual, r_var the
 * (diagonal) noise. lag_s > 0 for a bearing measured lag_s before the state's
 * time: its position error then was dp - lag dv (pose_history.hpp); with
 * lag_s == 0 the velocity columns are skipped, not multiplied by zero.
 */
struct Meas2 {
  Mat23 hp = Mat23::Zero();
  Mat23 hth = Mat23::Zero();
  double lag_s = 0.0;
  LagNoise d{};
  Vec2 r = Vec2::Zero();
  Vec2 r_var = Vec2::Ones();
};

/** D of the process noise of @p imu over @p lag_s seconds (velocity and angle random walks). */
LagNoise lag_noise(const ImuSpec& imu, double lag_s) noexcept;

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
 * only those blocks are read. Each of the two products is checked against
 * full checksums (fdir/abft.hpp) and computed again while wrong (the results
 * in w.last_fp, w.last_fpft; a product still wrong is reported and kept).
 */
void propagate_covariance(Mat15& p, const Mat15& f, const Vec15& q, CovWork& w, bsp::Work& work) noexcept;

/** Outcome of one gated update. */
struct GateResult {
  double d2 = 0.0;             ///< Mahalanobis distance squared of the residual
  bool accepted = false;       ///< d2 <= gate, S invertible, every product checked right, variances kept positive
  bool check_failed = false;   ///< a product still wrong after its recomputations: nothing applied
  bool variance_lost = false;  ///< the update would leave a variance <= 0 (round-off): nothing applied
};

/**
 * Gated Kalman update: S = H P H^T + R, d2 = r^T S^-1 r; if d2 <= gate,
 * K = P H^T S^-1, P <- P - K (P H^T)^T and dx = K r. K (P H^T)^T =
 * P H^T S^-1 H P is symmetric: its upper triangle is computed and mirrored,
 * so P comes out exactly symmetric. A lagged measurement weighs P - m.d (the
 * process noise added since the image) in P H^T and S; D comes back after
 * the update, which leaves P - K ((P - D) H^T)^T, so P itself is never
 * touched by D. m.d is ignored (taken as zero) unless every diagonal entry
 * of P it touches exceeds twice its own. An update that would leave a
 * variance <= 0 is refused (variance_lost). A rejected measurement leaves P
 * and dx untouched.
 *
 * Three products are checked on their row checksums (fdir/abft.hpp, rows
 * only; sites kAbftSitePht..kAbftSiteKpht, results in w.last_update) and
 * computed again while wrong. One still wrong after its recomputations
 * (reported abft_failed) is not applied: P is written only after the last
 * check, so the measurement is dropped, P and dx untouched, and the result
 * says check_failed (not accepted). Pre: P symmetric positive definite.
 */
GateResult kalman_update(Mat15& p, const Meas2& m, double gate_chi2, Vec15& dx, CovWork& w,
                         bsp::Work& work) noexcept;

/**
 * Covariance reset after injecting an attitude error dth into the nominal
 * quaternion: P <- G P G^T with G = I except G_thth = I - [dth/2]x. Pre: P
 * symmetric; the attitude rows are transformed and mirrored into the columns,
 * so P stays exactly symmetric.
 */
void reset_attitude(Mat15& p, const Vec3& dth, bsp::Work& work) noexcept;

/** Makes P exactly symmetric: upper and lower triangles become their mean. */
void symmetrize(Mat15& p) noexcept;

/** Flops of one propagate_covariance call (the cost model charges these). */
// Per side: seven 3x3 by 3x15 block products (135 MAC each) and two scaled rows.
inline constexpr std::uint64_t kFlopsCovPropagate = 2ULL * (7 * 135 * 2 + 2 * 15 * 2) + 15 + 210;
/**
 * Flops of one accepted kalman_update, its checks apart (a rejected one costs
 * kFlopsGate and the check of P H^T).
 */
// Gate: P H^T (15x6 by 6x2), S (2x6 by 6x2, + R), det, d2, S^-1 as four products with 1 / det (the one division).
inline constexpr std::uint64_t kFlopsGate = 360 + 2 * 2 * 6 * 2 + 12 + 8 + 4;
// K (15x2 by 2x2), the upper triangle of K (P H^T)^T (120 entries of 2 MAC),
// the diagonal's sign test (15), P minus that triangle (120), dx = K r.
inline constexpr std::uint64_t kFlopsUpdate = kFlopsGate + 120 + 480 + 15 + 120 + 60;
/**
 * Extra flops of a lagged measurement: P - lag P_v on two sets of six columns,
 * and in S; D H^T off P H^T; -lag H_p in the checks' dense H^T. The update
 * itself adds none (D cancels out of P - K (P H^T)^T).
 */
inline constexpr std::uint64_t kFlopsLagGate = 90 + 12 + 9 + 40 + 6;
/** Flops of lag_noise(). */
inline constexpr std::uint64_t kFlopsLagNoise = 12;
/** Flops of one reset_attitude call: G times the attitude rows, then the attitude block. */
inline constexpr std::uint64_t kFlopsReset = 6 + 3 * 15 * 5 + 3 * 3 * 5 + 6;

}  // namespace trn::filter
