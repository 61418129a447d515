#include "physics/rotating_axes.hpp"

#include <cmath>

namespace ajx::physics {

TopKinematics top_in_rotating_axes(const MotorSchedule& schedule, double t) {
  const double R = schedule.radius();
  double phi, omega, omega_dot;
  schedule.phase(t, phi, omega, omega_dot);
  // point_on_circle(R, 0, ω, ω̇) without its cos 0 and sin 0: a = (R, 0, 0), ȧ = (0, R ω, 0),
  // ä = (−R ω², R ω̇, 0), the same values to the last bit (up to the sign of a zero).
  TopKinematics k;
  k.phi = 0.0;
  k.omega = k.motor_omega = omega;
  k.omega_dot = k.motor_omega_dot = omega_dot;
  k.a = Vec3(R, 0.0, 0.0);
  k.a_dot = Vec3(0.0, R * omega, 0.0);
  k.a_ddot = Vec3(-(R * omega * omega), R * omega_dot, 0.0);
  return k;
}

// flatten: as physics::evaluate (astrojax_system.cpp), the drive and the dynamics in one body.
[[gnu::flatten]] void rhs_in_rotating_axes(const Model& m, const MotorSchedule& schedule, const Contact& c,
                                           double t, const numerics::Vec& y, numerics::Vec& dydt) {
  const TopKinematics top = top_in_rotating_axes(schedule, t);
  const Dynamics d = evaluate(m, top, c, y, true);
  const double w = top.omega;
  // Ω×x = ω (−x_y, x_x, 0)
  const auto omega_cross = [w](const auto& x) { return Vec3(-w * x.y(), w * x.x(), 0.0); };
  dydt.resize(y.size());
  dydt.segment<3>(idx::r1) = y.segment<3>(idx::v1) - omega_cross(y.segment<3>(idx::r1));
  dydt.segment<3>(idx::r2) = y.segment<3>(idx::v2) - omega_cross(y.segment<3>(idx::r2));
  dydt.segment<3>(idx::v1) = d.acc1 - omega_cross(y.segment<3>(idx::v1));
  dydt.segment<3>(idx::v2) = d.acc2 - omega_cross(y.segment<3>(idx::v2));
  dydt(idx::motor_work) = d.motor_power + d.couple_power;  // the couple's power comes from the motor
  dydt(idx::drag_loss) = d.drag_power;
  dydt(idx::friction_loss) = d.friction_power;
  if (y.size() > idx::dim) ledger_rates(m, top, c, d, y, dydt);  // the pair couple's (no tie in these axes)
}

void rotate_about_z(numerics::Vec& y, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  for (int k : {idx::r1, idx::r2, idx::v1, idx::v2}) {
    const double x = y(k), yy = y(k + 1);
    y(k) = c * x - s * yy;
    y(k + 1) = s * x + c * yy;
  }
}

}  // namespace ajx::physics
