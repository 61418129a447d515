// The tie of the string to the motor's rod (the tie-clutch layer). Rigid by default: the top
// of the string is a(t) = R (cos φ, sin φ, 0). With the clutch, the tie is a small body of
// moment of inertia I_a at azimuth χ on the same circle, held to the rod by dry friction:
//   held      χ = φ + δ (δ fixed), while the torque the rod must apply,
//             τ = I_a ω̇_m − R (ê_χ·u1) F1, stays within |τ| <= τ_s;
//   slipping  I_a χ̈ = σ τ_k + c_a (ω_m − χ̇) + R (ê_χ·u1) F1,  σ = sgn(ω_m − χ̇),
// with F1 the net pull of the string's upper link on the tie (along u1, towards the bead)
// and ê_χ = (−sin χ, cos χ, 0). F1 depends on ä = R χ̈ ê_χ − R χ̇² ê_r linearly, so χ̈ solves
//   χ̈ [I_a − R (ê_χ·u1) ∂F1/∂χ̈] = σ τ_k + R (ê_χ·u1) F1(χ̈ = 0),
// where −R (ê_χ·u1) ∂F1/∂χ̈ >= 0 (pulling the tie towards the bead slackens the string): the
// bracket is positive for every I_a > 0. The tie on the string is an undamped oscillator
// (stiffness ≈ R² F1 / L1 against I_a); the clutch's small viscous part c_a damps it at the
// rate c_a / 2I_a while adding only c_a (ω_m − χ̇) to τ_k (defaults: I_a = 5e-8 kg m², a 0.5 g
// knot at 1 cm, and c_a = 1e-7 N m s: 1/s, and 3e-6 N m at a slip of 30 rad/s).
// The ledger (physics/energy.hpp). The rod applies τ_rod to the tie: the held torque above, or
// τ_c = σ τ_k + c_a (ω_m − χ̇) while slipping. The motor's power is τ_rod ω_m; the tie's
// equation times χ̇ splits it as
//   τ_rod ω_m = d(½ I_a χ̇²)/dt + τ_c (ω_m − χ̇) + (−F1 u1·ȧ),
// the tie's kinetic energy, the clutch's loss (>= 0, zero while held) and the power the top
// passes into the string (ȧ = R χ̇ ê_χ).
#pragma once
#include "numerics/vector.hpp"
#include "physics/astrojax_system.hpp"
#include "physics/drive.hpp"
#include "physics/model.hpp"
#include "physics/state.hpp"

namespace ajx::physics {

// The top of the string at (t, y) in contact state c: the schedule's a(t) turned by the tie's
// offset while held; the tie's χ, χ̇ and the solved χ̈ while slipping. `motor_omega` is ω_m.
TopKinematics top_kinematics(const Model& m, const MotorSchedule& schedule, const Contact& c, double t,
                             const numerics::Vec& y);

// The torque τ = I_a ω̇_m − R (ê_χ·u1) F1 the rod must apply to keep the tie held, for a top
// `held` that moves with the motor [N m].
double tie_torque_needed(const Model& m, const TopKinematics& held, const Contact& c, const numerics::Vec& y);
// The same from the mode's dynamics already evaluated at that top (the guards share one).
double tie_torque_needed(const Model& m, const TopKinematics& held, const Dynamics& d);

// The motor's power at the rod, τ_rod ω_m, and the clutch's loss τ_c (ω_m − χ̇) [W], at the top
// `top` (top_kinematics) with the dynamics `d` evaluated there.
struct TiePowers {
  double rod;     // τ_rod ω_m [W]
  double clutch;  // τ_c (ω_m − χ̇), 0 while held [W]
};
TiePowers tie_powers(const Model& m, const TopKinematics& top, const Contact& c, const Dynamics& d);

// ½ I_a χ̇² [J]; 0 for a rigid tie (the state has no χ̇).
double tie_energy(const Parameters& p, const numerics::Vec& y);

// A held tie's state at time t: χ = φ + δ, χ̇ = ω_m written into y.
void hold_tie(const MotorSchedule& schedule, double t, double offset, numerics::Vec& y);

}  // namespace ajx::physics
