#include "bench/peers/hand_model.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace ajx::hand {

void Params::omega(double t, double& w, double& wd) const {
  std::size_t k = 0;
  while (k + 1 < drive.size() && t >= drive[k + 1].t_begin) ++k;
  const Segment& s = drive[k];
  const double tau = std::min(t - s.t_begin, s.duration);
  w = s.omega_begin + s.rate * tau;
  wd = t - s.t_begin <= s.duration ? s.rate : 0.0;
}

namespace {
V3 at(const double* y, int i) { return {y[i], y[i + 1], y[i + 2]}; }
double held_L1(const Params& p, const Contact& c) {
  return c.mode == Mode::Bottom ? p.l - p.d : c.mode == Mode::Top ? p.s_min : c.s_star;
}
}  // namespace

Forces forces(const Params& p, const Contact& c, double t, const double* y, bool cone) {
  double w, wd;
  p.omega(t, w, wd);
  const V3 a(p.R, 0, 0), a_dot(0, p.R * w, 0), a_ddot(-p.R * w * w, p.R * wd, 0);
  const V3 r1 = at(y, 0), r2 = at(y, 3), v1 = at(y, 6), v2 = at(y, 9);
  Forces F;
  F.omega = w;
  const V3 d1 = r1 - a, d2 = r2 - r1, w1 = v1 - a_dot, w2 = v2 - v1;
  F.L1 = d1.norm();
  F.L2 = d2.norm();
  F.u1 = d1 / F.L1;
  F.u2 = d2 / F.L2;
  const double uw1 = F.u1.dot(w1), uw2 = F.u2.dot(w2);
  F.L1_dot = uw1;
  const double q1 = (w1.squaredNorm() - uw1 * uw1) / F.L1, q2 = (w2.squaredNorm() - uw2 * uw2) / F.L2;
  const double c12 = F.u1.dot(F.u2);
  const V3 f1 = -p.cD * v1 - V3(0, 0, p.m1 * p.g), f2 = -p.cD * v2 - V3(0, 0, p.m2 * p.g);
  const bool sliding = c.mode == Mode::Sliding;
  F.psi = cone || sliding ? std::atan2(F.u1.cross(F.u2).norm(), c12) : 0.0;
  F.margin_up = F.margin_down = std::numeric_limits<double>::infinity();
  if (sliding) {
    const double kappa = c.sigma == 0 ? 1.0 : std::exp(p.mu_k * F.psi * c.sigma);
    const double num = F.u1.dot(f1 / p.m1 - a_ddot) + F.u2.dot(f2 / p.m2 - f1 / p.m1) + q1 + q2;
    F.T2 = F.F2 = num / ((1 - c12) * (1 + kappa) / p.m1 + 1 / p.m2);
    F.T1 = F.F1 = kappa * F.T2;
  } else {
    const double A00 = 1 / p.m1, A01 = -c12 / p.m1, A11 = 1 / p.m1 + 1 / p.m2;
    const double b0 = F.u1.dot(f1) / p.m1 - F.u1.dot(a_ddot) + q1;
    const double b1 = F.u2.dot(f2) / p.m2 - F.u2.dot(f1) / p.m1 + q2;
    const double det = A00 * A11 - A01 * A01;
    F.F1 = (A11 * b0 - A01 * b1) / det;
    F.F2 = (A00 * b1 - A01 * b0) / det;
    F.T1 = F.F1;
    F.T2 = F.F2;
    if (cone) {
      const double lo = std::exp(-p.mu_s * F.psi), hi = std::exp(p.mu_s * F.psi);
      if (c.mode == Mode::Stuck) {
        F.margin_up = F.F1 - lo * F.F2;
        F.margin_down = hi * F.F2 - F.F1;
      } else if (c.mode == Mode::Bottom) {  // the ball pushes the bead up: T2 nearest F2 in the cone
        F.T2 = std::max(std::min(F.F2, F.F1 / lo), F.F1 / hi);
        F.margin_up = F.F1 - lo * F.F2;
      } else {  // the top pushes the bead down
        F.T1 = std::max(std::min(F.F1, hi * F.F2), lo * F.F2);
        F.margin_down = hi * F.F2 - F.F1;
      }
    }
  }
  F.acc1 = (-F.F1 * F.u1 + F.F2 * F.u2 + f1) / p.m1;
  F.acc2 = (-F.F2 * F.u2 + f2) / p.m2;
  return F;
}

void rhs(const Params& p, const Contact& c, double t, const double* y, double* dydt) {
  const Forces F = forces(p, c, t, y, false);
  const double w = F.omega;
  // ṙ = v − ω ẑ×r, v̇ = acc − ω ẑ×v, with ẑ×x = (−x_y, x_x, 0).
  for (int b = 0; b < 2; ++b) {
    const double* r = y + 3 * b;
    const double* v = y + 6 + 3 * b;
    const V3& acc = b == 0 ? F.acc1 : F.acc2;
    dydt[3 * b] = v[0] + w * r[1];
    dydt[3 * b + 1] = v[1] - w * r[0];
    dydt[3 * b + 2] = v[2];
    dydt[6 + 3 * b] = acc[0] + w * v[1];
    dydt[6 + 3 * b + 1] = acc[1] - w * v[0];
    dydt[6 + 3 * b + 2] = acc[2];
  }
}

// Guard order per mode: sliding (LandBottom, LandTop, Rest, Slacken); stuck (SlipUp, SlipDown,
// Slacken); bottom (SlipUp, Slacken); top (SlipDown, Slacken).
int guards(const Params& p, const Contact& c, double t, const double* y, double* g) {
  const Forces F = forces(p, c, t, y, c.mode != Mode::Sliding);
  const double slack = std::min(F.T1, F.T2);
  switch (c.mode) {
    case Mode::Sliding:
      g[0] = F.L2 - p.d;
      g[1] = F.L1 - p.s_min;
      g[2] = c.sigma * F.L1_dot;
      g[3] = slack;
      return c.sigma != 0 ? 4 : 2;  // without a direction, no rest guard (never the case here)
    case Mode::Stuck:
      g[0] = F.margin_up;
      g[1] = F.margin_down;
      g[2] = slack;
      return 3;
    case Mode::Bottom:
      g[0] = F.margin_up;
      g[1] = slack;
      return 2;
    case Mode::Top:
      g[0] = F.margin_down;
      g[1] = slack;
      return 2;
  }
  return 0;
}

namespace {
using Row = Eigen::Matrix<double, 1, 6>;
using V6 = Eigen::Matrix<double, 6, 1>;

// The constraint rows of a mode at y: n rows of J, C and b (Ċ = J v − b).
int constraints(const Params& p, const Contact& c, double t, const double* y, Eigen::Matrix<double, 2, 6>& J,
                Eigen::Vector2d& C, Eigen::Vector2d& b) {
  double w, wd;
  p.omega(t, w, wd);
  const V3 a(p.R, 0, 0), a_dot(0, p.R * w, 0);
  const V3 d1 = at(y, 0) - a, d2 = at(y, 3) - at(y, 0);
  const V3 u1 = d1.normalized(), u2 = d2.normalized();
  J.setZero();
  C.setZero();
  b.setZero();
  b(0) = u1.dot(a_dot);
  if (c.mode == Mode::Sliding) {
    J.block<1, 3>(0, 0) = (u1 - u2).transpose();
    J.block<1, 3>(0, 3) = u2.transpose();
    C(0) = d1.norm() + d2.norm() - p.l;
    return 1;
  }
  const double s1 = held_L1(p, c);
  J.block<1, 3>(0, 0) = u1.transpose();
  J.block<1, 3>(1, 0) = -u2.transpose();
  J.block<1, 3>(1, 3) = u2.transpose();
  C << d1.norm() - s1, d2.norm() - (p.l - s1);
  return 2;
}

V6 inverse_mass(const Params& p) { return (V6() << V3::Constant(1 / p.m1), V3::Constant(1 / p.m2)).finished(); }

// λ from (J M⁻¹ Jᵀ) λ = r on the n rows.
Eigen::Vector2d solve(const Eigen::Matrix<double, 2, 6>& J, const V6& Minv, const Eigen::Vector2d& r, int n) {
  const Eigen::Matrix2d A = J * Minv.asDiagonal() * J.transpose();
  return n == 1 ? Eigen::Vector2d(r(0) / A(0, 0), 0) : Eigen::Vector2d(A.inverse() * r);
}

// v ← v − M⁻¹Jᵀλ with λ making J v = b on the rows (an inelastic impact or a projection).
void remove_rate(const Eigen::Matrix<double, 2, 6>& J, const Eigen::Vector2d& b, int n, const V6& Minv, double* y) {
  Eigen::Map<V6> v(y + 6);
  const Eigen::Vector2d lambda = solve(J, Minv, J * v - b, n);
  v -= Minv.asDiagonal() * (J.transpose() * lambda);
}
}  // namespace

void project(const Params& p, const Contact& c, double t, double* y, double tol) {
  const V6 Minv = inverse_mass(p);
  Eigen::Matrix<double, 2, 6> J;
  Eigen::Vector2d C, b;
  int n = constraints(p, c, t, y, J, C, b);
  if (C.head(n).cwiseAbs().maxCoeff() > tol) {
    for (int it = 0; it < 4 && C.head(n).cwiseAbs().maxCoeff() > 1e-15 * p.l; ++it) {
      Eigen::Map<V6> x(y);
      x -= Minv.asDiagonal() * (J.transpose() * solve(J, Minv, C, n));
      n = constraints(p, c, t, y, J, C, b);
    }
  }
  const Eigen::Map<const V6> v(y + 6);
  if ((J * v - b).head(n).cwiseAbs().maxCoeff() > tol) remove_rate(J, b, n, Minv, y);
}

bool switch_mode(const Params& p, Contact& c, int guard, double t, double* y) {
  const V6 Minv = inverse_mass(p);
  const bool slack = (c.mode == Mode::Sliding && guard == 3) || (c.mode == Mode::Stuck && guard == 2) ||
                     ((c.mode == Mode::Bottom || c.mode == Mode::Top) && guard == 1);
  if (slack) return false;
  if (c.mode == Mode::Stuck) {
    c = {Mode::Sliding, guard == 0 ? -1 : +1, 0};
  } else if (c.mode == Mode::Bottom) {
    c = {Mode::Sliding, -1, 0};
  } else if (c.mode == Mode::Top) {
    c = {Mode::Sliding, +1, 0};
  } else if (guard == 0 || guard == 1) {  // a landing: the bead's approach stops (e = 0)
    double w, wd;
    p.omega(t, w, wd);
    const V3 a(p.R, 0, 0), a_dot(0, p.R * w, 0);
    Eigen::Matrix<double, 2, 6> J = Eigen::Matrix<double, 2, 6>::Zero();
    Eigen::Vector2d b = Eigen::Vector2d::Zero();
    if (guard == 0) {
      const V3 u2 = (at(y, 3) - at(y, 0)).normalized();
      J.block<1, 3>(0, 0) = -u2.transpose();
      J.block<1, 3>(0, 3) = u2.transpose();
    } else {
      const V3 u1 = (at(y, 0) - a).normalized();
      J.block<1, 3>(0, 0) = u1.transpose();
      b(0) = u1.dot(a_dot);
    }
    remove_rate(J, b, 1, Minv, y);
    c = {guard == 0 ? Mode::Bottom : Mode::Top, 0, 0};
  } else {  // at rest on the string: held at s* = L1 while the μ_s cone holds
    const V3 a(p.R, 0, 0);
    c = {Mode::Stuck, 0, (at(y, 0) - a).norm()};
  }
  // A held bead outside its cone slides at once, towards the violated bound.
  if (c.mode != Mode::Sliding) {
    const Forces F = forces(p, c, t, y, true);
    if (F.margin_up < 0) c = {Mode::Sliding, -1, 0};
    else if (F.margin_down < 0) c = {Mode::Sliding, +1, 0};
  }
  return true;
}

double guard_rate(const Params& p, double t, const double* y) {
  double w, wd;
  p.omega(t, w, wd);
  double rel = 0, centrifugal = 0;
  for (int b = 0; b < 2; ++b) {
    const double x = y[3 * b], yy = y[3 * b + 1], vx = y[6 + 3 * b], vy = y[7 + 3 * b];
    const double rho2 = x * x + yy * yy;
    const double theta_dot = (x * vy - yy * vx) / std::max(rho2, p.R * p.R);
    rel = std::max(rel, std::abs(w - theta_dot));
    centrifugal = std::max(centrifugal, theta_dot * theta_dot * std::sqrt(rho2));
  }
  const V3 a(p.R, 0, 0);
  const double L_short = std::min((at(y, 0) - a).norm(), (at(y, 3) - at(y, 0)).norm());
  return std::max(rel, std::sqrt(std::hypot(p.g, centrifugal) / std::max(L_short, 1e-4 * p.l)));
}

}  // namespace ajx::hand
