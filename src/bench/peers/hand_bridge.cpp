#include "bench/peers/hand_bridge.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "physics/rotating_axes.hpp"

namespace ajx::bench {

// The hand-written model's parameters from a scene; refuses what it does not model.
hand::Params hand_params(const Scene& s) {
  const physics::Layers& L = s.model.layers;
  if (L.friction != physics::Friction::StickSlip || L.friction_law != physics::FrictionLaw::Capstan ||
      !L.bottom_stop || !L.top_stop || L.tie_clutch || L.pair_couple != physics::PairCouple::None)
    throw std::runtime_error(s.name + ": the hand-written peer models the default layers only");
  const physics::Parameters& p = s.model.p;
  hand::Params h{p.string_length, p.bead_mass, p.ball_mass, p.drag, p.mu_static, p.mu_kinetic,
                 p.gravity, p.drive_radius, p.contact_distance, p.top_stop, {}};
  const auto& seg = s.schedule.segments();
  const auto& begin = s.schedule.breakpoints();
  for (std::size_t k = 0; k < seg.size(); ++k)
    h.drive.push_back({begin[k], seg[k].omega_begin, (seg[k].omega_end - seg[k].omega_begin) / seg[k].duration,
                       seg[k].duration});
  return h;
}

hand::Contact hand_contact(const physics::Contact& c) {
  switch (c.mode) {
    case physics::Mode::Sliding: return {hand::Mode::Sliding, c.sigma, 0};
    case physics::Mode::BottomStop: return {hand::Mode::Bottom, 0, 0};
    case physics::Mode::TopStop: return {hand::Mode::Top, 0, 0};
    case physics::Mode::Stuck: return {hand::Mode::Stuck, 0, c.s_star};
    case physics::Mode::Slack: break;
  }
  throw std::runtime_error("the hand-written peer does not model a slack string");
}

physics::Mode project_mode(hand::Mode m) {
  switch (m) {
    case hand::Mode::Sliding: return physics::Mode::Sliding;
    case hand::Mode::Bottom: return physics::Mode::BottomStop;
    case hand::Mode::Top: return physics::Mode::TopStop;
    case hand::Mode::Stuck: return physics::Mode::Stuck;
  }
  return physics::Mode::Slack;
}

double phase(const Scene& s, double t) {
  double phi, w, wd;
  s.schedule.phase(t, phi, w, wd);
  return phi;
}


double rhs_mismatch(const Scene& s, const hand::Params& h, const physics::State& lab) {
  numerics::Vec y = lab.y;
  physics::rotate_about_z(y, -phase(s, lab.t));
  numerics::Vec f(physics::idx::dim);
  physics::rhs_in_rotating_axes(s.model, s.schedule, lab.contact, lab.t, y, f);
  double g[12], diff = 0.0, scale = 0.0;
  hand::rhs(h, hand_contact(lab.contact), lab.t, y.data(), g);
  for (int i = 0; i < 12; ++i) {
    diff = std::max(diff, std::abs(g[i] - f(i)));
    scale = std::max(scale, std::abs(f(i)));
  }
  return diff / scale;
}

RhsCost rhs_cost(const Scene& s, const hand::Params& h, const physics::State& lab, long n) {
  numerics::Vec y = lab.y;
  physics::rotate_about_z(y, -phase(s, lab.t));
  numerics::Vec f(physics::idx::dim);
  const numerics::System sys = [&](double t, const numerics::Vec& x, numerics::Vec& d) {
    physics::rhs_in_rotating_axes(s.model, s.schedule, lab.contact, t, x, d);
  };
  const hand::Contact c = hand_contact(lab.contact);
  double g[12];
  volatile double sink = 0.0;  // keeps the calls
  RhsCost best{1e300, 1e300};
  for (int batch = 0; batch < 5; ++batch) {
    double c0 = cpu_seconds();
    for (long k = 0; k < n; ++k) {
      sys(lab.t + 1e-9 * double(k), y, f);
      sink = sink + f(6);
    }
    best.project = std::min(best.project, (cpu_seconds() - c0) / double(n));
    c0 = cpu_seconds();
    for (long k = 0; k < n; ++k) {
      hand::rhs(h, c, lab.t + 1e-9 * double(k), y.data(), g);
      sink = sink + g[6];
    }
    best.hand = std::min(best.hand, (cpu_seconds() - c0) / double(n));
  }
  return best;
}

}  // namespace ajx::bench
