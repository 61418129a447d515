#include "physics/energy.hpp"

#include <algorithm>
#include <cmath>

#include "physics/tie.hpp"

namespace ajx::physics {

double mechanical_energy(const Parameters& p, const numerics::Vec& y) {
  const double kinetic = 0.5 * p.bead_mass * y.segment<3>(idx::v1).squaredNorm() +
                         0.5 * p.ball_mass * y.segment<3>(idx::v2).squaredNorm();
  const double potential = p.gravity * (p.bead_mass * y(idx::r1 + 2) + p.ball_mass * y(idx::r2 + 2));
  return kinetic + potential;
}

EnergyBalance energy_balance(const Parameters& p, const State& b, const State& e) {
  EnergyBalance r;
  r.string_work = e.y(idx::motor_work) - b.y(idx::motor_work);
  const bool ledger = has_ledger(e.y) && has_ledger(b.y);
  r.motor_work = ledger ? e.y(idx::rod_work) - b.y(idx::rod_work) : r.string_work;
  r.clutch_loss = ledger ? e.y(idx::clutch_loss) - b.y(idx::clutch_loss) : 0.0;
  r.delta_tie_energy = has_tie(e.y) && has_tie(b.y) ? tie_energy(p, e.y) - tie_energy(p, b.y) : 0.0;
  r.delta_energy = mechanical_energy(p, e.y) - mechanical_energy(p, b.y);
  r.drag_loss = e.y(idx::drag_loss) - b.y(idx::drag_loss);
  r.friction_loss = e.y(idx::friction_loss) - b.y(idx::friction_loss);
  r.impact_loss = e.impact_loss - b.impact_loss;
  r.tie_residual = r.motor_work - r.delta_tie_energy - r.clutch_loss - r.string_work;
  r.residual = r.motor_work - r.delta_tie_energy - r.clutch_loss - r.delta_energy - r.drag_loss -
               r.friction_loss - r.impact_loss;
  r.scale = std::max({std::abs(r.motor_work), std::abs(r.string_work), r.clutch_loss, std::abs(r.delta_tie_energy),
                      std::abs(r.delta_energy), r.drag_loss, r.friction_loss, r.impact_loss});
  return r;
}

}  // namespace ajx::physics
