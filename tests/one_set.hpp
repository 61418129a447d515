// The one parameter set of docs/reports/reproduction-evidence.md, "One parameter set for the whole protocol": the tie clutch at
// R = 15 mm, d = 3.5 cm, τ_s = 1.5e-3 N m, τ_k = 1.35e-3 N m, c_a = 2e-6 N m s.
#pragma once
#include "physics/model.hpp"

inline ajx::physics::Model one_parameter_set() {
  ajx::physics::Model m;
  m.layers.tie_clutch = true;
  m.p.drive_radius = 0.015;
  m.p.contact_distance = 0.035;
  m.p.tie_static_torque = 1.5e-3;
  m.p.tie_kinetic_torque = 1.35e-3;
  m.p.tie_damping = 2e-6;
  return m;
}

// The documented apparatus (sweeps/paper.toml), R = 15 mm, d = 3.5 cm: with `clutch` the set
// above, else the paper's rigid tie.
inline ajx::physics::Model documented_set(bool clutch) {
  if (clutch) return one_parameter_set();
  ajx::physics::Model m;
  m.p.drive_radius = 0.015;
  m.p.contact_distance = 0.035;
  return m;
}
