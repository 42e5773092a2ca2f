/**
 * @file nav_integrity.cpp
 * @brief Per-axis error against the reported 3-sigma.
 */
#include "tools/common/mission/nav_integrity.hpp"

#include <cmath>

namespace tools {

void NavIntegrity::add(double t_s, const std::array<double, 3>& error_m,
                       const std::array<double, 3>& sigma3_m) noexcept {
  ++outputs;
  bool bad = false;
  for (std::size_t i = 0; i < 3U; ++i) {
    const double s3 = sigma3_m[i];
    const double e = std::abs(error_m[i]);
    if (!std::isfinite(s3) || !(s3 > 0.0) || !std::isfinite(e)) {
      bad = true;
      ++beyond_3sigma[i];
      ++beyond_5sigma[i];
      continue;
    }
    const double ratio = e / s3;
    beyond_3sigma[i] += ratio > 1.0 ? 1U : 0U;
    beyond_5sigma[i] += ratio > 5.0 / 3.0 ? 1U : 0U;
    if (ratio > worst_ratio[i]) {
      worst_ratio[i] = ratio;
      if (ratio >= worst_ratio[0] && ratio >= worst_ratio[1] && ratio >= worst_ratio[2]) {
        worst_at_s = t_s;
      }
    }
  }
  bad_sigma += bad ? 1U : 0U;
}

double NavIntegrity::fraction_beyond_3sigma(int axis) const noexcept {
  if (outputs == 0U || axis < 0 || axis > 2) {
    return 0.0;
  }
  return static_cast<double>(beyond_3sigma[static_cast<std::size_t>(axis)]) / static_cast<double>(outputs);
}

}  // namespace tools
