#include "physics/mode_transitions.hpp"

#include <algorithm>
#include <cmath>

#include "physics/astrojax_system.hpp"
#include "physics/contact_modes.hpp"
#include "physics/string_friction.hpp"
#include "physics/tie.hpp"

namespace ajx::physics {

std::string_view to_string(Guard g) {
  switch (g) {
    case Guard::LandBottom: return "land_bottom";
    case Guard::LandTop: return "land_top";
    case Guard::Rest: return "rest";
    case Guard::SlipUp: return "slip_up";
    case Guard::SlipDown: return "slip_down";
    case Guard::Slacken: return "slacken";
    case Guard::Taut: return "taut";
    case Guard::ReachBall: return "the bead reached the bottom ball";
    case Guard::ReachTop: return "the bead reached the top";
    case Guard::TieSlipAhead: return "tie_slip_ahead";
    case Guard::TieSlipBehind: return "tie_slip_behind";
    case Guard::TieLock: return "tie_lock";
    case Guard::WatchTension: return "negative tension without the slack layer";
    case Guard::WatchStick: return "ṡ = 0 inside the static cone without stick-slip";
    case Guard::WatchBottom: return "bead below the bottom stop without that layer";
    case Guard::WatchTop: return "bead above the top stop without that layer";
  }
  return "?";
}

bool is_watch(Guard g) { return g >= Guard::WatchTension; }

std::vector<GuardSpec> guards(const Model& m, const Contact& c) {
  const Layers& L = m.layers;
  std::vector<GuardSpec> out;
  const auto add = [&](Guard g, int dir) { out.push_back({g, dir}); };
  const auto tension = [&] {
    if (L.slack) add(Guard::Slacken, -1);
    else add(Guard::WatchTension, 0);
  };
  switch (c.mode) {
    case Mode::Sliding:
      add(L.bottom_stop ? Guard::LandBottom : Guard::WatchBottom, L.bottom_stop ? -1 : 0);
      add(L.top_stop ? Guard::LandTop : Guard::WatchTop, L.top_stop ? -1 : 0);
      if (!L.bottom_stop) add(Guard::ReachBall, -1);
      if (!L.top_stop) add(Guard::ReachTop, -1);
      if (can_stick(m) && c.sigma != 0) add(Guard::Rest, -1);
      if (regularised(m)) add(Guard::WatchStick, 0);
      tension();
      break;
    case Mode::Stuck:
      add(Guard::SlipUp, -1);
      add(Guard::SlipDown, -1);
      tension();
      break;
    case Mode::BottomStop:
      add(Guard::SlipUp, -1);
      tension();
      break;
    case Mode::TopStop:
      add(Guard::SlipDown, -1);
      tension();
      break;
    case Mode::Slack:
      add(Guard::Taut, +1);
      if (L.bottom_stop) add(Guard::LandBottom, -1);
      if (L.top_stop) add(Guard::LandTop, -1);
      break;
  }
  if (L.tie_clutch) {
    if (c.tie.slip) {
      add(Guard::TieLock, -1);
    } else {
      add(Guard::TieSlipAhead, -1);
      add(Guard::TieSlipBehind, -1);
    }
  }
  return out;
}

double guard_value(Guard g, const Model& m, const TopKinematics& top, const Contact& c,
                   const numerics::Vec& y) {
  const Vec3 r1 = y.segment<3>(idx::r1), r2 = y.segment<3>(idx::r2);
  switch (g) {
    case Guard::LandBottom:
    case Guard::WatchBottom: return (r2 - r1).norm() - m.p.contact_distance;
    case Guard::LandTop:
    case Guard::WatchTop: return (r1 - top.a).norm() - m.p.top_stop;
    case Guard::Taut: return (r1 - top.a).norm() + (r2 - r1).norm() - m.p.string_length - taut_margin(m.p);
    case Guard::ReachBall: return (r2 - r1).norm() - 1e-4 * m.p.string_length;
    case Guard::ReachTop: return (r1 - top.a).norm() - 1e-4 * m.p.string_length;
    case Guard::Rest:
    case Guard::WatchStick: {
      const Vec3 u1 = (r1 - top.a).normalized();
      const double sdot = u1.dot(Vec3(y.segment<3>(idx::v1)) - top.a_dot);
      return g == Guard::Rest ? c.sigma * sdot : sdot;
    }
    case Guard::TieLock: return c.tie.sigma * (top.motor_omega - top.omega);
    case Guard::TieSlipAhead:
    case Guard::TieSlipBehind:
    case Guard::SlipUp:
    case Guard::SlipDown:
    case Guard::Slacken:
    case Guard::WatchTension: return guard_value(g, m, top, c, y, evaluate(m, top, c, y));
  }
  return 1.0;
}

bool needs_dynamics(Guard g) {
  return g == Guard::SlipUp || g == Guard::SlipDown || g == Guard::Slacken || g == Guard::WatchTension ||
         g == Guard::TieSlipAhead || g == Guard::TieSlipBehind;
}

double guard_value(Guard g, const Model& m, const TopKinematics& top, const Contact& c,
                   const numerics::Vec& y, const Dynamics& d) {
  switch (g) {
    case Guard::SlipUp: return d.margins.up;
    case Guard::SlipDown: return d.margins.down;
    case Guard::Slacken:
    case Guard::WatchTension: return std::min(d.T1, d.T2);
    case Guard::TieSlipAhead: return m.p.tie_static_torque - tie_torque_needed(m, top, d);
    case Guard::TieSlipBehind: return m.p.tie_static_torque + tie_torque_needed(m, top, d);
    default: return guard_value(g, m, top, c, y);
  }
}

Contact held_here(const TopKinematics& top, const Contact& c, const numerics::Vec& y) {
  Contact held{Mode::Stuck, 0, (Vec3(y.segment<3>(idx::r1)) - top.a).norm()};
  held.tie = c.tie;
  return held;
}

Contact at_rest(const Model& m, const TopKinematics& top, const numerics::Vec& y, double band) {
  const double s = (Vec3(y.segment<3>(idx::r1)) - top.a).norm();
  const Contact held{Mode::Stuck, 0, s};
  const ConeMargins c = evaluate(m, top, held, y).margins;
  if (can_stick(m) && c.up >= -band && c.down >= -band) return held;
  if (can_stick(m)) return {Mode::Sliding, c.up < -band ? -1 : +1, 0.0};
  // No stuck mode: the direction of s̈ under frictionless sliding, which friction only scales.
  const Model frictionless{m.p, Layers{Friction::None, m.layers.friction_law}};
  const Dynamics d = evaluate(frictionless, top, {Mode::Sliding, 0, 0.0}, y);
  const double sdd = d.g.u1.dot(d.acc1 - top.a_ddot) + d.g.q1;
  return {Mode::Sliding, sdd > 0.0 ? +1 : (sdd < 0.0 ? -1 : 0), 0.0};
}

double static_cone_margin(const Model& m, const TopFor& top_for, const Contact& c, const numerics::Vec& y) {
  Model held_model = m;
  held_model.layers.friction = Friction::StickSlip;  // the μ_s cone
  const Contact held = held_here(top_for(c), c, y);
  // The held bead's top: its χ̈ does not depend on the friction layer (two constraints, no κ).
  const ConeMargins k = evaluate(held_model, top_for(held), held, y).margins;
  return std::min(k.up, k.down);
}

namespace {

// settle() for the bead's mode only (the returned tie is the default one).
Contact settle_bead(const Model& m, const TopFor& top_for, const Contact& c, const numerics::Vec& y,
                    double band) {
  const TopKinematics top = top_for(c);
  switch (c.mode) {
    case Mode::Stuck:
    case Mode::BottomStop:
    case Mode::TopStop: {
      const ConeMargins k = evaluate(m, top, c, y).margins;
      if (k.up < -band) return {Mode::Sliding, -1, 0.0};
      if (k.down < -band) return {Mode::Sliding, +1, 0.0};
      return c;
    }
    case Mode::Sliding: {
      if (m.layers.friction == Friction::None || regularised(m))
        return {Mode::Sliding, 0, 0.0};
      const double sdot = geometry(top, y.segment<3>(idx::r1), y.segment<3>(idx::r2), y.segment<3>(idx::v1),
                                   y.segment<3>(idx::v2))
                              .L1_dot;
      // A direction already chosen (by the cone, at a slip) stands while ṡ is at round-off.
      const double sdot_floor = 1e-12;  // [m/s]
      if (c.sigma != 0 && std::abs(sdot) <= sdot_floor) return c;
      if (sdot != 0.0) return {Mode::Sliding, sdot > 0.0 ? +1 : -1, 0.0};
      // The cone is the held bead's, at the top the held bead gives (not this mode's: with a
      // slipping tie the sliding mode's χ̈, hence ä, differs).
      return at_rest(m, top_for(held_here(top, c, y)), y, band);
    }
    case Mode::Slack:
      return c;
  }
  return c;
}

}  // namespace

Contact settle(const Model& m, const TopFor& top_for, const Contact& c, const numerics::Vec& y,
               double band) {
  Contact out = settle_bead(m, top_for, c, y, band);
  out.tie = c.tie;  // the bead's mode settles; the tie's state (held at its offset, or slipping) stays
  return out;
}

}  // namespace ajx::physics
