#include "sim/mode_switches.hpp"

#include "physics/tie.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

namespace ajx::sim {

using numerics::Vec;
using physics::Guard;
using physics::Mode;
using physics::Vec3;

ModeSwitches::ModeSwitches(RunContext& ctx)
    : ctx_(ctx),
      top_now_([&ctx](const Contact& c) { return ctx.axes.top(c, ctx.s.t, ctx.s.y); }),
      on_surface_(1e-10 * ctx.model.p.string_length) {}

// Enter a taut mode: snap onto its constraints with an impulse (restitution e; zero work for
// a consistent switch), then let the cones and ṡ decide the final mode.
void ModeSwitches::enter(Contact next, double e) {
  State& s = ctx_.s;
  Contact& contact = s.contact;
  RunSummary& sum = ctx_.sum;
  next.tie = contact.tie;  // the bead's mode changes, the tie's state stays
  const physics::TopKinematics top = ctx_.axes.top(next, s.t, s.y);
  // The string goes slack from taut: start the flight on L1 + L2 = l (to rounding, not to the
  // step's drift), strictly on the slack side of the Taut guard (physics::taut_margin).
  if (next.mode == Mode::Slack && contact.mode != Mode::Slack)
    physics::project_positions(ctx_.model, contact, ctx_.axes.top(contact, s.t, s.y), s.y);
  if (next.mode != Mode::Slack) {
    physics::project_positions(ctx_.model, next, top, s.y);
    const physics::ProjectionEnergy pe = physics::project_velocities(ctx_.model, next, top, s.y, e);
    book_impulse(pe);
    next = physics::settle(ctx_.model, top_now_, next, s.y, ctx_.band);
  }
  if (next.mode == Mode::Stuck && contact.mode != Mode::Stuck && sum.sticks++ == 0) sum.first_stick = s.t;
  if (next.mode == Mode::Slack && contact.mode != Mode::Slack) ++sum.slack_phases;
  if (next.mode != contact.mode || next.sigma != contact.sigma) ++sum.mode_switches;
  contact = next;
}

// An impulse's work −λᵀb is done by the top, which moves as prescribed through it: with the
// tie clutch the tie is taken as rigid for the instant (its impulse would need an unbounded
// clutch torque), so the rod supplies that work too and the tie's balance is untouched.
void ModeSwitches::book_impulse(const physics::ProjectionEnergy& pe) {
  State& s = ctx_.s;
  s.y(physics::idx::motor_work) += pe.motor_work;
  if (physics::has_ledger(s.y)) s.y(physics::idx::rod_work) += pe.motor_work;
  s.impact_loss += pe.dissipated;
}

void ModeSwitches::impact_account(const physics::ProjectionEnergy& pe) {
  book_impulse(pe);
  ++ctx_.sum.impacts;
}

// The bead meets a stop (the bottom ball, or the top). In free flight: a plastic collision,
// and the string stays slack. On a taut string: a plastic landing onto the two-link set.
void ModeSwitches::meet_stop(bool bottom) {
  State& s = ctx_.s;
  if (s.contact.mode == Mode::Slack) {
    impact_account(bottom ? physics::collide_with_ball(ctx_.model, s.y, 0.0)
                          : physics::collide_with_top(ctx_.model, ctx_.top_at(s.t, s.y), s.y, 0.0));
    return;
  }
  const double w0 = s.y(physics::idx::motor_work), l0 = s.impact_loss;
  enter({bottom ? Mode::BottomStop : Mode::TopStop, 0, 0.0}, 0.0);
  if (s.y(physics::idx::motor_work) != w0 || s.impact_loss != l0) ++ctx_.sum.impacts;
}

// The slack string pulls taut: one simultaneous impact with restitution e onto the active set,
// L1 + L2 = l, together with a stop the bead touches at that instant (the bead resting on the
// ball moves with it). With e > 0 the string rebounds and stays slack; with e = 0 it is taut.
void ModeSwitches::pull_taut() {
  State& s = ctx_.s;
  const physics::Parameters& p = ctx_.model.p;
  const physics::Layers& layers = ctx_.model.layers;
  const physics::TopKinematics top = ctx_.top_at(s.t, s.y);
  const Vec3 r1 = s.y.segment<3>(physics::idx::r1), r2 = s.y.segment<3>(physics::idx::r2);
  Contact set{Mode::Sliding, 0, 0.0};
  if (layers.bottom_stop && (r2 - r1).norm() - p.contact_distance <= on_surface_)
    set.mode = Mode::BottomStop;
  else if (layers.top_stop && (r1 - top.a).norm() - p.top_stop <= on_surface_)
    set.mode = Mode::TopStop;
  // Bounces shrink geometrically (a Zeno sequence): below the rest speed the impact is plastic,
  // before the flights become shorter than any event can resolve.
  const physics::Geometry g = physics::geometry(top, r1, r2, s.y.segment<3>(physics::idx::v1),
                                                s.y.segment<3>(physics::idx::v2));
  const double approach = g.L1_dot + g.L2_dot;
  if (ctx_.restitution > 0.0 && approach > ctx_.opt.rest_speed) {
    // The rebound flight starts on L1 + L2 = l, on the slack side of the Taut guard (the event
    // was located δ_s beyond it, physics::taut_margin).
    physics::project_positions(ctx_.model, set, top, s.y);
    impact_account(physics::project_velocities(ctx_.model, set, top, s.y, ctx_.restitution));
  } else {
    const double l0 = s.impact_loss;
    enter(set, 0.0);
    if (s.impact_loss != l0) ++ctx_.sum.impacts;
  }
}

// The tie (physics/tie.hpp). It slips from where it is held, with χ and χ̇ continuous.
void ModeSwitches::slip_tie(int sigma) {
  State& s = ctx_.s;
  const physics::TopKinematics held = ctx_.top_at(s.t, s.y);
  s.y(physics::idx::chi) = held.phi;
  s.y(physics::idx::chi_dot) = held.omega;
  s.contact.tie = {true, sigma, 0.0};
  if (ctx_.sum.tie_slips++ == 0) ctx_.sum.first_tie_slip = s.t;
  ++ctx_.sum.mode_switches;
}

// The slipping tie has caught the rod: held at the present offset if the torque it needs
// is within τ_s, else it slips on in the sense that torque asks.
void ModeSwitches::lock_tie() {
  State& s = ctx_.s;
  double phi, omega, omega_dot;
  ctx_.schedule.phase(s.t, phi, omega, omega_dot);
  Contact held = s.contact;
  held.tie = {false, 0, s.y(physics::idx::chi) - phi};
  const double tau = physics::tie_torque_needed(ctx_.model, ctx_.axes.top(held, s.t, s.y), held, s.y);
  ++ctx_.sum.mode_switches;
  if (std::abs(tau) <= ctx_.model.p.tie_static_torque + ctx_.band) {
    s.contact.tie = held.tie;
    // The catch is located to the event's tolerance, χ̇ ≈ ω_m: a plastic catch of I_a by the
    // rod, J = I_a (ω_m − χ̇), rod work J ω_m, loss ½ I_a (ω_m − χ̇)².
    const double jump = omega - s.y(physics::idx::chi_dot);
    s.y(physics::idx::rod_work) += ctx_.model.p.tie_inertia * jump * omega;
    s.y(physics::idx::clutch_loss) += 0.5 * ctx_.model.p.tie_inertia * jump * jump;
    physics::hold_tie(ctx_.schedule, s.t, held.tie.offset, s.y);
  } else {
    s.contact.tie = {true, tau > 0.0 ? +1 : -1, 0.0};
  }
}

// A held tie whose torque is already past τ_s (at the start, or after ä jumped) slips now.
bool ModeSwitches::tie_slips_now() {
  const State& s = ctx_.s;
  if (!ctx_.model.layers.tie_clutch || s.contact.tie.slip) return false;
  const double tau = physics::tie_torque_needed(ctx_.model, ctx_.top_at(s.t, s.y), s.contact, s.y);
  if (std::abs(tau) <= ctx_.model.p.tie_static_torque + ctx_.band) return false;
  slip_tie(tau > 0.0 ? +1 : -1);
  return true;
}

void ModeSwitches::on_event(Guard g) {
  State& s = ctx_.s;
  const physics::TopKinematics top = ctx_.top_at(s.t, s.y);
  switch (g) {
    case Guard::LandBottom:
    case Guard::LandTop:
      meet_stop(g == Guard::LandBottom);
      break;
    case Guard::Rest:
      // The cone is judged on the held bead's forces at the top the held bead would give:
      // with a slipping tie, ä (through χ̈) depends on the bead's mode.
      enter(physics::at_rest(ctx_.model, top_now_(physics::held_here(top, s.contact, s.y)), s.y, ctx_.band), 0.0);
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
      ctx_.sum.failure = fmt::format("at t = {:.6f} s {} (the {} layer is off): the equations are singular there",
                                     s.t, physics::to_string(g), g == Guard::ReachBall ? "bottom-stop" : "top-stop");
      break;
    default:
      break;
  }
}

bool ModeSwitches::resolve_pass() {
  State& s = ctx_.s;
  const Contact& contact = s.contact;
  const physics::Parameters& p = ctx_.model.p;
  const physics::Layers& layers = ctx_.model.layers;
  if (tie_slips_now()) return true;
  const physics::TopKinematics top = ctx_.top_at(s.t, s.y);
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
  const bool into_ball = layers.bottom_stop && g.L2 - p.contact_distance <= on_surface_ && g.L2_dot < -still;
  const bool into_top = layers.top_stop && g.L1 - p.top_stop <= on_surface_ && g.L1_dot < -still;
  if (free && (into_ball || into_top)) {
    meet_stop(into_ball);
    return true;
  }
  if (contact.mode == Mode::Slack) {
    if (g.L1 + g.L2 - p.string_length >= -on_surface_ && g.L1_dot + g.L2_dot > still) {
      pull_taut();
      return true;
    }
    return false;
  }
  const Contact settled = physics::settle(ctx_.model, top_now_, contact, s.y, ctx_.band);
  if (settled.mode != contact.mode || settled.sigma != contact.sigma) {
    enter(settled, 0.0);
    return true;
  }
  if (layers.slack) {
    const physics::Dynamics d = physics::evaluate(ctx_.model, top, contact, s.y);
    if (std::min(d.T1, d.T2) < -ctx_.band) {
      enter({Mode::Slack, 0, 0.0}, 0.0);
      return true;
    }
  }
  return false;
}

void ModeSwitches::resolve_now() {
  for (int pass = 0; pass < 20; ++pass)
    if (!resolve_pass()) return;
  // Twenty changes at one instant and still not settled: the modes cycle, and no choice is
  // consistent there. Going on would integrate a mode whose own conditions fail.
  ctx_.sum.failure = fmt::format("at t = {:.6f} s the contact modes did not settle after 20 changes at one instant "
                                 "(last: {})", ctx_.s.t, physics::to_string(ctx_.s.contact.mode));
}

}  // namespace ajx::sim
