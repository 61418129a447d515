// Energy accounting. The motor's work at the rod goes into the tie's kinetic energy, the
// clutch's loss and the string (physics/tie.hpp); what the string receives goes into the balls'
// energy and the losses:
//   W_m = ΔE_tie + W_c + W_s,   W_s = ΔE + drag loss + friction loss + impact loss.
// For a rigid tie W_m = W_s and ΔE_tie = W_c = 0.
#pragma once
#include "numerics/vector.hpp"
#include "physics/model.hpp"
#include "physics/state.hpp"

namespace ajx::physics {

// E = ½ m1 |v1|² + ½ m2 |v2|² + m1 g z1 + m2 g z2 [J]
double mechanical_energy(const Parameters& p, const numerics::Vec& y);

struct EnergyBalance {
  double motor_work;       // W_m, the motor's work at the rod, ∫ τ_rod ω_m dt [J]
  double string_work;      // W_s, the work the top passes into the string [J]
  double clutch_loss;      // W_c = ∫ τ_c (ω_m − χ̇) dt [J]
  double delta_tie_energy; // ΔE_tie = Δ(½ I_a χ̇²) [J]
  double delta_energy;     // ΔE [J]
  double drag_loss;        // [J]
  double friction_loss;    // [J]
  double impact_loss;      // [J]
  double residual;         // W_m − ΔE_tie − W_c − ΔE − losses [J]
  double tie_residual;     // W_m − ΔE_tie − W_c − W_s, the tie's own balance [J]
  double scale;            // the largest term, for a relative residual [J]
  double relative() const { return scale > 0 ? residual / scale : 0.0; }
};

// The balance between two states of one run (the work integrals are cumulative).
EnergyBalance energy_balance(const Parameters& p, const State& begin, const State& end);

}  // namespace ajx::physics
