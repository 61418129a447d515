// Test problems with known solutions shared by the numerics tests.
#pragma once
#include <cmath>
#include <numbers>

#include "numerics/vector.hpp"

namespace ajx::numerics::testing {

// Kepler problem, mu = 1, semi-major axis 1 (period 2 pi), eccentricity e, start at the
// pericentre: q = (1 - e, 0), p = (0, sqrt((1 + e)/(1 - e))). State (x, y, vx, vy).
struct Kepler {
  double e = 0.5;
  static constexpr double period = 2.0 * std::numbers::pi;

  // x'' = -x / r^3.
  void operator()(double /*t*/, const Vec& s, Vec& ds) const {
    const double r2 = s[0] * s[0] + s[1] * s[1];
    const double ir3 = 1.0 / (r2 * std::sqrt(r2));
    ds[0] = s[2];
    ds[1] = s[3];
    ds[2] = -s[0] * ir3;
    ds[3] = -s[1] * ir3;
  }

  // Exact state at time t: mean anomaly M = t solves Kepler's equation E - e sin E = M
  // (Newton), x = cos E - e, y = sqrt(1-e^2) sin E, E' = 1 / (1 - e cos E).
  Vec exact(double t) const {
    double E = t;
    for (int i = 0; i < 50; ++i) {
      const double dE = (E - e * std::sin(E) - t) / (1.0 - e * std::cos(E));
      E -= dE;
      if (std::abs(dE) < 1e-16) break;
    }
    const double b = std::sqrt(1.0 - e * e);
    const double Ed = 1.0 / (1.0 - e * std::cos(E));
    Vec s(4);
    s << std::cos(E) - e, b * std::sin(E), -std::sin(E) * Ed, b * std::cos(E) * Ed;
    return s;
  }
};

// Harmonic oscillator y'' = -y, state (y, y'): from (1, 0), y = cos t.
inline void oscillator(double /*t*/, const Vec& s, Vec& ds) {
  ds[0] = s[1];
  ds[1] = -s[0];
}

inline double max_abs_diff(const Vec& a, const Vec& b) { return (a - b).cwiseAbs().maxCoeff(); }

}  // namespace ajx::numerics::testing
