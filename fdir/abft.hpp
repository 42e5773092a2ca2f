/**
 * @file abft.hpp
 * @brief Algorithm-based fault tolerance of matrix products (Huang and Abraham 1984): full
 *        checksums of C = A B, a tolerance that separates a fault from round-off, the wrong
 *        element located, the product recomputed a bounded number of times, events.
 *
 * For C = A B (A m x k, B k x n) and e the vector of ones, exact arithmetic
 * gives C e = A (B e) and e^T C = (e^T A) B. The references on the right and
 * their tolerances cost four matrix-vector products and four sums of A and B
 * (about 2 (m k + k n) multiply-adds), the check two sums of C, against
 * m k n multiply-adds for the product: O(n^2) against O(n^3).
 *
 * Tolerance. In floating point (unit roundoff u = 2^-53) each side carries
 * round-off. With gamma_j = j u / (1 - j u) and |.| taken elementwise:
 *   computed C        = A B + E1,            |E1| <= gamma_k |A| |B|
 *   computed C e      = C e + E2,            |E2| <= gamma_n |C| e
 *   computed B e      = B e + E3,            |E3| <= gamma_n |B| e
 *   computed A (B e)  = A fl(B e) + E4,      |E4| <= gamma_k |A| |fl(B e)|
 * so the row residual r = fl(C e) - fl(A fl(B e)) obeys, to first order in u,
 *   |r_i| <= (2 k + 2 n) u (|A| (|B| e))_i,
 * and the column residual likewise with m in place of n. The check allows
 *   tol_i = kAbftSafety (k + n + 2) u (|A| (|B| e))_i + kAbftFloor
 * (the safety factor 8 covers the second-order terms and leaves a factor 4 over
 * the first-order bound; kAbftFloor covers products of subnormal numbers).
 * Because the bound is elementwise (|A| |B|, not norms), a row of small
 * numbers is checked against its own scale, not against the matrix's largest
 * entry: an error of a few ulps of a covariance's bias block is seen even when
 * its position block is 12 orders of magnitude larger. An error below the
 * tolerance is not seen; it is of the size of the round-off the product makes
 * anyway (stated in docs/FDIR.md).
 *
 * Locating and correcting. One wrong element C(i, j) makes exactly row i and
 * column j fail, by the same amount: it is located. The product is then
 * computed again by the same kernel (not patched from the checksum, which is
 * exact only to round-off: a recomputed product is bit for bit the clean one,
 * which replicas and replays compare) and checked again, at most
 * kAbftMaxRecompute times. Anything else (several rows or columns, a
 * non-finite value) is recomputed the same way. Still wrong after that, the
 * product is reported failed and the caller decides.
 *
 * Rows only. A thin product (the filter update's 15 x 2 and 15 x 2 x 15 ones)
 * can be checked on its row sums alone (AbftSite::rows_only): C e against
 * A (B e), one sum of B, one matrix-vector product and one sum of C, about
 * half the full check. A wrong element still fails its row, so the product
 * is still found wrong and recomputed, and the row is located; the column is
 * not (AbftResult::col stays -1). What a row check cannot see that a full one
 * can: an error below its row's tolerance but above its column's, i.e. an
 * element many orders of magnitude smaller than the rest of its row.
 *
 * Symmetric outer products. The Kalman update's K (P H^T)^T is symmetric;
 * abft_upper_product computes its upper triangle only and checks each row of
 * the triangle against K_i times the suffix sum of the other operand's rows
 * (row i holds columns i..m-1), the same row check for a triangle.
 *
 * Flight code: no allocation, fixed-size Eigen matrices, bounded loops.
 */
#pragma once

#include "bsp_tile64/api/port.hpp"
#include "bsp_tile64/api/work.hpp"
#include "fdir/event_ids.hpp"

#include <Eigen/Core>

#include <cmath>
#include <cstdint>

namespace fdir {

/** Unit roundoff of IEEE double. */
inline constexpr double kAbftUnitRoundoff = 0x1p-53;
/** Factor over the first-order round-off bound of a residual (see the file comment). */
inline constexpr double kAbftSafety = 8.0;
/** Absolute floor of every tolerance (subnormal products). */
inline constexpr double kAbftFloor = 1e-300;
/** Recomputations of a product found wrong before it is reported failed. */
inline constexpr std::uint32_t kAbftMaxRecompute = 2U;

enum class AbftVerdict : std::uint8_t {
  kClean,      ///< the first computation passed
  kCorrected,  ///< found wrong, recomputed, then passed
  kFailed,     ///< still wrong after kAbftMaxRecompute recomputations
};

/**
 * Flops counted for checking a product of an m x k and a k x n matrix that
 * passes (references, the two sums of C, no tolerance computed): what a
 * caller's budget adds per checked product.
 */
constexpr std::uint64_t abft_clean_flops(std::uint64_t m, std::uint64_t k, std::uint64_t n) noexcept {
  return (k * n + m * k) + 2U * (m * k + k * n) + 2U * m * n + 4U * (m + n);
}

/**
 * Flops counted for a rows-only check (AbftSite::rows_only) of an m x k times
 * k x n product that passes: B e, A (B e), C e and the comparisons.
 */
constexpr std::uint64_t abft_rows_flops(std::uint64_t m, std::uint64_t k, std::uint64_t n) noexcept {
  return k * n + 2U * m * k + m * n + 4U * m;
}

/**
 * The most a rows-only check of a right product can add to abft_rows_flops:
 * every row's residual above the free lower bound of its tolerance (a row sum
 * that cancels), so |B| e and every row's exact tolerance computed.
 */
constexpr std::uint64_t abft_rows_tolerance_flops(std::uint64_t m, std::uint64_t k, std::uint64_t n) noexcept {
  return k * n + m * (2U * k + 2U);
}

/** Where a checked product is (for its events), and where an `sdc` may corrupt its result. */
struct AbftSite {
  std::uint32_t id = 0U;           ///< caller's number of the product (events' subject)
  std::uint32_t sdc_channel = 0U;  ///< bsp::publish_filter channel of the result before the check (0: none)
  bool rows_only = false;          ///< check the row sums only (thin products; the column is not located)
  /**
   * Check the row sums, and only when a row fails the column sums too, to
   * locate the element: a clean product costs a rows-only check, a wrong one
   * is located as by the full check. Detection is the rows' (a wrong element
   * always fails its row; errors that cancel within one row are missed,
   * which the column sums could catch).
   */
  bool rows_first = false;
};


struct AbftResult {
  AbftVerdict verdict = AbftVerdict::kClean;
  int row = -1;                    ///< the wrong element's row, if one element was located (first check)
  int col = -1;                    ///< -1 also when only the rows were checked
  std::uint32_t bad_rows = 0U;     ///< rows and columns past their tolerance at the first check
  std::uint32_t bad_cols = 0U;
  std::uint32_t recomputes = 0U;
  double residual = 0.0;           ///< the located row's residual (the element's error), or the worst row's
};

/**
 * Reference checksums of one product C = A B (M x K times K x N), the
 * tolerances of the rows and columns that needed them, and the scratch their
 * computation needs: the caller's storage (a static or a member), so nothing
 * of it is on the stack. Fixed sizes in flight code; Eigen::Dynamic (sized
 * once by abft_resize) in host tools.
 */
template <int M, int K, int N>
struct AbftSums {
  Eigen::Matrix<double, M, 1> row_ref;  ///< A (B e)
  Eigen::Matrix<double, 1, N> col_ref;  ///< (e^T A) B
  Eigen::Matrix<double, M, 1> row_tol;  ///< tolerances (abft_tolerances; the check fills the ones it needs)
  Eigen::Matrix<double, 1, N> col_tol;
  Eigen::Matrix<double, K, 1> be;       ///< B e
  Eigen::Matrix<double, 1, K> ea;       ///< e^T A
  Eigen::Matrix<double, K, 1> abe;      ///< |B| e (when a tolerance was needed)
  Eigen::Matrix<double, 1, K> eaa;      ///< e^T |A|
  Eigen::Matrix<double, M, 1> rs;       ///< C e, as computed
  Eigen::Matrix<double, 1, N> cs;       ///< e^T C
};

/** Sizes dynamic sums for an m x k times k x n product (host tools; fixed sizes need nothing). */
template <int M, int K, int N>
void abft_resize(AbftSums<M, K, N>& s, Eigen::Index m, Eigen::Index k, Eigen::Index n) {
  s.row_ref.resize(m);
  s.col_ref.resize(n);
  s.row_tol.resize(m);
  s.col_tol.resize(n);
  s.be.resize(k);
  s.ea.resize(k);
  s.abe.resize(k);
  s.eaa.resize(k);
  s.rs.resize(m);
  s.cs.resize(n);
}

/**
 * The reference checksums of C = A B, from the operands (one pass over A and B
 * each, twice; once with @p rows_only, which leaves the column references
 * alone); charges @p work.
 */
template <typename DA, typename DB, int M, int K, int N>
void abft_sums(const Eigen::MatrixBase<DA>& a, const Eigen::MatrixBase<DB>& b, AbftSums<M, K, N>& s,
               bsp::Work& work, bool rows_only = false) noexcept {
  const auto m = static_cast<std::uint64_t>(a.rows());
  const auto k = static_cast<std::uint64_t>(a.cols());
  const auto n = static_cast<std::uint64_t>(b.cols());
  s.be.noalias() = b.rowwise().sum();
  if (rows_only) {
    s.row_ref.noalias() = a.lazyProduct(s.be);
    work.flops += k * n + 2U * m * k;
    work.mem_words += 2U * (m * k + k * n);
    return;
  }
  s.ea.noalias() = a.colwise().sum();
  s.row_ref.noalias() = a.lazyProduct(s.be);
  s.col_ref.noalias() = s.ea.lazyProduct(b);
  work.flops += (k * n + m * k) + 2U * (m * k + k * n);
  work.mem_words += 4U * (m * k + k * n);
}

/** Row and column factors of the tolerance (see the file comment). */
template <int M, int K, int N>
double abft_row_factor(const AbftSums<M, K, N>& s) noexcept {
  return kAbftSafety * static_cast<double>(s.be.size() + s.col_ref.size() + 2) * kAbftUnitRoundoff;
}
template <int M, int K, int N>
double abft_col_factor(const AbftSums<M, K, N>& s) noexcept {
  return kAbftSafety * static_cast<double>(s.be.size() + s.row_ref.size() + 2) * kAbftUnitRoundoff;
}

/** Every row's and column's tolerance into s.row_tol and s.col_tol (tests, tools); charges @p work. */
template <typename DA, typename DB, int M, int K, int N>
void abft_tolerances(const Eigen::MatrixBase<DA>& a, const Eigen::MatrixBase<DB>& b, AbftSums<M, K, N>& s,
                     bsp::Work& work) noexcept {
  s.abe.noalias() = b.cwiseAbs().rowwise().sum();
  s.eaa.noalias() = a.cwiseAbs().colwise().sum();
  s.row_tol.noalias() = a.cwiseAbs().lazyProduct(s.abe);
  s.col_tol.noalias() = s.eaa.lazyProduct(b.cwiseAbs());
  s.row_tol = (s.row_tol.array() * abft_row_factor(s) + kAbftFloor).matrix();
  s.col_tol = (s.col_tol.array() * abft_col_factor(s) + kAbftFloor).matrix();
  const auto mk = static_cast<std::uint64_t>(a.rows() * a.cols());
  const auto kn = static_cast<std::uint64_t>(b.rows() * b.cols());
  work.flops += 3U * (mk + kn);
  work.int_ops += 2U * (mk + kn);  // absolute values (the sign bit)
  work.mem_words += 4U * (mk + kn);
}

namespace detail {

/** The rows of C = A B past their tolerance (s.rs holds C e); into @p r. */
template <typename DA, typename DB, int M, int K, int N>
void abft_check_rows(const Eigen::MatrixBase<DA>& a, const Eigen::MatrixBase<DB>& b, AbftSums<M, K, N>& s,
                     AbftResult& r, bsp::Work& work) noexcept {
  const double f = abft_row_factor(s);
  const auto k = static_cast<std::uint64_t>(a.cols());
  bool abe_ready = false;
  double worst = -1.0;
  for (Eigen::Index i = 0; i < s.rs.size(); ++i) {
    const double d = s.rs(i) - s.row_ref(i);
    if (std::abs(d) <= f * std::abs(s.row_ref(i)) + kAbftFloor) {
      continue;  // within a lower bound of its tolerance
    }
    if (!abe_ready) {
      s.abe.noalias() = b.cwiseAbs().rowwise().sum();
      abe_ready = true;
      const auto kn = static_cast<std::uint64_t>(b.rows() * b.cols());
      work += bsp::Work{kn, 0U, kn, 0U, kn};
    }
    s.row_tol(i) = f * a.row(i).cwiseAbs().dot(s.abe.transpose()) + kAbftFloor;
    work += bsp::Work{0U, 0U, 2U * k + 2U, 0U, 2U * k};
    if (!(std::abs(d) <= s.row_tol(i))) {
      ++r.bad_rows;
      const double excess = std::isfinite(d) ? std::abs(d) / s.row_tol(i) : HUGE_VAL;
      if (excess > worst) {
        worst = excess;
        r.row = static_cast<int>(i);
        r.residual = d;
      }
    }
  }
}

/** The columns of C = A B past their tolerance (s.cs holds e^T C); into @p r. */
template <typename DA, typename DB, int M, int K, int N>
void abft_check_cols(const Eigen::MatrixBase<DA>& a, const Eigen::MatrixBase<DB>& b, AbftSums<M, K, N>& s,
                     AbftResult& r, bsp::Work& work) noexcept {
  const double f = abft_col_factor(s);
  const auto k = static_cast<std::uint64_t>(a.cols());
  bool eaa_ready = false;
  double worst = -1.0;
  for (Eigen::Index j = 0; j < s.cs.size(); ++j) {
    const double d = s.cs(j) - s.col_ref(j);
    if (std::abs(d) <= f * std::abs(s.col_ref(j)) + kAbftFloor) {
      continue;
    }
    if (!eaa_ready) {
      s.eaa.noalias() = a.cwiseAbs().colwise().sum();
      eaa_ready = true;
      const auto mk = static_cast<std::uint64_t>(a.rows() * a.cols());
      work += bsp::Work{mk, 0U, mk, 0U, mk};
    }
    s.col_tol(j) = f * s.eaa.dot(b.col(j).cwiseAbs().transpose()) + kAbftFloor;
    work += bsp::Work{0U, 0U, 2U * k + 2U, 0U, 2U * k};
    if (!(std::abs(d) <= s.col_tol(j))) {
      ++r.bad_cols;
      const double excess = std::isfinite(d) ? std::abs(d) / s.col_tol(j) : HUGE_VAL;
      if (excess > worst) {
        worst = excess;
        r.col = static_cast<int>(j);
      }
    }
  }
}

}  // namespace detail

/**
 * Checks @p c = A B against @p s: the rows and columns whose residual passes
 * their tolerance (a NaN fails). Each residual is first held against a lower
 * bound of its tolerance that costs nothing (|A (B e)|_i <= (|A| |B| e)_i):
 * below it, the row is right; only a row above it gets its tolerance computed
 * (|B| e once, then one row of |A| against it), so a clean product costs the
 * two sums of C. With @p rows_only (sums from abft_sums with the same flag)
 * only the rows are checked: one sum of C. Charges @p work.
 */
template <typename DA, typename DB, typename DC, int M, int K, int N>
AbftResult abft_check(const Eigen::MatrixBase<DA>& a, const Eigen::MatrixBase<DB>& b, const Eigen::MatrixBase<DC>& c,
                      AbftSums<M, K, N>& s, bsp::Work& work, bool rows_only = false) noexcept {
  AbftResult r{};
  s.rs.noalias() = c.rowwise().sum();
  if (rows_only) {
    const auto elems = static_cast<std::uint64_t>(c.rows() * c.cols());
    work.flops += elems + 4U * static_cast<std::uint64_t>(c.rows());
    work.mem_words += elems;
    detail::abft_check_rows(a, b, s, r, work);
    return r;
  }
  s.cs.noalias() = c.colwise().sum();
  const auto elems = static_cast<std::uint64_t>(c.rows() * c.cols());
  work.flops += 2U * elems + 4U * static_cast<std::uint64_t>(c.rows() + c.cols());
  work.mem_words += 2U * elems;
  detail::abft_check_rows(a, b, s, r, work);
  detail::abft_check_cols(a, b, s, r, work);
  return r;
}

/** Flops of a passing rows-first check (AbftSite::rows_first): those of a rows-only check. */
constexpr std::uint64_t abft_rows_first_flops(std::uint64_t m, std::uint64_t k, std::uint64_t n) noexcept {
  return abft_rows_flops(m, k, n);
}

/** Reports a product found wrong (corrected or failed) as an event. */
void abft_report(const AbftSite& site, const AbftResult& r) noexcept;

/**
 * C = A B by @p kernel (called as kernel(a, b, c), the caller's product code,
 * dense or exploiting a known structure of A or B), published on the site's
 * sdc channel (where a fault corrupts it), checked against the full
 * checksums, and recomputed by the same kernel while wrong, at most
 * kAbftMaxRecompute times. A corrected or failed product is reported
 * (abft_corrected, abft_failed). @p s is the caller's scratch. The result
 * says where the first check found the product wrong: one row and one column
 * locate the element (row, col); otherwise they are the worst row and column.
 * A rows-only site (AbftSite::rows_only) checks and locates rows only; a
 * rows-first one (AbftSite::rows_first) checks the rows, and the columns
 * only once a row failed: the cost of a rows-only check when clean, the
 * element located when wrong (the recomputations are checked on the rows).
 */
template <typename DA, typename DB, typename DC, int M, int K, int N, typename Kernel>
AbftResult abft_product(const Eigen::MatrixBase<DA>& a, const Eigen::MatrixBase<DB>& b, Eigen::MatrixBase<DC>& c,
                        const AbftSite& site, Kernel&& kernel, AbftSums<M, K, N>& s, bsp::Work& work) noexcept {
  kernel(a.derived(), b.derived(), c.derived());
  if (site.sdc_channel != 0U) {
    (void)bsp::publish_filter(site.sdc_channel, c.derived().data(),
                              sizeof(double) * static_cast<std::size_t>(c.rows() * c.cols()));
  }
  const bool rows = site.rows_only || site.rows_first;
  abft_sums(a, b, s, work, rows);
  AbftResult first = abft_check(a, b, c, s, work, rows);
  if (first.bad_rows == 0U && first.bad_cols == 0U) {
    return first;
  }
  if (site.rows_first && !site.rows_only) {
    // Wrong: the column references too, and the full check, to locate the element.
    abft_sums(a, b, s, work, false);
    first = abft_check(a, b, c, s, work, false);
  }
  first.verdict = AbftVerdict::kFailed;
  for (std::uint32_t n = 0; n < kAbftMaxRecompute; ++n) {
    kernel(a.derived(), b.derived(), c.derived());
    ++first.recomputes;
    const AbftResult again = abft_check(a, b, c, s, work, rows);
    if (again.bad_rows == 0U && again.bad_cols == 0U) {
      first.verdict = AbftVerdict::kCorrected;
      break;
    }
  }
  abft_report(site, first);
  return first;
}

/**
 * Scratch of a checked symmetric outer product (abft_upper_product): the
 * caller's storage, like AbftSums.
 */
template <int M, int N>
struct AbftUpperSums {
  Eigen::Matrix<double, M, N> suffix;      ///< row i: the sum of the second operand's rows i..M-1
  Eigen::Matrix<double, M, N> abs_suffix;  ///< the same of its absolute values (when a tolerance was needed)
  Eigen::Matrix<double, M, 1> row_ref;     ///< K_i . suffix_i
  Eigen::Matrix<double, M, 1> rs;          ///< the computed triangle's row sums
};

/** The upper triangle (diagonal included) of U = K A^T, element by element in a fixed order. */
template <int M, int N>
void abft_upper_kernel(const Eigen::Matrix<double, M, N>& k, const Eigen::Matrix<double, M, N>& a,
                       Eigen::Matrix<double, M, M>& u) noexcept {
  for (int j = 0; j < M; ++j) {
    for (int i = 0; i <= j; ++i) {
      double v = 0.0;
      for (int c = 0; c < N; ++c) {
        v += k(i, c) * a(j, c);
      }
      u(i, j) = v;
    }
  }
}

namespace detail {

/** Row i of the triangle against K_i . suffix_i; the rows past their tolerance into a result. */
template <int M, int N>
AbftResult abft_upper_check(const Eigen::Matrix<double, M, N>& k, const Eigen::Matrix<double, M, N>& a,
                            const Eigen::Matrix<double, M, M>& u, AbftUpperSums<M, N>& s,
                            bsp::Work& work) noexcept {
  AbftResult r{};
  bool abs_ready = false;
  double worst = -1.0;
  for (int i = 0; i < M; ++i) {
    double sum = 0.0;
    for (int j = i; j < M; ++j) {
      sum += u(i, j);
    }
    s.rs(i) = sum;
    // Row i is an (M - i)-column product of inner dimension N: the tolerance of abft.hpp's comment.
    const double f = kAbftSafety * static_cast<double>(N + (M - i) + 2) * kAbftUnitRoundoff;
    const double d = sum - s.row_ref(i);
    if (std::abs(d) <= f * std::abs(s.row_ref(i)) + kAbftFloor) {
      continue;
    }
    if (!abs_ready) {
      s.abs_suffix.row(M - 1) = a.row(M - 1).cwiseAbs();
      for (int j = M - 2; j >= 0; --j) {
        s.abs_suffix.row(j) = s.abs_suffix.row(j + 1) + a.row(j).cwiseAbs();
      }
      abs_ready = true;
      work += bsp::Work{std::uint64_t{M} * N, 0U, (std::uint64_t{M} - 1U) * N, 0U, std::uint64_t{M} * N};
    }
    const double tol = f * k.row(i).cwiseAbs().dot(s.abs_suffix.row(i)) + kAbftFloor;
    work += bsp::Work{0U, 0U, 2U * std::uint64_t{N} + 2U, 0U, 2U * std::uint64_t{N}};
    if (!(std::abs(d) <= tol)) {
      ++r.bad_rows;
      const double excess = std::isfinite(d) ? std::abs(d) / tol : HUGE_VAL;
      if (excess > worst) {
        worst = excess;
        r.row = i;
        r.residual = d;
      }
    }
  }
  const std::uint64_t tri = std::uint64_t{M} * (std::uint64_t{M} + 1U) / 2U;
  work.flops += tri + 4U * std::uint64_t{M};
  work.mem_words += tri;
  return r;
}

}  // namespace detail

/** Flops counted for a passing abft_upper_product check of an M x N by N x M symmetric outer product. */
constexpr std::uint64_t abft_upper_flops(std::uint64_t m, std::uint64_t n) noexcept {
  return (m - 1U) * n + 2U * m * n + m * (m + 1U) / 2U + 4U * m;
}

/** The most a clean abft_upper_product check adds to abft_upper_flops: every row's exact tolerance. */
constexpr std::uint64_t abft_upper_tolerance_flops(std::uint64_t m, std::uint64_t n) noexcept {
  return (m - 1U) * n + m * (2U * n + 2U);
}

/**
 * The upper triangle of U = K A^T (diagonal included) for a product known to
 * be symmetric (K = A W with W symmetric: the Kalman update's
 * P H^T S^-1 H P), checked on the rows of the triangle it computes: row i of
 * the triangle sums to K_i . (A_i + ... + A_{M-1}), suffix sums of A's rows
 * (the Huang and Abraham row check of a triangular product; same tolerance,
 * with the row's own M - i columns). The lower triangle is not written. A
 * wrong element fails its row, which is located (the column is not: the
 * event says rows only); the triangle is computed again, at most
 * kAbftMaxRecompute times, and reported like abft_product. The check costs
 * abft_upper_flops, against about 2 M^2 N for the triangle.
 */
template <int M, int N>
AbftResult abft_upper_product(const Eigen::Matrix<double, M, N>& k, const Eigen::Matrix<double, M, N>& a,
                              Eigen::Matrix<double, M, M>& u, const AbftSite& site, AbftUpperSums<M, N>& s,
                              bsp::Work& work) noexcept {
  abft_upper_kernel(k, a, u);
  if (site.sdc_channel != 0U) {
    (void)bsp::publish_filter(site.sdc_channel, u.data(), sizeof(double) * static_cast<std::size_t>(M * M));
  }
  s.suffix.row(M - 1) = a.row(M - 1);
  for (int j = M - 2; j >= 0; --j) {
    s.suffix.row(j) = s.suffix.row(j + 1) + a.row(j);
  }
  for (int i = 0; i < M; ++i) {
    double v = 0.0;
    for (int c = 0; c < N; ++c) {
      v += k(i, c) * s.suffix(i, c);
    }
    s.row_ref(i) = v;
  }
  work.flops += (std::uint64_t{M} - 1U) * N + 2U * std::uint64_t{M} * N;  // suffix sums, K_i . suffix_i
  work.mem_words += 3U * std::uint64_t{M} * N;
  AbftResult first = detail::abft_upper_check(k, a, u, s, work);
  if (first.bad_rows == 0U) {
    return first;
  }
  first.verdict = AbftVerdict::kFailed;
  for (std::uint32_t n = 0; n < kAbftMaxRecompute; ++n) {
    abft_upper_kernel(k, a, u);
    ++first.recomputes;
    const AbftResult again = detail::abft_upper_check(k, a, u, s, work);
    if (again.bad_rows == 0U) {
      first.verdict = AbftVerdict::kCorrected;
      break;
    }
  }
  abft_report(site, first);
  return first;
}

/** The plain dense kernel: c = a b (Eigen's lazy product; no allocation). Charges nothing. */
struct AbftDense {
  template <typename A, typename B, typename C>
  void operator()(const A& a, const B& b, C& c) const noexcept {
    c.noalias() = a.lazyProduct(b);
  }
};

}  // namespace fdir
