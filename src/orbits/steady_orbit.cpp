#include "orbits/steady_orbit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "numerics/damped_newton.hpp"
#include "physics/string_friction.hpp"

namespace ajx::orbits {

std::string_view to_string(Closure c) {
  switch (c) {
    case Closure::Stuck: return "stuck";
    case Closure::BottomStop: return "bottom_stop";
    case Closure::Frictionless: return "frictionless";
    case Closure::ConeUp: return "cone_up";
    case Closure::ConeDown: return "cone_down";
  }
  return "?";
}

Scales scales(const physics::Model& m) {
  return {m.p.string_length, (m.p.bead_mass + m.p.ball_mass) * m.p.gravity};
}

namespace {
constexpr double kEps = std::numeric_limits<double>::epsilon();

Vec3 horizontal(const Vec3& v) { return {v.x(), v.y(), 0.0}; }

Vec9 unknown_scales(const physics::Model& m) {
  const Scales sc = scales(m);
  Vec9 d;
  d << Vec3::Constant(sc.length), Vec3::Constant(sc.length), sc.force, sc.force, sc.length;
  return d;
}
}  // namespace

Vec9 residual(const OrbitProblem& pb, const Vec9& X) {
  const physics::Parameters& p = pb.model.p;
  const Scales sc = scales(pb.model);
  const Vec3 a(p.drive_radius, 0, 0), W(0, 0, pb.omega), z = Vec3::UnitZ();
  const Vec3 p1 = X.segment<3>(0), p2 = X.segment<3>(3);
  const double F1 = X(6), F2 = X(7), s = X(8), w2 = pb.omega * pb.omega;
  const Vec3 d1 = p1 - a, d2 = p2 - p1;
  const double L1 = d1.norm(), L2 = d2.norm();
  const Vec3 u1 = d1 / L1, u2 = d2 / L2;
  Vec9 r;
  // m ω² P p + (string + drag + gravity) = 0 for each ball.
  r.segment<3>(0) = (-F1 * u1 + F2 * u2 - p.drag * W.cross(p1) - p.bead_mass * p.gravity * z +
                     p.bead_mass * w2 * horizontal(p1)) / sc.force;
  r.segment<3>(3) =
      (-F2 * u2 - p.drag * W.cross(p2) - p.ball_mass * p.gravity * z + p.ball_mass * w2 * horizontal(p2)) / sc.force;
  r(6) = (L1 - s) / sc.length;
  r(7) = (L2 - (p.string_length - s)) / sc.length;
  switch (pb.closure) {
    case Closure::Stuck: r(8) = (s - pb.s_star) / sc.length; break;
    case Closure::BottomStop: r(8) = (s - (p.string_length - p.contact_distance)) / sc.length; break;
    case Closure::Frictionless: r(8) = (F1 - F2) / sc.force; break;
    case Closure::ConeUp:
    case Closure::ConeDown: {
      const physics::FrictionCone cone = physics::friction_cone(
          pb.model.layers.friction_law, physics::sticking_mu(pb.model), physics::deflection(u1, u2));
      r(8) = (F1 - (pb.closure == Closure::ConeUp ? cone.lo : cone.hi) * F2) / sc.force;
      break;
    }
  }
  return r;
}

Mat9 jacobian(const OrbitProblem& pb, const Vec9& X) {
  return numerics::central_jacobian<9>([&](const Vec9& x) { return residual(pb, x); }, X, unknown_scales(pb.model));
}

double default_tolerance(const OrbitProblem& pb) {
  // Each scaled equation sums a handful of terms of size up to 1 + ω² l/g (the centripetal
  // force over W); each carries a rounding of ε, and so does their sum.
  const physics::Parameters& p = pb.model.p;
  return 16.0 * kEps * (1.0 + pb.omega * pb.omega * p.string_length / std::max(p.gravity, 1e-300));
}

NewtonResult solve(const OrbitProblem& pb, Vec9 X, const NewtonOptions& opt) {
  const double tol = opt.tolerance > 0.0 ? opt.tolerance : default_tolerance(pb);
  const double l = pb.model.p.string_length;
  const auto solve_step = [](const Mat9& J, const Vec9& r) -> Vec9 {
    Eigen::CompleteOrthogonalDecomposition<Mat9> cod(J);
    cod.setThreshold(1e-11);  // R = 0 without drag: the azimuth is free, take the least step
    return -cod.solve(r);
  };
  const auto limit = [l](Vec9 dx) {  // far from the root, no ball moves by more than l/5 in one step
    const double move = std::max(dx.segment<3>(0).norm(), dx.segment<3>(3).norm());
    if (move > 0.2 * l) dx *= 0.2 * l / move;
    return dx;
  };
  const auto root = numerics::damped_newton<9>([&](const Vec9& x) { return residual(pb, x); }, X,
                                               unknown_scales(pb.model), tol, opt.max_iterations, solve_step, limit);
  NewtonResult out;
  out.X = root.x;
  out.residual = root.residual;
  out.iterations = root.iterations;
  out.converged = root.converged;
  return out;
}

physics::Contact holding_contact(const physics::Model& m, Closure c, double s) {
  if (c == Closure::BottomStop) return {physics::Mode::BottomStop, 0, 0.0};
  if (physics::can_stick(m)) return {physics::Mode::Stuck, 0, s};
  return {physics::Mode::Sliding, 0, 0.0};
}

SteadyOrbit describe(const OrbitProblem& pb, const Vec9& X) {
  const physics::Model& m = pb.model;
  const physics::Parameters& p = m.p;
  constexpr double inf = std::numeric_limits<double>::infinity();
  SteadyOrbit o;
  o.closure = pb.closure;
  o.omega = pb.omega;
  o.p1 = X.segment<3>(0);
  o.p2 = X.segment<3>(3);
  o.F1 = X(6);
  o.F2 = X(7);
  o.s = X(8);
  o.rho1 = std::hypot(o.p1.x(), o.p1.y());
  o.rho2 = std::hypot(o.p2.x(), o.p2.y());
  o.z1 = o.p1.z();
  o.z2 = o.p2.z();
  o.phase1 = std::atan2(o.p1.y(), o.p1.x());
  o.phase2 = std::atan2(o.p2.y(), o.p2.x());
  const Vec3 a(p.drive_radius, 0, 0);
  physics::Geometry g{};
  g.u1 = (o.p1 - a).normalized();
  g.u2 = (o.p2 - o.p1).normalized();
  g.psi = physics::deflection(g.u1, g.u2);
  o.psi = g.psi;
  const physics::FrictionCone cone = physics::friction_cone(m.layers.friction_law, physics::sticking_mu(m), g.psi);
  o.margins = physics::cone_margins(m, g, o.F1, o.F2);
  o.T1 = o.F1;
  o.T2 = o.F2;
  if (pb.closure == Closure::BottomStop) {
    // As physics::evaluate: the T2 closest to F2 that the cone allows; the ball pushes the rest.
    const double T2_max = cone.lo > 0.0 ? o.F1 / cone.lo : inf;
    o.T2 = std::max(std::min(o.F2, T2_max), o.F1 / cone.hi);
    o.contact = o.T2 - o.F2;
    o.margins.down = inf;
  }
  if (o.T1 > 0 && o.T2 > 0) {
    if (m.layers.friction_law == physics::FrictionLaw::Capstan)
      o.mu_required = o.psi > 0 ? std::abs(std::log(o.T1 / o.T2)) / o.psi : (o.T1 == o.T2 ? 0.0 : inf);
    else
      o.mu_required = std::abs(o.T1 - o.T2) * std::cos(0.5 * o.psi) / ((o.T1 + o.T2) * std::sin(0.5 * o.psi));
  }
  const double s_lo = m.layers.top_stop ? p.top_stop : 0.0;
  const double s_hi = m.layers.bottom_stop ? p.string_length - p.contact_distance : p.string_length;
  const double slack = 64.0 * kEps * p.string_length;
  o.taut = o.T1 > 0 && o.T2 > 0;
  o.in_range = o.s >= s_lo - slack && o.s <= s_hi + slack;
  // The edges and the frictionless orbits sit on or inside the cone by construction; allow
  // the round-off of the closure.
  const double edge = 64.0 * kEps * scales(m).force;
  bool cone_ok = true;
  switch (pb.closure) {
    case Closure::BottomStop: cone_ok = m.layers.bottom_stop && o.margins.up >= -edge && o.contact >= -edge; break;
    case Closure::Frictionless: cone_ok = true; break;
    case Closure::Stuck:
    case Closure::ConeUp:
    case Closure::ConeDown: cone_ok = o.margins.up >= -edge && o.margins.down >= -edge; break;
  }
  o.admissible = o.taut && o.in_range && cone_ok;
  o.branch = std::string(o.p1.x() > 0 ? "+" : "-") + "/" + (o.p2.x() > 0 ? "+" : "-");
  o.residual = residual(pb, X).lpNorm<Eigen::Infinity>();
  return o;
}

}  // namespace ajx::orbits
