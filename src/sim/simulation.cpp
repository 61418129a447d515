#include "sim/simulation.hpp"

#include "physics/mode_transitions.hpp"
#include "physics/rotating_axes.hpp"
#include "physics/tie.hpp"
#include "sim/step_bound.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <stdexcept>
#include <vector>

namespace ajx::sim {

using numerics::Vec;
using physics::idx::dim;
using physics::Model;
using physics::Vec3;

namespace {

// Unwrapped azimuth of a point about the motor axis, advanced in small increments. The
// increment is measured in a frame that turned by dbeta against these axes since the last
// point (where it is smaller): Δθ = ∠(last, Rz(−dbeta) now) + dbeta.
struct Azimuth {
  double theta = 0.0;
  Eigen::Vector2d last = Eigen::Vector2d::Zero();
  void reset(const Vec3& r) { theta = 0.0; last = r.head<2>(); }
  void advance(const Vec3& r, double dbeta = 0.0) {
    const Eigen::Vector2d now = r.head<2>();
    Eigen::Vector2d seen = now;
    if (dbeta != 0.0) {
      const double c = std::cos(dbeta), s = std::sin(dbeta);
      seen = Eigen::Vector2d(c * now.x() + s * now.y(), -s * now.x() + c * now.y());
    }
    const double cross = last.x() * seen.y() - last.y() * seen.x();
    theta += std::atan2(cross, last.dot(seen)) + dbeta;
    last = now;
  }
};

}  // namespace

Simulation::Simulation(const physics::Model& model, const physics::MotorSchedule& schedule,
                       RunOptions opt)
    : model_(model), schedule_(schedule), opt_(std::move(opt)) {}

RunSummary Simulation::run(State& s, double t_end, double sample_dt, const SampleObserver& on_sample,
                           double sample_origin) {
  using physics::Guard;
  const physics::Parameters& p = model_.p;
  const physics::Layers& layers = model_.layers;
  const double R = p.drive_radius;
  auto stepper = numerics::make_stepper(opt_.method);
  RunSummary sum;
  const State begin = s;
  Contact& contact = s.contact;
  numerics::IntegrateOptions integ = opt_.integ;
  // In rotating axes every physics function takes the top at φ = 0 and the rotated state y'
  // (they are invariant under rotations about z); s.y is rotated in here and back at the end.
  // A tie that may slip on the rod (physics/tie.hpp) is not at φ: with it the run stays in the lab.
  const bool rotating =
      !layers.tie_clutch &&
      (opt_.axes == Axes::Rotating ||
       (opt_.axes == Axes::Auto && corotates(physics::top_kinematics(model_, schedule_, contact, s.t, s.y), s.y)));
  // The top of the string: the motor's a(t), or the tie's, for the bead's mode c (a slipping
  // tie's χ̈ depends on the string's pull in that mode).
  const auto top_for = [&](const Contact& c, double t, const Vec& y) {
    return rotating ? physics::top_in_rotating_axes(schedule_, R, t)
                    : physics::top_kinematics(model_, schedule_, c, t, y);
  };
  const auto top_at = [&](double t, const Vec& y) { return top_for(contact, t, y); };
  // The same for physics::settle, at the present state s (which it may be projecting).
  const physics::TopFor top_now = [&](const Contact& c) { return top_for(c, s.t, s.y); };
  // A fixed step is not bounded by Ω, and neither sampled inside (as before the samples: the
  // step is the user's; the h_bound call alone cost 4-6 % of an Euler or RK4 step).
  if (!stepper->adaptive()) integ.event_samples = 0;
  if (opt_.guard_step_bound)
    integ.h_bound = [&, k = integ.event_samples](double t, const Vec& y) {
      return guard_step_bound(p, top_at(t, y), y, k);
    };
  // The angle from the integrator's axes to the lab's: φ(t), or 0 in the lab.
  const auto axes_angle = [&](double t) {
    if (!rotating) return 0.0;
    double phi, w, wd;
    schedule_.phase(t, phi, w, wd);
    return phi;
  };

  const numerics::System f = rotating ? numerics::System([&](double t, const Vec& y, Vec& dydt) {
    physics::rhs_in_rotating_axes(model_, schedule_, contact, t, y, dydt);
  })
                                      : numerics::System([&](double t, const Vec& y, Vec& dydt) {
    physics::rhs(model_, schedule_, contact, t, y, dydt);
  });

  // Chatter resolution: after a storm of switches the force guards (cone margins, tensions)
  // switch only past a band of `band` newtons, and impacts become plastic. Deterministic:
  // the band starts at 1e-9 (m1 + m2) g and grows tenfold per further storm.
  double band = 0.0;
  double restitution = layers.restitution;
  const double weight = (p.bead_mass + p.ball_mass) * p.gravity;
  std::vector<double> recent_switches;

  // Violations of omitted layers: entered when the watch crosses into its bad side; the worst
  // excess is followed at every accepted step while inside.
  struct Watch {
    Violation v;
    bool inside = false;
  };
  std::vector<std::pair<Guard, Watch>> watches;
  const auto watch = [&](Guard g) -> Watch& {
    for (auto& [k, w] : watches)
      if (k == g) return w;
    Watch w;
    w.v.what = std::string(physics::to_string(g));
    w.v.unit = g == Guard::WatchTension ? "N" : (g == Guard::WatchStick ? "N of cone margin" : "m");
    watches.emplace_back(g, w);
    return watches.back().second;
  };
  const auto enter_violation = [&](Guard g, double t, double excess) {
    Watch& w = watch(g);
    if (w.v.count++ == 0) w.v.first_time = t;
    w.v.worst = std::max(w.v.worst, excess);
  };
  // The cone margin a stuck bead would have here: > 0 means a model with stick would hold it.
  const auto stick_margin = [&](double t, const Vec& y) {
    return physics::static_cone_margin(model_, [&](const Contact& c) { return top_for(c, t, y); }, contact, y);
  };
  const auto follow_watches = [&](double t, const Vec& y) {
    for (auto& [g, w] : watches) {
      if (!w.inside || g == Guard::WatchStick) continue;
      w.v.worst = std::max(w.v.worst, -physics::guard_value(g, model_, top_at(t, y), contact, y));
    }
  };

  // The force guards of a mode (two cone margins, the tensions) share one evaluation at (t, y).
  struct {
    bool valid = false;
    double t = 0.0;
    Vec y;
    physics::Dynamics d;
    const physics::Dynamics& at(double tq, const physics::TopKinematics& top, const Vec& yq, const Model& m,
                                const Contact& c) {
      if (!(valid && tq == t && yq.size() == y.size() && (yq.array() == y.array()).all())) {
        d = physics::evaluate(m, top, c, yq);
        t = tq;
        y = yq;
        valid = true;
      }
      return d;
    }
  } guard_store;
  const auto guard_cache_at = [&](double t, const physics::TopKinematics& top, const Vec& y) -> const physics::Dynamics& {
    return guard_store.at(t, top, y, model_, contact);
  };
  // The guards of the current mode as events; force guards are shifted by the band.
  std::vector<physics::GuardSpec> specs;
  std::vector<numerics::Event> events;
  const auto arm = [&] {
    specs = physics::guards(model_, contact);
    // A violation already present at a segment start is never seen as a crossing: check here.
    for (const auto& g : specs) {
      if (!physics::is_watch(g.kind) || g.kind == Guard::WatchStick) continue;
      const double value = physics::guard_value(g.kind, model_, top_at(s.t, s.y), contact, s.y);
      Watch& w = watch(g.kind);
      if (value < 0.0 && !w.inside) enter_violation(g.kind, s.t, -value);
      w.inside = value < 0.0;
    }
    events.clear();
    guard_store.valid = false;
    for (const auto& g : specs) {
      const bool force = g.kind == Guard::SlipUp || g.kind == Guard::SlipDown || g.kind == Guard::Slacken;
      events.push_back({[&, kind = g.kind, force](double t, const Vec& y) {
                          const physics::TopKinematics top = top_at(t, y);
                          if (!physics::needs_dynamics(kind)) return physics::guard_value(kind, model_, top, contact, y);
                          return physics::guard_value(kind, model_, top, contact, y, guard_cache_at(t, top, y)) +
                                 (force ? band : 0.0);
                        },
                        g.direction});
    }
  };


  if (rotating) physics::rotate_about_z(s.y, -axes_angle(s.t));
  // Samples on the grid origin + k sample_dt, and the azimuths for ω_ball (in the integrator's
  // axes; the lab azimuth adds the axes' angle φ).
  const double t_start = s.t;
  const double origin = std::isfinite(sample_origin) ? sample_origin : t_start;
  long next_sample = sample_dt > 0.0 ? long(std::ceil((t_start - origin) / sample_dt - 1e-9)) : 0;
  Vec ybuf(s.y.size());
  Azimuth az1, az2;
  az1.reset(s.y.segment<3>(physics::idx::r1));
  az2.reset(s.y.segment<3>(physics::idx::r2));
  const double window = std::min(opt_.omega_window, 0.5 * (t_end - t_start));
  const double t_window = t_end - window;
  double theta_window = 0.0;  // (θ1 + θ2)/2 at t_window
  bool window_started = t_window <= t_start;
  sum.min_tension = std::numeric_limits<double>::infinity();
  sum.min_friction_power = std::numeric_limits<double>::infinity();

  Vec ylab(s.y.size());
  // Samples are handed out in the lab.
  const auto emit = [&](double t, const Vec& y) {
    ylab = y;
    if (rotating) physics::rotate_about_z(ylab, axes_angle(t));
    const physics::TopKinematics top = physics::top_kinematics(model_, schedule_, contact, t, ylab);
    const physics::Dynamics dyn = physics::evaluate(model_, top, contact, ylab);
    if (opt_.run_statistics) {
      sum.max_sample_drift =
          std::max(sum.max_sample_drift, physics::constraint_drift(model_, contact, top, ylab).position);
      if (contact.mode != Mode::Slack) sum.min_tension = std::min({sum.min_tension, dyn.T1, dyn.T2});
      sum.min_friction_power = std::min(sum.min_friction_power, dyn.friction_power);
    }
    if (on_sample) on_sample(Sample{t, contact, ylab, dyn, top, s.impact_loss});
  };
  // The larger |dθ/dt| of the two balls about the axis, in the integrator's axes:
  // θ̇ = (x w_y − y w_x)/(x² + y²), w the velocity seen in the axes (v − Ω×r when rotating).
  // and in the other frame (the lab's θ̇ = θ̇' + ω, or the rotating θ̇' = θ̇ − ω).
  struct Rates {
    double own = 0.0, other = 0.0;
  };
  const auto azimuth_rates = [&](double t, const Vec& y) {
    double phi, w, wd;
    schedule_.phase(t, phi, w, wd);
    Rates r;
    for (int b : {physics::idx::r1, physics::idx::r2}) {
      const double x = y(b), yy = y(b + 1), vx = y(b + 6), vy = y(b + 7);
      const double rho2 = x * x + yy * yy;
      const double lab_rate = rho2 > 0.0 ? (x * vy - yy * vx) / rho2 : 0.0;  // v is the lab velocity
      const double rot_rate = lab_rate - w;
      r.own = std::max(r.own, std::abs(rotating ? rot_rate : lab_rate));
      r.other = std::max(r.other, std::abs(rotating ? lab_rate : rot_rate));
    }
    return r;
  };
  Vec yend(dim);
  Rates rate_start = azimuth_rates(s.t, s.y);
  const auto observe = [&](const numerics::StepView& step) {
    // Samples in (t0, t1] (the first one at t_start is emitted before integrating).
    while (sample_dt > 0.0) {
      const double ts = origin + double(next_sample) * sample_dt;
      if (ts > step.t1() || ts > t_end) break;
      if (ts >= step.t0()) {
        step.at(ts, ybuf);
        emit(ts, ybuf);
      }
      ++next_sample;
    }
    if (!opt_.run_statistics) return true;
    // Azimuths in increments small enough to unwrap (< 0.25 rad, with the rates of both ends of
    // the step). One increment takes the end state and leaves the interpolant alone (DOP853's
    // costs 3 extra evaluations per step).
    // The increments are measured in the integrator's axes or in the other frame (the lab or
    // the rotating one, turned by β = ∓φ against them), whichever the balls turn slower in.
    step.end(yend);
    const Rates rate_end = azimuth_rates(step.t1(), yend);
    const double dt_step = std::abs(step.t1() - step.t0());
    const double own = std::max(rate_start.own, rate_end.own), other = std::max(rate_start.other, rate_end.other);
    const bool use_other = other < own;
    const int n = 1 + int(std::min(1e3, std::min(own, other) * dt_step / 0.25));
    rate_start = rate_end;
    // β(t): the other frame's angle against the integrator's axes (−φ from rotating axes to the
    // lab, +φ from the lab to rotating axes).
    const auto beta = [&](double t) {
      if (!use_other) return 0.0;
      double phi, w, wd;
      schedule_.phase(t, phi, w, wd);
      return rotating ? -phi : phi;
    };
    double t_prev = step.t0(), beta_prev = beta(t_prev);
    for (int k = 1; k <= n; ++k) {
      const double t = step.t0() + (step.t1() - step.t0()) * k / n;
      const double beta_t = beta(t);
      if (k == n)
        ybuf = yend;
      else
        step.at(t, ybuf);
      if (!window_started && t >= t_window) {
        Vec yw(s.y.size());
        step.at(t_window, yw);
        const double dbw = beta(t_window) - beta_prev;
        Azimuth a1 = az1, a2 = az2;
        a1.advance(yw.segment<3>(physics::idx::r1), dbw);
        a2.advance(yw.segment<3>(physics::idx::r2), dbw);
        theta_window = 0.5 * (a1.theta + a2.theta);
        window_started = true;
      }
      az1.advance(ybuf.segment<3>(physics::idx::r1), beta_t - beta_prev);
      az2.advance(ybuf.segment<3>(physics::idx::r2), beta_t - beta_prev);
      t_prev = t;
      beta_prev = beta_t;
    }
    return true;
  };
  const auto post_step = [&](double t, Vec& y) {
    follow_watches(t, y);
    if (contact.mode == Mode::Slack) return false;
    const physics::TopKinematics top = top_at(t, y);
    const physics::Drift drift = physics::constraint_drift(model_, contact, top, y);
    sum.max_drift = std::max(sum.max_drift, drift.position);
    if (drift.position <= opt_.projection_tol && drift.velocity <= opt_.projection_tol) return false;
    physics::project_positions(model_, contact, top, y);
    physics::project_velocities(model_, contact, top, y);
    ++sum.projections;
    return true;
  };
  // Enter a taut mode: snap onto its constraints with an impulse (restitution e; zero work for
  // a consistent switch), then let the cones and ṡ decide the final mode.
  const auto enter = [&](Contact next, double e) {
    next.tie = contact.tie;  // the bead's mode changes, the tie's state stays
    const physics::TopKinematics top = top_for(next, s.t, s.y);
    // The string goes slack from taut: start the flight on L1 + L2 = l (to rounding, not to the
    // step's drift), strictly on the slack side of the Taut guard (physics::taut_margin).
    if (next.mode == Mode::Slack && contact.mode != Mode::Slack)
      physics::project_positions(model_, contact, top_for(contact, s.t, s.y), s.y);
    if (next.mode != Mode::Slack) {
      physics::project_positions(model_, next, top, s.y);
      const physics::ProjectionEnergy pe = physics::project_velocities(model_, next, top, s.y, e);
      s.y(physics::idx::motor_work) += pe.motor_work;
      s.impact_loss += pe.dissipated;
      next = physics::settle(model_, top_now, next, s.y, band);
    }
    if (next.mode == Mode::Stuck && contact.mode != Mode::Stuck && sum.sticks++ == 0) sum.first_stick = s.t;
    if (next.mode == Mode::Slack && contact.mode != Mode::Slack) ++sum.slack_phases;
    if (next.mode != contact.mode || next.sigma != contact.sigma) ++sum.mode_switches;
    contact = next;
  };
  const auto impact_account = [&](const physics::ProjectionEnergy& pe) {
    s.y(physics::idx::motor_work) += pe.motor_work;
    s.impact_loss += pe.dissipated;
    ++sum.impacts;
  };
  const double on_surface = 1e-10 * p.string_length;  // a state this close sits on a surface [m]
  // The bead meets a stop (the bottom ball, or the top). In free flight: a plastic collision,
  // and the string stays slack. On a taut string: a plastic landing onto the two-link set.
  const auto meet_stop = [&](bool bottom) {
    if (contact.mode == Mode::Slack) {
      impact_account(bottom ? physics::collide_with_ball(model_, s.y, 0.0)
                            : physics::collide_with_top(model_, top_at(s.t, s.y), s.y, 0.0));
      return;
    }
    const double w0 = s.y(physics::idx::motor_work), l0 = s.impact_loss;
    enter({bottom ? Mode::BottomStop : Mode::TopStop, 0, 0.0}, 0.0);
    if (s.y(physics::idx::motor_work) != w0 || s.impact_loss != l0) ++sum.impacts;
  };
  // The slack string pulls taut: one simultaneous impact with restitution e onto the active set,
  // L1 + L2 = l, together with a stop the bead touches at that instant (the bead resting on the
  // ball moves with it). With e > 0 the string rebounds and stays slack; with e = 0 it is taut.
  const auto pull_taut = [&] {
    const physics::TopKinematics top = top_at(s.t, s.y);
    const Vec3 r1 = s.y.segment<3>(physics::idx::r1), r2 = s.y.segment<3>(physics::idx::r2);
    Contact set{Mode::Sliding, 0, 0.0};
    if (layers.bottom_stop && (r2 - r1).norm() - p.contact_distance <= on_surface)
      set.mode = Mode::BottomStop;
    else if (layers.top_stop && (r1 - top.a).norm() - p.top_stop <= on_surface)
      set.mode = Mode::TopStop;
    // Bounces shrink geometrically (a Zeno sequence): below the rest speed the impact is plastic,
    // before the flights become shorter than any event can resolve.
    const physics::Geometry g = physics::geometry(top, r1, r2, s.y.segment<3>(physics::idx::v1),
                                                  s.y.segment<3>(physics::idx::v2));
    const double approach = g.L1_dot + g.L2_dot;
    if (restitution > 0.0 && approach > opt_.rest_speed) {
      // The rebound flight starts on L1 + L2 = l, on the slack side of the Taut guard (the event
      // was located δ_s beyond it, physics::taut_margin).
      physics::project_positions(model_, set, top, s.y);
      impact_account(physics::project_velocities(model_, set, top, s.y, restitution));
    } else {
      const double l0 = s.impact_loss;
      enter(set, 0.0);
      if (s.impact_loss != l0) ++sum.impacts;
    }
  };
  // A storm of switches in a short time: widen the band, make impacts plastic.
  const auto check_chatter = [&] {
    recent_switches.push_back(s.t);
    if (recent_switches.size() < std::size_t(opt_.chatter_switches)) return;
    const double span = recent_switches.back() - recent_switches.front();
    recent_switches.erase(recent_switches.begin());
    if (span > opt_.chatter_window) return;
    if (sum.chatter++ == 0) sum.first_chatter = s.t;
    band = band == 0.0 ? 1e-9 * weight : std::min(10.0 * band, 1e-3 * weight);
    restitution = 0.0;
    recent_switches.clear();
  };

  // The tie (physics/tie.hpp). It slips from where it is held, with χ and χ̇ continuous.
  const auto slip_tie = [&](int sigma) {
    const physics::TopKinematics held = top_at(s.t, s.y);
    s.y(physics::idx::chi) = held.phi;
    s.y(physics::idx::chi_dot) = held.omega;
    contact.tie = {true, sigma, 0.0};
    if (sum.tie_slips++ == 0) sum.first_tie_slip = s.t;
    ++sum.mode_switches;
  };
  // The slipping tie has caught the rod: held at the present offset if the torque it needs
  // is within τ_s, else it slips on in the sense that torque asks.
  const auto lock_tie = [&] {
    double phi, omega, omega_dot;
    schedule_.phase(s.t, phi, omega, omega_dot);
    Contact held = contact;
    held.tie = {false, 0, s.y(physics::idx::chi) - phi};
    const double tau = physics::tie_torque_needed(model_, top_for(held, s.t, s.y), held, s.y);
    ++sum.mode_switches;
    if (std::abs(tau) <= p.tie_static_torque + band) {
      contact.tie = held.tie;
      physics::hold_tie(schedule_, s.t, held.tie.offset, s.y);
    } else {
      contact.tie = {true, tau > 0.0 ? +1 : -1, 0.0};
    }
  };
  // A held tie whose torque is already past τ_s (at the start, or after ä jumped) slips now.
  const auto tie_slips_now = [&] {
    if (!layers.tie_clutch || contact.tie.slip) return false;
    const double tau = physics::tie_torque_needed(model_, top_at(s.t, s.y), contact, s.y);
    if (std::abs(tau) <= p.tie_static_torque + band) return false;
    slip_tie(tau > 0.0 ? +1 : -1);
    return true;
  };

  // After an impact, and at every segment start, the state may sit on a guard's surface while
  // moving into its forbidden side, where no crossing is ever seen: act on it here. A taut
  // mode must also satisfy its cone (settle) and, with the slack layer, positive tensions.
  const auto resolve_now = [&] {
    for (int pass = 0; pass < 20; ++pass) {
      if (tie_slips_now()) continue;
      const physics::TopKinematics top = top_at(s.t, s.y);
      const physics::Geometry g =
          physics::geometry(top, s.y.segment<3>(physics::idx::r1), s.y.segment<3>(physics::idx::r2),
                            s.y.segment<3>(physics::idx::v1), s.y.segment<3>(physics::idx::v2));
      const bool free = contact.mode == Mode::Sliding || contact.mode == Mode::Slack;
      // A rate Li_dot = ui·wi computed from speeds |v| carries a roundoff of a few eps |v|; after
      // an impact's projection zeroed it, only that is left. Below 16 eps (|v1| + |v2| + |ȧ|)
      // a rate is zero: such a state touches the surface without moving into it (the guards
      // see where its acceleration takes it). Counting the roundoff as an approach made the
      // modes cycle (stop, leave, stop, ...) at one instant.
      const double still = 16.0 * std::numeric_limits<double>::epsilon() *
                           (s.y.segment<3>(physics::idx::v1).norm() + s.y.segment<3>(physics::idx::v2).norm() +
                            top.a_dot.norm());
      const bool into_ball = layers.bottom_stop && g.L2 - p.contact_distance <= on_surface && g.L2_dot < -still;
      const bool into_top = layers.top_stop && g.L1 - p.top_stop <= on_surface && g.L1_dot < -still;
      if (free && (into_ball || into_top)) {
        meet_stop(into_ball);
        continue;
      }
      if (contact.mode == Mode::Slack) {
        if (g.L1 + g.L2 - p.string_length >= -on_surface && g.L1_dot + g.L2_dot > still) {
          pull_taut();
          continue;
        }
        return;
      }
      const Contact settled = physics::settle(model_, top_now, contact, s.y, band);
      if (settled.mode != contact.mode || settled.sigma != contact.sigma) {
        enter(settled, 0.0);
        continue;
      }
      if (layers.slack) {
        const physics::Dynamics d = physics::evaluate(model_, top, contact, s.y);
        if (std::min(d.T1, d.T2) < -band) {
          enter({Mode::Slack, 0, 0.0}, 0.0);
          continue;
        }
      }
      return;
    }
    // Twenty changes at one instant and still not settled: the modes cycle, and no choice is
    // consistent there. Going on would integrate a mode whose own conditions fail.
    sum.failure = fmt::format("at t = {:.6f} s the contact modes did not settle after 20 changes at one instant "
                              "(last: {})", s.t, physics::to_string(contact.mode));
  };

  long n_events = 0;
  Vec last_good = s.y;
  // A law with no solution (the point contact jammed) ends the run with its reason.
  try {
    resolve_now();
    if (sample_dt > 0.0 && origin + double(next_sample) * sample_dt <= t_start) {
      emit(s.t, s.y);
      ++next_sample;
    }
    while (s.t < t_end && sum.failure.empty()) {
      // Stop on the schedule's breakpoints: ω̇ jumps there.
      double t_stop = t_end;
      for (double tb : schedule_.breakpoints())
        if (tb > s.t * (1 + 1e-15) + 1e-15 && tb < t_stop) t_stop = tb;

      arm();
      last_good = s.y;
      const numerics::IntegrateResult r =
          numerics::integrate(f, *stepper, s.t, s.y, t_stop, events, observe, post_step, integ);
      sum.steps += r.steps;
      sum.rejected += r.rejected;
      s.t = r.t;
      if (r.h_next > 0) integ.h_init = r.h_next;
      sum.status = r.status;

      if (r.status == numerics::IntegrateStatus::Reached) {
        resolve_now();  // a new segment: ä jumps with ω̇, so the cones are checked again
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
      const Guard g = specs[std::size_t(r.event_index)].kind;
      const physics::TopKinematics top = top_at(s.t, s.y);
      if (physics::is_watch(g)) {
        // Entering or leaving an omitted layer's bad side; the mode goes on.
        const double value = physics::guard_value(g, model_, top, contact, s.y);
        Watch& w = watch(g);
        if (g == Guard::WatchStick) {
          const double margin = stick_margin(s.t, s.y);
          if (margin > 0.0) enter_violation(g, s.t, margin);
        } else if (!w.inside && value <= 0.0) {
          w.inside = true;
          enter_violation(g, s.t, -value);
        } else {
          w.inside = false;
        }
        continue;
      }
      switch (g) {
        case Guard::LandBottom:
        case Guard::LandTop:
          meet_stop(g == Guard::LandBottom);
          break;
        case Guard::Rest:
          // The kinetic layer has no static coefficient: where μ_s would have held the bead,
          // its assumption failed (whether μ_k then holds it or lets it reverse).
          if (layers.friction == physics::Friction::Kinetic) {
            const double margin = stick_margin(s.t, s.y);
            if (margin > 0.0) enter_violation(Guard::WatchStick, s.t, margin);
          }
          {
            // The cone is judged on the held bead's forces at the top the held bead would give:
            // with a slipping tie, ä (through χ̈) depends on the bead's mode.
            enter(physics::at_rest(model_, top_now(physics::held_here(top, contact, s.y)), s.y, band), 0.0);
          }
          break;
        case Guard::SlipUp:
          enter({Mode::Sliding, -1, 0.0}, 0.0);
          break;
        case Guard::SlipDown:
          enter({Mode::Sliding, +1, 0.0}, 0.0);
          break;
        case Guard::Slacken:
          enter({Mode::Slack, 0, 0.0}, 0.0);
          break;
        case Guard::Taut:
          pull_taut();
          break;
        case Guard::TieSlipAhead:
        case Guard::TieSlipBehind:
          slip_tie(g == Guard::TieSlipAhead ? +1 : -1);
          break;
        case Guard::TieLock:
          lock_tie();
          break;
        case Guard::ReachBall:
        case Guard::ReachTop:
          sum.failure = fmt::format("at t = {:.6f} s {} (the {} layer is off): the equations are singular there",
                                    s.t, physics::to_string(g), g == Guard::ReachBall ? "bottom-stop" : "top-stop");
          break;
        default:
          break;
      }
      if (!sum.failure.empty()) break;
      check_chatter();
      resolve_now();
      if (!sum.failure.empty()) break;
    }
  } catch (const std::domain_error& e) {
    s.y = last_good;
    sum.failure = fmt::format("the friction law failed after t = {:.6f} s: {}", s.t, e.what());
  }
  double theta_axes_window = 0.0;  // the axes' angle at t_window
  if (window > 0 && window_started) theta_axes_window = axes_angle(std::max(t_window, t_start));
  if (rotating) physics::rotate_about_z(s.y, axes_angle(s.t));
  if (sum.failure.empty()) sum.status = numerics::IntegrateStatus::Reached;
  for (auto& [g, w] : watches) sum.violations.push_back(w.v);
  sum.t_end = s.t;
  sum.rhs_evals = stepper->rhs_evals();
  sum.energy = physics::energy_balance(p, begin, s);
  if (window > 0 && window_started)
    sum.omega_ball =
        (0.5 * (az1.theta + az2.theta) - theta_window + axes_angle(s.t) - theta_axes_window) / (s.t - t_window);
  if (!std::isfinite(sum.min_tension)) sum.min_tension = 0.0;
  if (!std::isfinite(sum.min_friction_power)) sum.min_friction_power = 0.0;
  if (!opt_.run_statistics) {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    sum.omega_ball = sum.min_tension = sum.min_friction_power = sum.max_sample_drift = nan;
  }
  return sum;
}

State hanging_at_rest(const physics::Model& model, const physics::MotorSchedule& schedule, double t0) {
  const physics::Parameters& p = model.p;
  const physics::TopKinematics top = schedule.top(p.drive_radius, t0);
  State s;
  s.t = t0;
  s.contact = {Mode::BottomStop, 0, 0.0};
  s.y.setZero(physics::state_dim(model));
  if (s.y.size() > dim) physics::hold_tie(schedule, t0, 0.0, s.y);
  s.y.segment<3>(physics::idx::r1) = top.a - (p.string_length - p.contact_distance) * Vec3::UnitZ();
  s.y.segment<3>(physics::idx::r2) = top.a - p.string_length * Vec3::UnitZ();
  return s;
}

State explicit_state(const physics::Model& model, const physics::MotorSchedule& schedule,
                     const Vec3& r1, const Vec3& r2, const Vec3& v1, const Vec3& v2, Mode mode,
                     double t0, double tol_length, double tie_slip_rate) {
  const physics::Parameters& p = model.p;
  const physics::TopKinematics top = schedule.top(p.drive_radius, t0);
  State s;
  s.t = t0;
  s.contact = {mode, 0, mode == Mode::Stuck ? (r1 - top.a).norm() : 0.0};
  s.y.setZero(physics::state_dim(model));
  if (s.y.size() > dim) physics::hold_tie(schedule, t0, 0.0, s.y);
  if (s.y.size() > dim && std::isfinite(tie_slip_rate)) {
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
