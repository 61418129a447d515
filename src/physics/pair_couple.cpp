#include "physics/pair_couple.hpp"

#include <cmath>

namespace ajx::physics {

double couple_slip(double motor_omega, const Vec3& d2, const Vec3& d2_dot) {
  const double rho2 = d2.x() * d2.x() + d2.y() * d2.y();
  const double floor = kCoupleTiltFloor * kCoupleTiltFloor * d2.squaredNorm();
  // ω_m ρ² − ẑ·(d2 × ḋ2) = ẑ·(d2 × (ω_m ẑ × d2 − ḋ2)): 0 for a segment turning at ω_m
  const Vec3 rel = motor_omega * Vec3(-d2.y(), d2.x(), 0.0) - d2_dot;
  return (d2.x() * rel.y() - d2.y() * rel.x()) / (rho2 + floor);
}

PairCoupleForces pair_couple_forces(const Model& m, double motor_omega, const Vec3& r1, const Vec3& r2,
                                    const Vec3& v1, const Vec3& v2) {
  PairCoupleForces out;
  if (m.layers.pair_couple != PairCouple::MotorClutch) return out;
  const Vec3 d2 = r2 - r1, d2_dot = v2 - v1;
  out.slip = couple_slip(motor_omega, d2, d2_dot);
  // τ = τ_c tanh(w/Ω_ε)
  out.couple = m.p.couple_torque * std::tanh(out.slip / m.p.couple_slip_rate);
  // F2 = (τ/L2²) ẑ × d2, ẑ × d2 = (−d2y, d2x, 0)
  out.f2 = (out.couple / d2.squaredNorm()) * Vec3(-d2.y(), d2.x(), 0.0);
  out.f1 = -out.f2;
  out.power = out.f2.dot(d2_dot);
  const double rho2 = d2.x() * d2.x() + d2.y() * d2.y();
  out.loss = out.couple / d2.squaredNorm() * (motor_omega * rho2 - (d2.x() * d2_dot.y() - d2.y() * d2_dot.x()));
  return out;
}

}  // namespace ajx::physics
