/**
 * @file rng.cpp
 * @brief Normal variates for the deterministic streams.
 */
#include "bsp_tile64/emu/rng.hpp"

#include <cmath>

namespace bsp {

double Rng::normal() noexcept {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  // Polar method: accept a point in the unit disc. Acceptance is pi/4, so the
  // bound of 64 tries fails with probability (1 - pi/4)^64 < 1e-42.
  for (int tries = 0; tries < 64; ++tries) {
    const double u = 2.0 * uniform() - 1.0;
    const double v = 2.0 * uniform() - 1.0;
    const double s = u * u + v * v;
    if (s > 0.0 && s < 1.0) {
      const double f = std::sqrt(-2.0 * std::log(s) / s);
      spare_ = v * f;
      has_spare_ = true;
      return u * f;
    }
  }
  return 0.0;
}

}  // namespace bsp
