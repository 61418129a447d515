#include "sim/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <stdexcept>
#include <vector>

namespace ajx::sim {

using numerics::Vec;
using physics::idx::dim;
using physics::Vec3;

namespace {

// Unwrapped azimuth of a point about the motor axis, advanced in small increments.
struct Azimuth {
  double theta = 0.0;
  Eigen::Vector2d last = Eigen::Vector2d::Zero();
  void reset(const Vec3& r) { theta = 0.0; last = r.head<2>(); }
  void advance(const Vec3& r) {
    const Eigen::Vector2d now = r.head<2>();
    const double cross = last.x() * now.y() - last.y() * now.x();
    theta += std::atan2(cross, last.dot(now));
    last = now;
  }
};

}  // namespace

Simulation::Simulation(const physics::Model& model, const physics::MotorSchedule& schedule,
                       RunOptions opt)
    : model_(model), schedule_(schedule), opt_(std::move(opt)) {}

namespace {

// The mode the bead enters when ṡ = 0 (a reversal while sliding, or a start at rest on the
// string): stuck while the two-link forces lie inside the friction cone, otherwise sliding in
// the direction of the violated bound.
Contact resolve_at_rest(const physics::Model& m, const physics::TopKinematics& top, const Vec& y) {
  const double s = (y.segment<3>(physics::idx::r1) - top.a).norm();
  if (m.layers.friction == physics::Friction::None) return {Mode::Sliding, 0, 0.0};
  const Contact stuck{Mode::Stuck, 0, s};
  const physics::ConeMargins c = physics::evaluate(m, top, stuck, y).margins;
  if (c.up >= 0.0 && c.down >= 0.0) return stuck;
  return {Mode::Sliding, c.up < 0.0 ? -1 : +1, 0.0};
}

}  // namespace

RunSummary Simulation::run(State& s, double t_end, double sample_dt, const SampleObserver& on_sample) {
  const physics::Parameters& p = model_.p;
  const double R = p.drive_radius;
  const bool friction = model_.layers.friction != physics::Friction::None;
  auto stepper = numerics::make_stepper(opt_.method);
  RunSummary sum;
  const State begin = s;
  Contact& contact = s.contact;
  numerics::IntegrateOptions integ = opt_.integ;

  const numerics::System f = [&](double t, const Vec& y, Vec& dydt) {
    physics::rhs(model_, schedule_, contact, t, y, dydt);
  };

  // Events of each mode (all "falling through zero"):
  //  sliding:     L2 - d (the bead lands on the bottom ball); σ ṡ (the bead comes to rest on the string)
  //  bottom stop: T1 - κ_lo F2 (the lower segment pulls the bead off the ball)
  //  stuck:       T1 - κ_lo T2 (slips up), κ_hi T2 - T1 (slips down)
  const auto L2_minus_d = [&](double, const Vec& y) {
    return (y.segment<3>(physics::idx::r2) - y.segment<3>(physics::idx::r1)).norm() - p.contact_distance;
  };
  const auto sigma_sdot = [&](double t, const Vec& y) {
    const physics::TopKinematics top = schedule_.top(R, t);
    const Vec3 u1 = (y.segment<3>(physics::idx::r1) - top.a).normalized();
    return contact.sigma * u1.dot(y.segment<3>(physics::idx::v1) - top.a_dot);
  };
  const auto margin_up = [&](double t, const Vec& y) {
    return physics::evaluate(model_, schedule_.top(R, t), contact, y).margins.up;
  };
  const auto margin_down = [&](double t, const Vec& y) {
    return physics::evaluate(model_, schedule_.top(R, t), contact, y).margins.down;
  };
  std::vector<numerics::Event> sliding_events{{L2_minus_d, -1}};
  if (friction) sliding_events.push_back({sigma_sdot, -1});
  const std::vector<numerics::Event> stop_events{{margin_up, -1}};
  const std::vector<numerics::Event> stuck_events{{margin_up, -1}, {margin_down, -1}};

  // Samples on the grid s.t + k sample_dt, and the azimuths for ω_ball.
  const double t_start = s.t;
  long next_sample = 0;
  Vec ybuf(dim);
  Azimuth az1, az2;
  az1.reset(s.y.segment<3>(physics::idx::r1));
  az2.reset(s.y.segment<3>(physics::idx::r2));
  const double window = std::min(opt_.omega_window, 0.5 * (t_end - t_start));
  const double t_window = t_end - window;
  double theta_window = 0.0;  // (θ1 + θ2)/2 at t_window
  bool window_started = t_window <= t_start;
  sum.min_tension = std::numeric_limits<double>::infinity();
  sum.min_friction_power = std::numeric_limits<double>::infinity();

  const auto emit = [&](double t, const Vec& y) {
    const physics::TopKinematics top = schedule_.top(R, t);
    const physics::Dynamics dyn = physics::evaluate(model_, top, contact, y);
    sum.max_sample_drift =
        std::max(sum.max_sample_drift, physics::constraint_drift(model_, contact, top, y).position);
    sum.min_tension = std::min({sum.min_tension, dyn.T1, dyn.T2});
    sum.min_friction_power = std::min(sum.min_friction_power, dyn.friction_power);
    if (on_sample) on_sample(Sample{t, contact, y, dyn, top, s.impact_loss});
  };
  const auto observe = [&](const numerics::StepView& step) {
    // Samples in (t0, t1] (the first one at t_start is emitted before integrating).
    while (sample_dt > 0.0) {
      const double ts = t_start + double(next_sample) * sample_dt;
      if (ts > step.t1() || ts > t_end) break;
      if (ts >= step.t0()) {
        step.at(ts, ybuf);
        emit(ts, ybuf);
      }
      ++next_sample;
    }
    // Azimuths in increments small enough to unwrap (< 0.25 rad of motor phase).
    double phi0, phi1, w, wd;
    schedule_.phase(step.t0(), phi0, w, wd);
    schedule_.phase(step.t1(), phi1, w, wd);
    const int n = 1 + int(std::abs(phi1 - phi0) / 0.25);
    for (int k = 1; k <= n; ++k) {
      const double t = step.t0() + (step.t1() - step.t0()) * k / n;
      step.at(t, ybuf);
      if (!window_started && t >= t_window) {
        Vec yw(dim);
        step.at(t_window, yw);
        Azimuth a1 = az1, a2 = az2;
        a1.advance(yw.segment<3>(physics::idx::r1));
        a2.advance(yw.segment<3>(physics::idx::r2));
        theta_window = 0.5 * (a1.theta + a2.theta);
        window_started = true;
      }
      az1.advance(ybuf.segment<3>(physics::idx::r1));
      az2.advance(ybuf.segment<3>(physics::idx::r2));
    }
    return true;
  };
  const auto post_step = [&](double t, Vec& y) {
    const physics::TopKinematics top = schedule_.top(R, t);
    const physics::Drift drift = physics::constraint_drift(model_, contact, top, y);
    sum.max_drift = std::max(sum.max_drift, drift.position);
    if (drift.position <= opt_.projection_tol && drift.velocity <= opt_.projection_tol) return false;
    physics::project_positions(model_, contact, top, y);
    physics::project_velocities(model_, contact, top, y);
    ++sum.projections;
    return true;
  };
  // Enter a new mode: snap onto its constraints; the velocity jump is an impulse whose
  // Carnot loss and motor work enter the energy account (zero for a consistent switch).
  const auto enter = [&](const Contact& next) {
    const physics::TopKinematics top = schedule_.top(R, s.t);
    contact = next;
    physics::project_positions(model_, contact, top, s.y);
    const physics::ProjectionEnergy e = physics::project_velocities(model_, contact, top, s.y);
    s.y(physics::idx::motor_work) += e.motor_work;
    s.impact_loss += e.dissipated;
    ++sum.mode_switches;
    if (contact.mode == Mode::Stuck) {
      if (sum.sticks++ == 0) sum.first_stick = s.t;
    }
  };

  // A sliding start needs a direction: sgn ṡ, or the rest rule when ṡ = 0.
  if (contact.mode == Mode::Sliding && friction) {
    const physics::TopKinematics top = schedule_.top(R, s.t);
    const double sdot = physics::geometry(top, s.y.segment<3>(physics::idx::r1), s.y.segment<3>(physics::idx::r2),
                                          s.y.segment<3>(physics::idx::v1), s.y.segment<3>(physics::idx::v2))
                            .L1_dot;
    if (sdot != 0.0)
      contact.sigma = sdot > 0 ? +1 : -1;
    else
      contact = resolve_at_rest(model_, top, s.y);
  }

  long events = 0;
  Vec last_good = s.y;
  // A law with no solution (the point contact jammed) ends the run with its reason.
  try {
    if (sample_dt > 0.0) {
      emit(s.t, s.y);
      next_sample = 1;
    }
    while (s.t < t_end) {
      // Stop on the schedule's breakpoints: ω̇ jumps there.
      double t_stop = t_end;
      for (double tb : schedule_.breakpoints())
        if (tb > s.t * (1 + 1e-15) + 1e-15 && tb < t_stop) t_stop = tb;

      const auto& events_now = contact.mode == Mode::Sliding  ? sliding_events
                               : contact.mode == Mode::Stuck ? stuck_events
                                                             : stop_events;
      last_good = s.y;
      const numerics::IntegrateResult r =
          numerics::integrate(f, *stepper, s.t, s.y, t_stop, events_now, observe, post_step, integ);
      sum.steps += r.steps;
      sum.rejected += r.rejected;
      s.t = r.t;
      if (r.h_next > 0) integ.h_init = r.h_next;
      sum.status = r.status;

      if (r.status == numerics::IntegrateStatus::Reached) {
        stepper->reset();
        continue;
      }
      if (r.status != numerics::IntegrateStatus::Event) {
        sum.failure = fmt::format("integration failed at t = {:.6f} s: {}", s.t, numerics::to_string(r.status));
        break;
      }
      if (++events > opt_.max_events) {
        sum.failure = fmt::format("event bound {} hit at t = {:.6f} s", opt_.max_events, s.t);
        break;
      }
      const physics::TopKinematics top = schedule_.top(R, s.t);
      switch (contact.mode) {
        case Mode::Sliding:
          if (r.event_index == 0) {  // landing on the bottom ball: a plastic impact
            if (!model_.layers.bottom_stop) {
              sum.failure = fmt::format(
                  "the bead reached the bottom ball (L2 = d) at t = {:.6f} s but the bottom-stop layer is off", s.t);
              break;
            }
            enter({Mode::BottomStop, 0, 0.0});
            ++sum.impacts;
            // It rests only while the contact holds; otherwise it leaves at once.
            if (physics::evaluate(model_, top, contact, s.y).margins.up < 0.0) enter({Mode::Sliding, -1, 0.0});
          } else {  // ṡ = 0: stick, or slide on in the direction the forces push
            enter(resolve_at_rest(model_, top, s.y));
          }
          break;
        case Mode::Stuck:
          enter({Mode::Sliding, r.event_index == 0 ? -1 : +1, 0.0});
          break;
        case Mode::BottomStop:
          enter({Mode::Sliding, -1, 0.0});  // the bead climbs off the bottom ball
          break;
      }
      if (!sum.failure.empty()) break;
      stepper->reset();
    }
  } catch (const std::domain_error& e) {
    s.y = last_good;
    sum.failure = fmt::format("the friction law failed after t = {:.6f} s: {}", s.t, e.what());
  }
  if (sum.failure.empty()) sum.status = numerics::IntegrateStatus::Reached;
  sum.t_end = s.t;
  sum.rhs_evals = stepper->rhs_evals();
  sum.energy = physics::energy_balance(p, begin, s);
  if (window > 0 && window_started)
    sum.omega_ball = (0.5 * (az1.theta + az2.theta) - theta_window) / (s.t - t_window);
  if (!std::isfinite(sum.min_tension)) sum.min_tension = 0.0;
  if (!std::isfinite(sum.min_friction_power)) sum.min_friction_power = 0.0;
  return sum;
}

State hanging_at_rest(const physics::Model& model, const physics::MotorSchedule& schedule, double t0) {
  const physics::Parameters& p = model.p;
  const physics::TopKinematics top = schedule.top(p.drive_radius, t0);
  State s;
  s.t = t0;
  s.contact = {Mode::BottomStop, 0, 0.0};
  s.y.setZero(dim);
  s.y.segment<3>(physics::idx::r1) = top.a - (p.string_length - p.contact_distance) * Vec3::UnitZ();
  s.y.segment<3>(physics::idx::r2) = top.a - p.string_length * Vec3::UnitZ();
  return s;
}

State explicit_state(const physics::Model& model, const physics::MotorSchedule& schedule,
                     const Vec3& r1, const Vec3& r2, const Vec3& v1, const Vec3& v2, Mode mode,
                     double t0, double tol_length) {
  const physics::Parameters& p = model.p;
  const physics::TopKinematics top = schedule.top(p.drive_radius, t0);
  State s;
  s.t = t0;
  s.contact = {mode, 0, mode == Mode::Stuck ? (r1 - top.a).norm() : 0.0};
  s.y.setZero(dim);
  s.y.segment<3>(physics::idx::r1) = r1;
  s.y.segment<3>(physics::idx::r2) = r2;
  s.y.segment<3>(physics::idx::v1) = v1;
  s.y.segment<3>(physics::idx::v2) = v2;
  const double L1 = (r1 - top.a).norm(), L2 = (r2 - r1).norm();
  if (std::abs(L1 + L2 - p.string_length) > tol_length)
    throw std::invalid_argument(fmt::format(
        "initial positions give L1 + L2 = {:.9g} m, not the string length l = {:.9g} m (tolerance {:g} m)",
        L1 + L2, p.string_length, tol_length));
  if (L2 < p.contact_distance - tol_length)
    throw std::invalid_argument(fmt::format(
        "initial positions put the bead below the bottom stop: L2 = {:.9g} m < d = {:.9g} m", L2,
        p.contact_distance));
  physics::project_positions(model, s.contact, top, s.y);
  physics::project_velocities(model, s.contact, top, s.y);
  return s;
}

}  // namespace ajx::sim
