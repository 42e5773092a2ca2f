/**
 * @file innovation_monitor.cpp
 * @brief The innovation monitor's window and its two tests (innovation_monitor.hpp).
 */
#include "fdir/innovation_monitor.hpp"

#include <algorithm>
#include <cmath>

namespace fdir {

namespace {

/** Largest clipped d2 a job may add, thousandths: the sum of a job is bounded by n times this. */
constexpr double kMaxNisMilli = 1.0e6;

/** Sums the window's last @p blocks blocks into @p win (n, rejected) and returns their d2 sum, thousandths. */
double sum_window(const InnovationMonitor& m, std::uint32_t blocks, InnovationWindow& win) noexcept {
  double nis = 0.0;
  for (std::uint32_t k = 0; k < blocks && k < kMaxInnovationBlocks; ++k) {
    const InnovationBlock& b = m.ring[(m.next + kMaxInnovationBlocks - 1U - k) % kMaxInnovationBlocks];
    win.n += b.n;
    win.rejected += b.rejected < b.n ? b.rejected : b.n;
    nis += static_cast<double>(b.nis_milli);
  }
  return nis;
}

InnovationVerdict judge(const InnovationMonitor& m, const InnovationMonitorConfig& c, double gate_chi2,
                        InnovationWindow& win, bsp::Work& work) noexcept {
  const double nis_milli = sum_window(m, c.window_blocks, win);
  work.int_ops += 4ULL * c.window_blocks;
  work.flops += 60U;  // two exponentials, two square roots, the tests
  if (win.n == 0U) {
    return InnovationVerdict::kConsistent;
  }
  const double n = static_cast<double>(win.n);
  const double mean = nis_milli / 1000.0 / n;
  win.mean_nis_milli = static_cast<std::uint32_t>(std::lround(mean * 1000.0));
  const double p = std::exp(-0.5 * gate_chi2);
  const double frac = static_cast<double>(win.rejected) / n;
  const double frac_se = std::sqrt(p * (1.0 - p) / n);
  if (frac > p + static_cast<double>(c.reject_sigmas) * frac_se &&
      frac * 100.0 > static_cast<double>(c.reject_floor_pct)) {
    return InnovationVerdict::kRejectedHigh;
  }
  const double mu = clipped_chi2_mean(gate_chi2);
  const double se = std::sqrt(clipped_chi2_var(gate_chi2) / n);
  if (mean > mu + static_cast<double>(c.nis_sigmas) * se &&
      mean * 1000.0 > static_cast<double>(c.nis_floor_milli)) {
    return InnovationVerdict::kNisHigh;
  }
  return InnovationVerdict::kConsistent;
}

}  // namespace

bool innovation_config_ok(const InnovationMonitorConfig& c) noexcept {
  return c.block_matches >= 1U && c.window_blocks >= 1U && c.window_blocks <= kMaxInnovationBlocks &&
         c.nis_sigmas >= 1U && c.reject_sigmas >= 1U && c.reject_floor_pct <= 100U;
}

double clipped_chi2_mean(double g) noexcept { return 2.0 * (1.0 - std::exp(-0.5 * g)); }

double clipped_chi2_var(double g) noexcept {
  const double mu = clipped_chi2_mean(g);
  return 8.0 * (1.0 - std::exp(-0.5 * g) * (1.0 + 0.5 * g)) - mu * mu;
}

void innovation_clear(InnovationMonitor& m) noexcept {
  m.ring.fill(InnovationBlock{});
  m.open = InnovationBlock{};
  m.next = 0U;
  m.filled = 0U;
}

InnovationVerdict innovation_add(InnovationMonitor& m, const InnovationMonitorConfig& c, double gate_chi2,
                                 std::uint32_t n, std::uint32_t rejected, double nis_sum, InnovationWindow& win,
                                 bsp::Work& work) noexcept {
  win = InnovationWindow{};
  if (n == 0U) {
    return InnovationVerdict::kNone;
  }
  work.int_ops += 6U;
  double milli = nis_sum * 1000.0;
  const double cap = std::min(kMaxNisMilli * static_cast<double>(n), 4.0e9);
  milli = !(milli >= 0.0) ? 0.0 : (milli > cap ? cap : milli);  // an upset's NaN or huge value bounded
  m.open.n += n;
  m.open.rejected += rejected;
  m.open.nis_milli += static_cast<std::uint32_t>(std::lround(milli));
  if (m.open.n < c.block_matches) {
    return InnovationVerdict::kNone;
  }
  m.next %= kMaxInnovationBlocks;
  m.ring[m.next] = m.open;
  m.next = (m.next + 1U) % kMaxInnovationBlocks;
  m.open = InnovationBlock{};
  if (m.filled < kMaxInnovationBlocks) {
    ++m.filled;
  }
  if (m.filled < c.window_blocks) {
    return InnovationVerdict::kNone;
  }
  return judge(m, c, gate_chi2, win, work);
}

}  // namespace fdir
