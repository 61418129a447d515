// Cubic Hermite interpolation on one step, shared by the fixed-step methods:
// p(theta) = h00 y0 + h10 h f0 + h01 y1 + h11 h f1, theta in [0, 1], with
// h00 = (1-s)^2 (1+2s), h10 = s (1-s)^2, h01 = s^2 (3-2s), h11 = s^2 (s-1).
// Interpolation error O(h^4) (order 3) when y0, y1 are exact.
#pragma once
#include "numerics/vector.hpp"

namespace ajx::numerics {

inline void hermite_cubic(double s, double h, const Vec& y0, const Vec& f0, const Vec& y1,
                          const Vec& f1, Vec& out) {
  const double s1 = 1.0 - s;
  const double h00 = s1 * s1 * (1.0 + 2.0 * s);
  const double h10 = s * s1 * s1 * h;
  const double h01 = s * s * (3.0 - 2.0 * s);
  const double h11 = -s * s * s1 * h;
  out = h00 * y0 + h10 * f0 + h01 * y1 + h11 * f1;
}

}  // namespace ajx::numerics
