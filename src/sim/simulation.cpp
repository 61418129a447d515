#include "sim/simulation.hpp"

#include "physics/rotating_axes.hpp"
#include "physics/tie.hpp"
#include "sim/chatter.hpp"
#include "sim/event_location.hpp"
#include "sim/mode_switches.hpp"
#include "sim/run_context.hpp"
#include "sim/sampling.hpp"
#include "sim/step.hpp"
#include "sim/violation_watches.hpp"

#include <cmath>
#include <fmt/format.h>
#include <stdexcept>

namespace ajx::sim {

using numerics::Vec;
using physics::Vec3;

Simulation::Simulation(const physics::Model& model, const physics::MotorSchedule& schedule,
                       RunOptions opt)
    : model_(model), schedule_(schedule), opt_(std::move(opt)) {
  // R is the model's parameter; the schedule carries it so that the top is never paired by hand.
  if (schedule.radius() != model.p.drive_radius)
    throw std::invalid_argument("Simulation: the motor schedule's drive radius is not the model's drive_radius");
}

// The loop of a run over its stages: segments of smooth flow between the schedule's
// breakpoints (sim/step.hpp) stopped by the mode's guards (sim/event_location.hpp); at a
// stop, a watch's crossing (sim/violation_watches.hpp) or a mode switch
// (sim/mode_switches.hpp) counted for chatter (sim/chatter.hpp); every accepted step
// observed for samples (sim/sampling.hpp).
RunSummary Simulation::run(State& s, double t_end, double sample_dt, const SampleObserver& on_sample,
                           double sample_origin) {
  auto stepper = numerics::make_stepper(opt_.method);
  RunSummary sum;
  const State begin = s;
  RunContext ctx{model_, schedule_, opt_, RunAxes::choose(model_, schedule_, opt_.axes, s), s, sum, 0.0,
                 model_.layers.restitution};
  numerics::IntegrateOptions integ = step_options(ctx, *stepper);
  const numerics::System f = ctx.axes.system(s.contact);
  GuardEvents guards(ctx);
  ViolationWatches watches(ctx);
  ChatterDetector chatter(ctx);
  ModeSwitches switches(ctx);
  // s.y is rotated into the integrator's axes here and back at the end.
  if (ctx.axes.rotating) physics::rotate_about_z(s.y, -ctx.axes.angle(s.t));
  Sampler sampler(ctx, t_end, sample_dt, on_sample, sample_origin);
  const auto observe = [&](const numerics::StepView& step) { return sampler.observe(step); };
  const auto post_step = [&](double t, Vec& y) {
    watches.follow(t, y);
    return project_after_step(ctx, t, y);
  };

  long n_events = 0;
  Vec last_good = s.y;
  // A law with no solution (the point contact jammed) ends the run with its reason.
  try {
    switches.resolve_now();
    sampler.start();
    while (s.t < t_end && sum.failure.empty()) {
      const double t_stop = segment_end(schedule_, s.t, t_end);  // ω̇ jumps at breakpoints
      guards.arm();
      watches.check_at_start(guards.specs());
      last_good = s.y;
      const numerics::IntegrateResult r =
          numerics::integrate(f, *stepper, s.t, s.y, t_stop, guards.events(), observe, post_step, integ);
      sum.steps += r.steps;
      sum.rejected += r.rejected;
      s.t = r.t;
      if (r.h_next > 0) integ.h_init = r.h_next;
      sum.status = r.status;

      if (r.status == numerics::IntegrateStatus::Reached) {
        switches.resolve_now();  // a new segment: ä jumps with ω̇, so the cones are checked again
        continue;
      }
      if (r.status != numerics::IntegrateStatus::Event) {
        sum.failure = fmt::format("integration failed at t = {:.6f} s: {}", s.t, numerics::to_string(r.status));
        break;
      }
      if (++n_events > opt_.max_events) {
        sum.failure = fmt::format("event bound {} hit at t = {:.6f} s", opt_.max_events, s.t);
        break;
      }
      const physics::Guard g = guards.kind(r.event_index);
      if (physics::is_watch(g)) {
        watches.on_crossing(g);  // the mode goes on
        continue;
      }
      watches.before_switch(g);
      switches.on_event(g);
      if (!sum.failure.empty()) break;
      chatter.record_switch();
      switches.resolve_now();
      if (!sum.failure.empty()) break;
    }
  } catch (const std::domain_error& e) {
    s.y = last_good;
    sum.failure = fmt::format("the friction law failed after t = {:.6f} s: {}", s.t, e.what());
  }
  if (ctx.axes.rotating) physics::rotate_about_z(s.y, ctx.axes.angle(s.t));
  if (sum.failure.empty()) sum.status = numerics::IntegrateStatus::Reached;
  sum.violations = watches.violations();
  sum.t_end = s.t;
  sum.rhs_evals = stepper->rhs_evals();
  sum.energy = physics::energy_balance(model_.p, begin, s);
  sampler.finish();
  return sum;
}

State hanging_at_rest(const physics::Model& model, const physics::MotorSchedule& schedule, double t0) {
  const physics::Parameters& p = model.p;
  const physics::TopKinematics top = schedule.top(t0);
  State s;
  s.t = t0;
  s.contact = {Mode::BottomStop, 0, 0.0};
  s.y.setZero(physics::state_dim(model));
  if (physics::has_tie(s.y)) physics::hold_tie(schedule, t0, 0.0, s.y);
  s.y.segment<3>(physics::idx::r1) = top.a - (p.string_length - p.contact_distance) * Vec3::UnitZ();
  s.y.segment<3>(physics::idx::r2) = top.a - p.string_length * Vec3::UnitZ();
  return s;
}

State explicit_state(const physics::Model& model, const physics::MotorSchedule& schedule,
                     const Vec3& r1, const Vec3& r2, const Vec3& v1, const Vec3& v2, Mode mode,
                     double t0, double tol_length, double tie_slip_rate) {
  const physics::Parameters& p = model.p;
  const physics::TopKinematics top = schedule.top(t0);
  State s;
  s.t = t0;
  s.contact = {mode, 0, mode == Mode::Stuck ? (r1 - top.a).norm() : 0.0};
  s.y.setZero(physics::state_dim(model));
  if (physics::has_tie(s.y)) physics::hold_tie(schedule, t0, 0.0, s.y);
  if (physics::has_tie(s.y) && std::isfinite(tie_slip_rate)) {
    // Slipping: the clutch torque acts in the sense σ = sgn(ω_m − χ̇) (physics/tie.hpp).
    s.y(physics::idx::chi_dot) = tie_slip_rate;
    const double slip = top.omega - tie_slip_rate;
    s.contact.tie = {true, slip > 0.0 ? +1 : (slip < 0.0 ? -1 : 0), 0.0};
  }
  s.y.segment<3>(physics::idx::r1) = r1;
  s.y.segment<3>(physics::idx::r2) = r2;
  s.y.segment<3>(physics::idx::v1) = v1;
  s.y.segment<3>(physics::idx::v2) = v2;
  const double L1 = (r1 - top.a).norm(), L2 = (r2 - r1).norm();
  if (mode == Mode::Slack && L1 + L2 > p.string_length + tol_length)
    throw std::invalid_argument(fmt::format(
        "initial positions give L1 + L2 = {:.9g} m, longer than the string l = {:.9g} m", L1 + L2, p.string_length));
  if (mode != Mode::Slack && std::abs(L1 + L2 - p.string_length) > tol_length)
    throw std::invalid_argument(fmt::format(
        "initial positions give L1 + L2 = {:.9g} m, not the string length l = {:.9g} m (tolerance {:g} m)",
        L1 + L2, p.string_length, tol_length));
  if (L2 < p.contact_distance - tol_length)
    throw std::invalid_argument(fmt::format(
        "initial positions put the bead below the bottom stop: L2 = {:.9g} m < d = {:.9g} m", L2,
        p.contact_distance));
  // A slipping tie moves at χ̇, not ω_m: the velocities are made consistent with its top.
  const physics::TopKinematics start = physics::top_kinematics(model, schedule, s.contact, t0, s.y);
  physics::project_positions(model, s.contact, start, s.y);
  physics::project_velocities(model, s.contact, start, s.y);
  return s;
}

}  // namespace ajx::sim
