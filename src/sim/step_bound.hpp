// A bound on the integrator's step from the time scales of the guards (max_step = "auto").
// Events are found only as sign changes of a guard between step ends (numerics/integrate.hpp):
// an excursion of a guard past zero that begins and ends inside one step is not seen. A guard
// oscillating at rate Ω with amplitude A stays past a level A − δ for 2 arccos(1 − δ/A)/Ω; with
// steps h ≤ c/Ω every excursion deeper than δ = A (1 − cos(c/2)) outlasts a step and contains
// a step end. c = 1: any excursion deeper than 12 % of the guard's amplitude is seen.
// With k guard samples inside each step (numerics::IntegrateOptions::event_samples, on the step's
// interpolant) the same holds for the samples 1/Ω apart, and the step may be (k + 1)/Ω.
#pragma once
#include "numerics/vector.hpp"
#include "physics/drive.hpp"
#include "physics/mode_transitions.hpp"
#include "physics/model.hpp"

namespace ajx::sim {

// One radian of the fastest guard oscillation per step (the hidden depth 1 − cos ½ = 0.122 A).
inline constexpr double kRadiansPerStep = 1.0;

// The fastest rate Ω [rad/s] at which a guard can oscillate at the state y (layout of
// physics::idx, in either axes: only rotation invariants are used). The guards (L1, L2, the
// tensions, the cone margins, ṡ) are invariant under rotations about z: they change only as the
// shape of the chain top-bead-ball changes, through
// - the top turning about the balls: Ω_rel = max_i |ω − θ̇_i|, ω the top's rate and
//   θ̇_i = (x v_y − y v_x)/max(ρ_i², R²) the ball's azimuthal rate (within ρ < R of the axis the top,
//   seen from the ball, turns at about ω). A locked orbit has Ω_rel = 0, a fallen sub-millimetre
//   orbit at high ω_m nearly ω_m;
// - the swing of the links: Ω_swing = √(g_eff / min(L1, L2)), the pendulum rate of the shorter
//   link under the weight and the orbit's centrifugal load per unit mass,
//   g_eff = √(g² + (max_i θ̇_i² ρ_i)²).
// Ω = max(Ω_rel, Ω_swing). The guarantee is relative to each oscillation's own amplitude, so
// the rate is not weighted by how small that amplitude is (docs/reports/accuracy-and-speed.md,
// "A step bound from the guards' time scales": weighting would hide the string's pull in tests/step_bound_test.cpp).
double guard_rate(const physics::Parameters& p, const physics::TopKinematics& top, const numerics::Vec& y);

// h ≤ (event_samples + 1) kRadiansPerStep / Ω [s]: guard samples (the step's ends and its
// event_samples interior points) at most kRadiansPerStep / Ω apart.
double guard_step_bound(const physics::Parameters& p, const physics::TopKinematics& top, const numerics::Vec& y,
                        int event_samples = 0);

// Conservative advancement (numerics::Event::change_bound). The bound above is needed only where
// a guard can reach zero within the step. For the guards that are lengths of the chain,
// g = L − c with L = |p − q| (L2 = |r2 − r1|, L1 = |r1 − a|, and L1 + L2 for Taut), the triangle
// inequality gives |ΔL| ≤ |Δp| + |Δq| along the step, and on the integrator's interpolant
// |Δr_b| ≤ |(e_x, e_y, e_z)| of ball b when e_i ≥ |y_i(t) − y_i(t0)| (numerics::Stepper::
// dense_excursion). The top moves by |Δa| ≤ top_travel (see RunContext's use: 0 in the rotating
// axes, where a' = (R, 0, 0); R ∫|ω| dt ≤ R h max(|ω(t0)|, |ω(t1)|), ω being linear within a
// schedule segment, and at most the diameter 2R, in the lab). So
//   L2 guards: |Δg| ≤ |Δr1| + |Δr2|;   L1 guards: |Δg| ≤ |Δr1| + |Δa|;   Taut: |Δg| ≤ 2|Δr1| + |Δr2| + |Δa|,
// and a guard with |g(t0)| above its bound keeps its sign on the whole step: it needs neither the
// bound nor guard samples there. The force guards (tensions, cone margins), Rest (ṡ) and the
// tie's guards have no such bound: a mode with any of them keeps the bound at every step.
bool has_change_bound(physics::Guard g);
double guard_change_bound(physics::Guard g, double top_travel, const numerics::Vec& e);

// The rule of axes = "auto": the balls co-rotate with the motor when their horizontal speeds are
// smaller in the axes turning at ω (|v_h − ω ẑ×r|) than in the lab (|v_h|), summed over both
// balls; the integrator then follows the slower state. A locked orbit is at rest in the turning
// axes; a fallen sub-millimetre orbit at high ω_m is slower in the lab.
bool corotates(const physics::TopKinematics& top, const numerics::Vec& y);

}  // namespace ajx::sim
