// Event-driven stick-slip against the regularised law T1 = T2 exp(μ_k ψ tanh(ṡ/ε)) as ε -> 0:
// the creep error of the regularised model (its exact solution against the event-driven
// ones) and the cost of integrating it, which grows as ε shrinks for explicit methods
// (stiffness ~ 1/ε) and need not for the implicit Radau IIA. tanh saturates at μ_k, so as
// ε -> 0 the regularised law tends to the kinetic layer (the Filippov completion of Coulomb's
// law with μ_k), not to stick-slip with μ_s > μ_k: both are compared. The Stribeck law
// [μ_k + (μ_s − μ_k) e^{-(ṡ/v_s)²}] tanh(ṡ/ε) peaks near μ_s and holds a stuck bead by creeping;
// it tends to stick-slip as ε -> 0 and then v_s -> 0.
#pragma once
#include <string>
#include <vector>

#include "bench/work_precision.hpp"

namespace ajx::bench {

struct FrictionRow {
  double eps = 0.0;          // ε [m/s]; 0: the event-driven stick-slip model
  std::string method;
  std::string param_kind;    // "rtol" or "step"
  double param = 0.0;
  Outcome out;
  double err_model = 0.0;    // position error against the same model's reference [m]
  double err_stick_slip = 0.0;  // position error against the event-driven stick-slip reference [m]
  double err_kinetic = 0.0;     // ... against the event-driven kinetic (μ_k, Filippov) reference [m]
  double creep_stick_slip = 0.0;  // |L1 of the regularised reference - L1 of stick-slip| [m]
  double creep_kinetic = 0.0;     // |L1 of the regularised reference - L1 of the kinetic model| [m]
};

// The scene with a regularised friction layer at ε (the stick-slip scene otherwise): `law` is
// Friction::Regularised (tanh, saturating at μ_k) or Friction::Stribeck (peak near μ_s, decaying
// to μ_k over the scene's layers.stribeck_speed).
Scene regularised(const Scene& base, double eps, physics::Friction law = physics::Friction::Regularised);
// The scene with the kinetic layer: μ_k only, held by Filippov sliding at ṡ = 0.
Scene kinetic(const Scene& base);

// L1 = |r1 - a| at the state's time [m].
double bead_position(const Scene& scene, const physics::State& s);

}  // namespace ajx::bench
