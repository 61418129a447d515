#include "physics/tie.hpp"

#include <cmath>

#include "physics/astrojax_system.hpp"

namespace ajx::physics {

namespace {

// The schedule's top turned by δ about the motor axis.
TopKinematics held_top(const MotorSchedule& schedule, double t, double offset) {
  double phi, omega, omega_dot;
  schedule.phase(t, phi, omega, omega_dot);
  TopKinematics k = point_on_circle(schedule.radius(), phi + offset, omega, omega_dot);
  schedule.add_hand(t, k);  // the hand's top, handed over at T onto the circle with δ = 0 (a held tie)
  return k;
}

}  // namespace

TopKinematics top_kinematics(const Model& m, const MotorSchedule& schedule, const Contact& c, double t,
                             const numerics::Vec& y) {
  if (!m.layers.tie_clutch || !c.tie.slip) return held_top(schedule, t, m.layers.tie_clutch ? c.tie.offset : 0.0);
  const double R = schedule.radius();
  // Slipping: a, ȧ from χ, χ̇; ä from the tie's equation with the string's pull.
  double phi_m, omega_m, omega_m_dot;
  schedule.phase(t, phi_m, omega_m, omega_m_dot);
  const double chi = y(idx::chi), chi_dot = y(idx::chi_dot);
  const Vec3 tangential(-std::sin(chi), std::cos(chi), 0.0);  // ê_χ
  TopKinematics k = point_on_circle(R, chi, chi_dot, 0.0);  // χ̈ = 0 for now
  k.motor_omega = omega_m;
  k.motor_omega_dot = omega_m_dot;
  // Only the pull F1 and u1 are read: the motion's evaluation (no cone) gives them bit for bit.
  const Dynamics d0 = evaluate(m, k, c, y, true);
  TopKinematics k1 = k;
  k1.a_ddot += R * tangential;  // χ̈ = 1 rad/s²
  const Dynamics d1 = evaluate(m, k1, c, y, true);
  const double lever = R * tangential.dot(d0.g.u1);  // R (ê_χ·u1)
  const double clutch = c.tie.sigma * m.p.tie_kinetic_torque + m.p.tie_damping * (omega_m - chi_dot);
  const double chi_ddot = (clutch + lever * d0.pull) / (m.p.tie_inertia - lever * (d1.pull - d0.pull));
  k.omega_dot = chi_ddot;
  k.a_ddot += chi_ddot * R * tangential;
  return k;
}

double tie_torque_needed(const Model& m, const TopKinematics& held, const Dynamics& d) {
  if (held.hand) return m.p.tie_inertia * held.motor_omega_dot;  // the string pulls the hand, not the tie
  const Vec3 tangential(-std::sin(held.phi), std::cos(held.phi), 0.0);
  return m.p.tie_inertia * held.motor_omega_dot - m.p.drive_radius * tangential.dot(d.g.u1) * d.pull;
}

double tie_torque_needed(const Model& m, const TopKinematics& held, const Contact& c, const numerics::Vec& y) {
  return tie_torque_needed(m, held, evaluate(m, held, c, y));
}

TiePowers tie_powers(const Model& m, const TopKinematics& top, const Contact& c, const Dynamics& d) {
  // While the hand holds the top the work the top does, −F1 u1·ẋ_top, is booked with the rod's:
  // W_m is the work of everything that moves the top.
  if (!c.tie.slip) return {tie_torque_needed(m, top, d) * top.motor_omega + (top.hand ? d.motor_power : 0.0), 0.0};
  const double slip = top.motor_omega - top.omega;  // ω_m − χ̇
  const double tau_c = c.tie.sigma * m.p.tie_kinetic_torque + m.p.tie_damping * slip;
  return {tau_c * top.motor_omega, tau_c * slip};
}

double tie_energy(const Parameters& p, const numerics::Vec& y) {
  if (!has_tie(y)) return 0.0;
  return 0.5 * p.tie_inertia * y(idx::chi_dot) * y(idx::chi_dot);
}

void hold_tie(const MotorSchedule& schedule, double t, double offset, numerics::Vec& y) {
  double phi, omega, omega_dot;
  schedule.phase(t, phi, omega, omega_dot);
  y(idx::chi) = phi + offset;
  y(idx::chi_dot) = omega;
}

}  // namespace ajx::physics
