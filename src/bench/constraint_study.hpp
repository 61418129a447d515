// Constraint handling compared on a smooth scene (one contact mode): the index-1 formulation
// alone ("none": the tensions enforce C̈ = 0, so C and Ċ drift with the truncation error),
// Baumgarte stabilisation C̈ + 2α Ċ + α² C = 0 (critically damped, gain α [1/s]), and the
// projection after every step whose drift exceeds 1e-12 m (the product's choice). Baumgarte's
// correction acts along the constraint normals, Δr̈ = M⁻¹Jᵀμ with (J M⁻¹ Jᵀ) μ = -(2αĊ + α²C):
// it vanishes on the constraint manifold and lives here, not in physics/.
#pragma once
#include <string>

#include "bench/work_precision.hpp"

namespace ajx::bench {

struct ConstraintVariant {
  std::string name;      // "none", "baumgarte", "projection"
  double alpha = 0.0;    // Baumgarte gain α [1/s]
  bool project = false;
};

struct ConstraintRun {
  std::string status = "ok";
  double cpu = 0.0;         // median CPU of the timed runs (no drift observer) [s]
  long steps = 0, rhs_evals = 0;
  double max_drift = 0.0;   // largest |C| after any step (before projection) [m]
  double end_drift = 0.0;   // |C| at the horizon [m]
  double energy_residual = 0.0;
  physics::State final;
};

// Integrates the scene's initial mode with numerics::integrate (no events) to the horizon.
ConstraintRun run_constraint_variant(const Scene& scene, const ConstraintVariant& v, const Setting& s, int repeats);

}  // namespace ajx::bench
