// Steady rotation of the two balls on two rigid links (lengths L1, L2) driven at constant ω:
// the bead on the bottom stop (L1 = l - d, L2 = d) or stuck at s* (L1 = s*, L2 = l - s*).
// In the frame turning with the motor (top at (R, 0, 0)) the balls sit still at p1, p2 with
// lab velocity ω ẑ × p and acceleration -ω² (x, y, 0), so Newton's law is the algebraic
// force balance
//   -m1 ω² P p1 = -F1 u1 + F2 u2 - c_D ω ẑ×p1 - m1 g ẑ
//   -m2 ω² P p2 =         -F2 u2 - c_D ω ẑ×p2 - m2 g ẑ
//   |p1 - a| = L1,  |p2 - p1| = L2,
// eight equations in (p1, p2, F1, F2), solved by Newton from the linear-theory guess. This
// is independent of the simulator's time integration, which must settle onto it.
#pragma once
#include <Eigen/Dense>
#include <cmath>

#include "physics/drive.hpp"
#include "physics/model.hpp"

namespace ajx::test {

using Vec8 = Eigen::Matrix<double, 8, 1>;
using physics::Vec3;

inline Vec8 steady_residual(const physics::Parameters& p, double L1, double L2, double w, const Vec8& x) {
  const Vec3 a(p.drive_radius, 0, 0), z = Vec3::UnitZ();
  const Vec3 p1 = x.segment<3>(0), p2 = x.segment<3>(3);
  const double F1 = x(6), F2 = x(7);
  const Vec3 u1 = (p1 - a).normalized(), u2 = (p2 - p1).normalized();
  const auto horiz = [](const Vec3& v) { return Vec3(v.x(), v.y(), 0.0); };
  Vec8 r;
  r.segment<3>(0) = -F1 * u1 + F2 * u2 - p.drag * w * z.cross(p1) - p.bead_mass * p.gravity * z +
                    p.bead_mass * w * w * horiz(p1);
  r.segment<3>(3) = -F2 * u2 - p.drag * w * z.cross(p2) - p.ball_mass * p.gravity * z + p.ball_mass * w * w * horiz(p2);
  r(6) = (p1 - a).norm() - L1;
  r(7) = (p2 - p1).norm() - L2;
  return r;
}

// Newton from a guess x0 = (p1, p2, F1, F2); check steady_residual(...) for convergence.
inline Vec8 solve_steady(const physics::Parameters& p, double L1, double L2, double w, Vec8 x) {
  for (int it = 0; it < 400; ++it) {
    const Vec8 r = steady_residual(p, L1, L2, w, x);
    if (r.norm() < 1e-15) break;
    Eigen::Matrix<double, 8, 8> J;
    for (int j = 0; j < 8; ++j) {
      Vec8 xp = x;
      const double h = 1e-7 * std::max(1.0, std::abs(x(j)));
      xp(j) += h;
      J.col(j) = (steady_residual(p, L1, L2, w, xp) - r) / h;
    }
    Vec8 dx = J.partialPivLu().solve(r);
    const double n = dx.norm();
    if (n > 0.05) dx *= 0.05 / n;  // damped steps far from the root
    x -= dx;
  }
  return x;
}

// The guess of linear theory: a pendulum of length l driven at R swings in phase with radius
// R ω0²/(ω0² - ω²), ω0² = g/l, both balls hanging straight below.
inline Vec8 linear_guess(const physics::Parameters& p, double L1, double L2, double w) {
  const double g = p.gravity, l = L1 + L2;
  const double rho = p.drive_radius * (g / l) / (g / l - w * w);
  Vec8 x;
  x << rho, 0, -L1, rho, 0, -L1 - L2, (p.bead_mass + p.ball_mass) * g, p.ball_mass * g;
  return x;
}

}  // namespace ajx::test
