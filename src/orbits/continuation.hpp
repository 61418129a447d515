// Pseudo-arclength continuation of locked orbits in ω_m or any model parameter λ, so that
// folds are passed and located instead of lost. In scaled unknowns Z = (X / scales, λ / λ_s)
// the branch is the curve G(Z) = 0 (steady_orbit.hpp's nine equations); each step predicts
// along the unit tangent t (ker G_Z, oriented to continue the previous one) and corrects by
// Newton on [G(Z); t·(Z − Z_pred)] = 0.
// Test functions along the branch, each located by bisection on its sign between two points:
//   fold          t_λ = 0 (the branch turns back in λ; two orbits meet and vanish)
//   branch point  det [G_Z; tᵀ] changes sign (another branch crosses)
//   stability     the number of eigenvalues with Re λ > 0 changes (orbit_stability.hpp):
//                 through a complex pair, a Hopf-type crossing with the frequency Im λ
//   cone exit     a static-cone margin changes sign (the bead slides up or down the string;
//                 at the bottom stop, climbs off the ball)
//   slack         min(T1, T2) changes sign
#pragma once
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "orbits/orbit_stability.hpp"
#include "orbits/steady_orbit.hpp"

namespace ajx::orbits {

// "omega" (ω_m), "s" (s* of a stuck orbit), or a model parameter the table marks
// (physics/parameter_table.hpp): string_length, bead_mass, ball_mass, drag, μ_s, μ_k, gravity,
// drive_radius, contact_distance, the clutch's τ_s, τ_k, c_a, mass (m1 = m2). The clutch's
// torques do not enter a locked orbit, nor does μ_k with stick-slip friction (the cone is μ_s's):
// along them a branch stands still and only its events move.
const std::vector<std::string>& continuation_parameters();
// Throws std::invalid_argument naming the allowed parameters.
double parameter_value(const OrbitProblem& pb, std::string_view name);
void set_parameter(OrbitProblem& pb, std::string_view name, double value);

struct BranchPoint {
  double lambda = 0.0;     // the parameter's value
  SteadyOrbit orbit;
  Stability stab;
  int unstable = 0;        // eigenvalues with Re λ > 0
  double tangent_lambda = 0.0;  // dλ/ds along the unit tangent (scaled)
};

enum class EventKind { Fold, BranchPoint, StabilityLoss, StabilityGain, Hopf, ConeExitUp, ConeExitDown, Slack };
std::string_view to_string(EventKind k);

struct BranchEvent {
  EventKind kind;
  double lambda = 0.0;     // where it happens
  SteadyOrbit orbit;       // the orbit there
  double frequency = 0.0;  // Hopf: |Im λ| of the crossing pair [rad/s]
  int after_point = 0;     // between points after_point and after_point + 1
  std::string note;
};

struct Branch {
  std::string parameter;
  Closure closure = Closure::Stuck;
  std::vector<BranchPoint> points;
  std::vector<BranchEvent> events;
  std::string stop_reason;
};

struct ContinuationOptions {
  double lambda_min = 0.0, lambda_max = 1e300;  // stop when λ leaves this interval
  int direction = +1;         // initial sign of dλ
  double step = 0.01;         // initial arclength step (scaled units)
  double step_min = 1e-7, step_max = 0.02;
  int max_points = 4000;
  bool stability = true;      // eigenvalues at each point (needed for stability events)
  // Stop after the first point (kept, with the events before it) for which this is true.
  std::function<bool(const BranchPoint&)> stop_at;
};

// Continue from X0 (an orbit of pb, or close to one) in `parameter`.
Branch continue_branch(OrbitProblem pb, const Vec9& X0, const std::string& parameter,
                       const ContinuationOptions& opt = {});

}  // namespace ajx::orbits
