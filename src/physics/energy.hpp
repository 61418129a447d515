// Energy accounting: motor work = Δ(kinetic + potential) + drag loss + friction loss + impact loss.
#pragma once
#include "numerics/vector.hpp"
#include "physics/model.hpp"
#include "physics/state.hpp"

namespace ajx::physics {

// E = ½ m1 |v1|² + ½ m2 |v2|² + m1 g z1 + m2 g z2 [J]
double mechanical_energy(const Parameters& p, const numerics::Vec& y);

struct EnergyBalance {
  double motor_work;    // W_m [J]
  double delta_energy;  // ΔE [J]
  double drag_loss;     // [J]
  double friction_loss; // [J]
  double impact_loss;   // [J]
  double residual;      // W_m - ΔE - losses [J]
  double scale;         // the largest term, for a relative residual [J]
  double relative() const { return scale > 0 ? residual / scale : 0.0; }
};

// The balance between two states of one run (the work integrals are cumulative).
EnergyBalance energy_balance(const Parameters& p, const State& begin, const State& end);

}  // namespace ajx::physics
