#include "physics/astrojax_system.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "physics/string_friction.hpp"

namespace ajx::physics {

Dynamics evaluate(const Model& m, const TopKinematics& top, const Contact& c, const numerics::Vec& y) {
  const Parameters& p = m.p;
  const Vec3 r1 = y.segment<3>(idx::r1), r2 = y.segment<3>(idx::r2);
  const Vec3 v1 = y.segment<3>(idx::v1), v2 = y.segment<3>(idx::v2);
  constexpr double inf = std::numeric_limits<double>::infinity();
  Dynamics d;
  d.g = geometry(top, r1, r2, v1, v2);
  const AppliedForces f = applied_forces(p, v1, v2);

  double F2 = 0.0;  // net pull of link 2 on the bottom ball
  switch (c.mode) {
    case Mode::Sliding: {
      // T1 = κ(ψ, σ) T2 with the mode's sliding direction σ.
      const double kappa = tension_ratio(m.layers.friction_law, sliding_mu(m), d.g.psi, c.sigma);
      d.T2 = sliding_tension_T2(p, d.g, f, top.a_ddot, kappa);
      d.T1 = kappa * d.T2;
      F2 = d.T2;
      d.contact = 0.0;
      d.margins = {inf, inf};
      break;
    }
    case Mode::Stuck: {
      const Eigen::Vector2d tf = two_link_forces(p, d.g, f, top.a_ddot);
      d.T1 = tf(0);
      d.T2 = F2 = tf(1);
      d.contact = 0.0;
      d.margins = cone_margins(m, d.g, d.T1, d.T2);
      break;
    }
    case Mode::BottomStop: {
      const Eigen::Vector2d tf = two_link_forces(p, d.g, f, top.a_ddot);
      d.T1 = tf(0);
      F2 = tf(1);
      // Friction at rest makes T2 indeterminate within T1/κ_hi <= T2 <= T1/κ_lo; report the
      // T2 closest to F2, i.e. the smallest contact push N_c = T2 - F2 >= 0.
      const FrictionCone cone = friction_cone(m.layers.friction_law, sliding_mu(m), d.g.psi);
      const double T2_min = d.T1 / cone.hi;
      const double T2_max = cone.lo > 0.0 ? d.T1 / cone.lo : inf;
      d.T2 = std::max(std::min(F2, T2_max), T2_min);
      d.contact = d.T2 - F2;
      // One-sided cone: the ball blocks slipping down; it climbs when T1 - κ_lo F2 < 0.
      d.margins = {cone_margins(m, d.g, d.T1, F2).up, inf};
      break;
    }
  }
  d.acc1 = (-d.T1 * d.g.u1 + F2 * d.g.u2 + f.f1) / p.bead_mass;
  d.acc2 = (-F2 * d.g.u2 + f.f2) / p.ball_mass;
  d.motor_power = -d.T1 * d.g.u1.dot(top.a_dot);
  d.drag_power = p.drag * (v1.squaredNorm() + v2.squaredNorm());
  d.friction_power = c.mode == Mode::Sliding ? (d.T1 - d.T2) * d.g.L1_dot : 0.0;
  return d;
}

void rhs(const Model& m, const MotorSchedule& schedule, const Contact& c, double t,
         const numerics::Vec& y, numerics::Vec& dydt) {
  const TopKinematics top = schedule.top(m.p.drive_radius, t);
  const Dynamics d = evaluate(m, top, c, y);
  dydt.resize(idx::dim);
  dydt.segment<3>(idx::r1) = y.segment<3>(idx::v1);
  dydt.segment<3>(idx::r2) = y.segment<3>(idx::v2);
  dydt.segment<3>(idx::v1) = d.acc1;
  dydt.segment<3>(idx::v2) = d.acc2;
  dydt(idx::motor_work) = d.motor_power;
  dydt(idx::drag_loss) = d.drag_power;
  dydt(idx::friction_loss) = d.friction_power;
}

}  // namespace ajx::physics
