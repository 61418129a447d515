#include "sim/violation_watches.hpp"

#include <algorithm>
#include <string>

namespace ajx::sim {

using numerics::Vec;
using physics::Guard;

ViolationWatches::Watch& ViolationWatches::watch(Guard g) {
  for (auto& [k, w] : watches_)
    if (k == g) return w;
  Watch w;
  w.v.what = std::string(physics::to_string(g));
  w.v.unit = g == Guard::WatchTension ? "N" : (g == Guard::WatchStick ? "N of cone margin" : "m");
  watches_.emplace_back(g, w);
  return watches_.back().second;
}

void ViolationWatches::enter(Guard g, double t, double excess) {
  Watch& w = watch(g);
  if (w.v.count++ == 0) w.v.first_time = t;
  w.v.worst = std::max(w.v.worst, excess);
}

double ViolationWatches::stick_margin(double t, const Vec& y) const {
  return physics::static_cone_margin(
      ctx_.model, [&](const Contact& c) { return ctx_.axes.top(c, t, y); }, ctx_.contact(), y);
}

void ViolationWatches::check_at_start(const std::vector<physics::GuardSpec>& specs) {
  const State& s = ctx_.s;
  for (const auto& g : specs) {
    if (!physics::is_watch(g.kind) || g.kind == Guard::WatchStick) continue;
    const double value = physics::guard_value(g.kind, ctx_.model, ctx_.top_at(s.t, s.y), s.contact, s.y);
    Watch& w = watch(g.kind);
    if (value < 0.0 && !w.inside) enter(g.kind, s.t, -value);
    w.inside = value < 0.0;
  }
}

void ViolationWatches::on_crossing(Guard g) {
  const State& s = ctx_.s;
  const double value = physics::guard_value(g, ctx_.model, ctx_.top_at(s.t, s.y), s.contact, s.y);
  Watch& w = watch(g);
  if (g == Guard::WatchStick) {
    const double margin = stick_margin(s.t, s.y);
    if (margin > 0.0) enter(g, s.t, margin);
  } else if (!w.inside && value <= 0.0) {
    w.inside = true;
    enter(g, s.t, -value);
  } else {
    w.inside = false;
  }
}

void ViolationWatches::before_switch(Guard g) {
  if (g != Guard::Rest || ctx_.model.layers.friction != physics::Friction::Kinetic) return;
  const double margin = stick_margin(ctx_.s.t, ctx_.s.y);
  if (margin > 0.0) enter(Guard::WatchStick, ctx_.s.t, margin);
}

void ViolationWatches::follow(double t, const Vec& y) {
  for (auto& [g, w] : watches_) {
    if (!w.inside || g == Guard::WatchStick) continue;
    w.v.worst = std::max(w.v.worst, -physics::guard_value(g, ctx_.model, ctx_.top_at(t, y), ctx_.contact(), y));
  }
}

std::vector<Violation> ViolationWatches::violations() const {
  std::vector<Violation> out;
  for (const auto& [g, w] : watches_) out.push_back(w.v);
  return out;
}

}  // namespace ajx::sim
