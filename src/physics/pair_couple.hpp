// The pair couple (the diagnostic layer `pair_couple = "motor_clutch"`, off by default): a pure
// couple about ẑ between the two balls, like kinetic friction between the motor's rotation and
// the lower segment's rotation about the axis. It asks what torque on the pair the climb from
// rest would need (docs/reports/reproduction-evidence.md, "A couple on the pair"); it is not a model of a part of the Astrojax.
//   d2 = r2 − r1, ḋ2 = v2 − v1, ρ² = d2x² + d2y² (the lower segment's horizontal length²);
//   β̇ = ẑ·(d2 × ḋ2)/ρ²                     the lower segment's spin about z;
//   w = (ω_m ρ² − ẑ·(d2 × ḋ2)) / (ρ² + (ε L2)²) = (ω_m − β̇) ρ²/(ρ² + (ε L2)²),  ε = 1e-3:
//                                           the slip, regularised near the vertical (no 1/ρ²)
//                                           and exactly 0 when the segment turns with the motor;
//   τ = τ_c tanh(w/Ω_ε);
//   F2 = (τ / L2²) ẑ × d2 on the bottom ball, F1 = −F2 on the bead.
// Zero net force; torque about z = τ ρ²/L2² = τ sin²θ12 (θ12 the lower segment's tilt), so
// |F2| ≤ τ_c/L2 and the couple vanishes for a vertical lower segment. Its power on the balls,
// F2·(v2 − v1) = τ ẑ·(d2 × ḋ2)/L2², comes from the motor through a slipping clutch: the motor turns
// its side at ω_m against the torque τ ρ²/L2² and delivers τ ω_m ρ²/L2², of which the slip
// dissipates the rest, τ (ω_m ρ² − ẑ·(d2 × ḋ2))/L2² >= 0 (τ has the sign of w). The ledger
// (physics/energy.hpp) counts the power on the balls with the string's work, the motor's share in
// W_m and the slip's in the clutches' loss W_c.
#pragma once
#include "physics/drive.hpp"
#include "physics/model.hpp"

namespace ajx::physics {

// ε of the slip's regularisation: the slip is scaled by ρ²/(ρ² + (ε L2)²), which differs from 1
// only below a tilt of a few mrad (where the couple's lever ρ/L2² vanishes anyway).
inline constexpr double kCoupleTiltFloor = 1e-3;

struct PairCoupleForces {
  Vec3 f1 = Vec3::Zero();  // on the bead [N]
  Vec3 f2 = Vec3::Zero();  // on the bottom ball [N]
  double slip = 0.0;       // w, the regularised ω_m − β̇ [rad/s]
  double couple = 0.0;     // τ [N m]
  double power = 0.0;      // F1·v1 + F2·v2 = F2·(v2 − v1) [W]
  double loss = 0.0;       // τ (ω_m ρ² − ẑ·(d2 × ḋ2))/L2², the slip's dissipation [W]
};

// w = (ω_m ρ² − ẑ·(d2 × ḋ2))/(ρ² + (ε |d2|)²) [rad/s]
double couple_slip(double motor_omega, const Vec3& d2, const Vec3& d2_dot);

// The couple's forces at a state; zero when the layer is off. `motor_omega` is ω_m.
PairCoupleForces pair_couple_forces(const Model& m, double motor_omega, const Vec3& r1, const Vec3& r2,
                                    const Vec3& v1, const Vec3& v2);

}  // namespace ajx::physics
