#include "sim/step.hpp"

#include "sim/step_bound.hpp"

#include <algorithm>

namespace ajx::sim {

using numerics::Vec;

numerics::IntegrateOptions step_options(const RunContext& ctx, const numerics::Stepper& stepper) {
  numerics::IntegrateOptions integ = ctx.opt.integ;
  // A fixed step is not bounded by Ω, and neither sampled inside (as before the samples: the
  // step is the user's; the h_bound call alone cost 4-6 % of an Euler or RK4 step).
  if (!stepper.adaptive()) integ.event_samples = 0;
  if (ctx.opt.guard_step_bound)
    integ.h_bound = [&ctx, k = integ.event_samples](double t, const Vec& y) {
      return guard_step_bound(ctx.model.p, ctx.top_at(t, y), y, k);
    };
  return integ;
}

double segment_end(const physics::MotorSchedule& schedule, double t, double t_end) {
  double t_stop = t_end;
  for (double tb : schedule.breakpoints())
    if (tb > t * (1 + 1e-15) + 1e-15 && tb < t_stop) t_stop = tb;
  return t_stop;
}

bool project_after_step(RunContext& ctx, double t, Vec& y) {
  const Contact& contact = ctx.contact();
  if (contact.mode == physics::Mode::Slack) return false;
  const physics::TopKinematics top = ctx.top_at(t, y);
  const physics::Drift drift = physics::constraint_drift(ctx.model, contact, top, y);
  ctx.sum.max_drift = std::max(ctx.sum.max_drift, drift.position);
  if (drift.position <= ctx.opt.projection_tol && drift.velocity <= ctx.opt.projection_tol) return false;
  physics::project_positions(ctx.model, contact, top, y);
  physics::project_velocities(ctx.model, contact, top, y);
  ++ctx.sum.projections;
  return true;
}

}  // namespace ajx::sim
