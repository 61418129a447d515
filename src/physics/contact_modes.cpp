#include "physics/contact_modes.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "physics/string_friction.hpp"

namespace ajx::physics {

namespace {
// |w⊥|²/L with w⊥ = w - (u·w) u: d/dt(u·w) = u·ẇ + |w⊥|²/L.
double normal_rate_term(const Vec3& u, const Vec3& w, double L) {
  const double wu = u.dot(w);
  return (w.squaredNorm() - wu * wu) / L;
}
}  // namespace

Geometry geometry(const TopKinematics& top, const Vec3& r1, const Vec3& r2, const Vec3& v1,
                  const Vec3& v2, bool with_psi) {
  Geometry g;
  const Vec3 d1 = r1 - top.a, d2 = r2 - r1;
  g.L1 = d1.norm();
  g.L2 = d2.norm();
  g.u1 = d1 / g.L1;
  g.u2 = d2 / g.L2;
  g.w1 = v1 - top.a_dot;
  g.w2 = v2 - v1;
  g.L1_dot = g.u1.dot(g.w1);
  g.L2_dot = g.u2.dot(g.w2);
  g.q1 = normal_rate_term(g.u1, g.w1, g.L1);
  g.q2 = normal_rate_term(g.u2, g.w2, g.L2);
  g.cos_psi = g.u1.dot(g.u2);
  g.psi = with_psi ? deflection(g.u1, g.u2) : std::numeric_limits<double>::quiet_NaN();
  return g;
}

AppliedForces applied_forces(const Parameters& p, const Vec3& v1, const Vec3& v2) {
  const Vec3 z = Vec3::UnitZ();
  return {-p.drag * v1 - p.bead_mass * p.gravity * z, -p.drag * v2 - p.ball_mass * p.gravity * z};
}

double sliding_tension_T2(const Parameters& p, const Geometry& g, const AppliedForces& f,
                          const Vec3& a_ddot, double kappa) {
  const double m1 = p.bead_mass, m2 = p.ball_mass;
  const double rhs = g.u1.dot(f.f1 / m1 - a_ddot) + g.u2.dot(f.f2 / m2 - f.f1 / m1) + g.q1 + g.q2;
  return rhs / ((1.0 - g.cos_psi) * (1.0 + kappa) / m1 + 1.0 / m2);
}

Eigen::Vector2d two_link_forces(const Parameters& p, const Geometry& g, const AppliedForces& f,
                                const Vec3& a_ddot) {
  const double m1 = p.bead_mass, m2 = p.ball_mass, c = g.cos_psi;
  Eigen::Matrix2d A;
  A << 1.0 / m1, -c / m1, -c / m1, 1.0 / m1 + 1.0 / m2;
  const Eigen::Vector2d rhs(g.u1.dot(f.f1) / m1 - g.u1.dot(a_ddot) + g.q1,
                            g.u2.dot(f.f2) / m2 - g.u2.dot(f.f1) / m1 + g.q2);
  // Closed-form 2×2 solve; det = (1 - c²)/m1² + 1/(m1 m2) > 0.
  const double det = A(0, 0) * A(1, 1) - A(0, 1) * A(1, 0);
  return {(A(1, 1) * rhs(0) - A(0, 1) * rhs(1)) / det, (A(0, 0) * rhs(1) - A(1, 0) * rhs(0)) / det};
}

ConeMargins cone_margins(const Model& m, const Geometry& g, double T1, double T2) {
  const FrictionCone cone = friction_cone(m.layers.friction_law, sticking_mu(m), g.psi);
  return {T1 - cone.lo * T2, std::isinf(cone.hi) ? std::numeric_limits<double>::infinity() : cone.hi * T2 - T1};
}

double held_length(const Model& m, const Contact& c) {
  switch (c.mode) {
    case Mode::BottomStop: return m.p.string_length - m.p.contact_distance;
    case Mode::TopStop: return m.p.top_stop;
    case Mode::Stuck: return c.s_star;
    default: return std::numeric_limits<double>::quiet_NaN();
  }
}

Constraints constraints(const Model& m, const Contact& contact, const TopKinematics& top,
                        const numerics::Vec& y) {
  const Vec3 r1 = y.segment<3>(idx::r1), r2 = y.segment<3>(idx::r2);
  const Vec3 d1 = r1 - top.a, d2 = r2 - r1;
  const double L1 = d1.norm(), L2 = d2.norm();
  const Vec3 u1 = d1 / L1, u2 = d2 / L2;
  Constraints c;
  c.J.setZero();
  c.C.setZero();
  c.b.setZero();
  switch (contact.mode) {
    case Mode::Sliding:  // C = L1 + L2 - l; ∂C/∂r1 = u1 - u2, ∂C/∂r2 = u2; Ċ = J v - u1·ȧ
      c.n = 1;
      c.J.block<1, 3>(0, 0) = (u1 - u2).transpose();
      c.J.block<1, 3>(0, 3) = u2.transpose();
      c.C(0) = L1 + L2 - m.p.string_length;
      c.b(0) = u1.dot(top.a_dot);
      break;
    case Mode::BottomStop:  // C = (L1 - (l - d), L2 - d)
    case Mode::TopStop:     // C = (L1 - s_min, L2 - (l - s_min))
    case Mode::Stuck: {     // C = (L1 - s*, L2 - (l - s*))
      const double s1 = held_length(m, contact);
      c.n = 2;
      c.J.block<1, 3>(0, 0) = u1.transpose();
      c.J.block<1, 3>(1, 0) = -u2.transpose();
      c.J.block<1, 3>(1, 3) = u2.transpose();
      c.C(0) = L1 - s1;
      c.C(1) = L2 - (m.p.string_length - s1);
      c.b(0) = u1.dot(top.a_dot);
      break;
    }
    case Mode::Slack:  // no constraint: a free flight
      c.n = 0;
      break;
  }
  return c;
}

namespace {
using Vec6 = Eigen::Matrix<double, 6, 1>;

Vec6 inverse_mass(const Parameters& p) {
  Vec6 w;
  w << Vec3::Constant(1.0 / p.bead_mass), Vec3::Constant(1.0 / p.ball_mass);
  return w;
}

// Solve (J M⁻¹ Jᵀ) λ = rhs on the n active rows; λ is zero beyond n.
Eigen::Vector2d multipliers(const Constraints& c, const Vec6& Minv, const Eigen::Vector2d& rhs) {
  const Eigen::Matrix<double, 2, 6> JW = c.J * Minv.asDiagonal();
  const Eigen::Matrix2d A = JW * c.J.transpose();
  if (c.n == 0) return Eigen::Vector2d::Zero();
  if (c.n == 1) return {rhs(0) / A(0, 0), 0.0};
  return A.inverse() * rhs;  // 2×2, det > 0 for two distinct links
}

double max_abs(const Eigen::Vector2d& v, int n) {
  if (n == 0) return 0.0;
  return n == 1 ? std::abs(v(0)) : std::max(std::abs(v(0)), std::abs(v(1)));
}
}  // namespace

Drift constraint_drift(const Model& m, const Contact& contact, const TopKinematics& top,
                       const numerics::Vec& y) {
  const Constraints c = constraints(m, contact, top, y);
  Vec6 v;
  v << y.segment<3>(idx::v1), y.segment<3>(idx::v2);
  const Eigen::Vector2d vres = c.J * v - c.b;
  return {max_abs(c.C, c.n), max_abs(vres, c.n)};
}

void project_positions(const Model& m, const Contact& contact, const TopKinematics& top,
                       numerics::Vec& y) {
  const Vec6 Minv = inverse_mass(m.p);
  // Newton on C(x) = 0 along M⁻¹Jᵀ: quadratic convergence, 3 iterations reach round-off
  // from any drift an accepted step can leave.
  for (int it = 0; it < 4; ++it) {
    const Constraints c = constraints(m, contact, top, y);
    if (max_abs(c.C, c.n) < 1e-15 * m.p.string_length) break;
    const Eigen::Vector2d lambda = multipliers(c, Minv, c.C);
    const Vec6 dx = -(Minv.asDiagonal() * (c.J.transpose() * lambda));
    y.segment<3>(idx::r1) += dx.head<3>();
    y.segment<3>(idx::r2) += dx.tail<3>();
  }
}

namespace {
// The impulse onto the constraint rows of c with restitution e, and its energy account.
ProjectionEnergy impulse(const Model& m, const Constraints& c, numerics::Vec& y, double e) {
  const Vec6 Minv = inverse_mass(m.p);
  Vec6 v;
  v << y.segment<3>(idx::v1), y.segment<3>(idx::v2);
  const double ke0 = 0.5 * v.dot(v.cwiseQuotient(Minv));
  const Eigen::Vector2d lambda = (1.0 + e) * multipliers(c, Minv, c.J * v - c.b);
  v -= Minv.asDiagonal() * (c.J.transpose() * lambda);
  y.segment<3>(idx::v1) = v.head<3>();
  y.segment<3>(idx::v2) = v.tail<3>();
  // ΔKE = -dissipated - λᵀb: what the top's impulse put in and the balls did not keep was lost.
  ProjectionEnergy out;
  out.motor_work = -lambda.dot(c.b);  // λ and b vanish beyond n
  out.dissipated = out.motor_work - (0.5 * v.dot(v.cwiseQuotient(Minv)) - ke0);
  return out;
}

Constraints one_row(const Vec3& d_r1, const Vec3& d_r2, double b) {
  Constraints c;
  c.n = 1;
  c.J.setZero();
  c.C.setZero();
  c.b.setZero();
  c.J.block<1, 3>(0, 0) = d_r1.transpose();
  c.J.block<1, 3>(0, 3) = d_r2.transpose();
  c.b(0) = b;
  return c;
}
}  // namespace

ProjectionEnergy project_velocities(const Model& m, const Contact& contact, const TopKinematics& top,
                                    numerics::Vec& y, double restitution) {
  return impulse(m, constraints(m, contact, top, y), y, restitution);
}

ProjectionEnergy collide_with_ball(const Model& m, numerics::Vec& y, double restitution) {
  const Vec3 u2 = (Vec3(y.segment<3>(idx::r2)) - Vec3(y.segment<3>(idx::r1))).normalized();
  return impulse(m, one_row(-u2, u2, 0.0), y, restitution);  // L̇2 = u2·(v2 - v1)
}

ProjectionEnergy collide_with_top(const Model& m, const TopKinematics& top, numerics::Vec& y,
                                  double restitution) {
  const Vec3 u1 = (Vec3(y.segment<3>(idx::r1)) - top.a).normalized();
  return impulse(m, one_row(u1, Vec3::Zero(), u1.dot(top.a_dot)), y, restitution);  // L̇1 = u1·(v1 - ȧ)
}

}  // namespace ajx::physics

namespace ajx::physics {
std::string_view to_string(Mode m) {
  switch (m) {
    case Mode::Sliding: return "sliding";
    case Mode::BottomStop: return "bottom_stop";
    case Mode::Stuck: return "stuck";
    case Mode::TopStop: return "top_stop";
    case Mode::Slack: return "slack";
  }
  return "?";
}
}  // namespace ajx::physics
