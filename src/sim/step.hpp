// The smooth flow between switches: the integrator's options for a run, where a segment
// must stop, and the projection onto the constraints after each accepted step.
#pragma once
#include "numerics/integrate.hpp"
#include "numerics/stepper.hpp"
#include "sim/run_context.hpp"

namespace ajx::sim {

// The run's integrator options: a fixed step is neither bounded by the guards' rates nor
// sampled inside; an adaptive one, with opt.guard_step_bound, is bounded by guard_step_bound.
numerics::IntegrateOptions step_options(const RunContext& ctx, const numerics::Stepper& stepper);

// The end of the segment starting at t: the next breakpoint of the schedule (ω̇ jumps there)
// before t_end, else t_end.
double segment_end(const physics::MotorSchedule& schedule, double t, double t_end);

// After an accepted step at (t, y): record the drift |C| of a taut mode and, past
// opt.projection_tol, project positions and velocities onto the constraints. True when y
// was changed.
bool project_after_step(RunContext& ctx, double t, numerics::Vec& y);

}  // namespace ajx::sim
