#include "sim/event_location.hpp"

#include <algorithm>
#include <cmath>

#include "sim/step_bound.hpp"

namespace ajx::sim {

using numerics::Vec;
using physics::Guard;

const physics::Dynamics& GuardEvents::DynamicsCache::at(double tq, const physics::TopKinematics& top,
                                                        const Vec& yq, const physics::Model& m,
                                                        const Contact& c) {
  if (!(valid && tq == t && yq.size() == y.size() && (yq.array() == y.array()).all())) {
    d = physics::evaluate(m, top, c, yq);
    t = tq;
    y = yq;
    valid = true;
  }
  return d;
}

double GuardEvents::value(Guard kind, bool force, double t, const Vec& y) {
  const physics::TopKinematics top = ctx_.top_at(t, y);
  const Contact& contact = ctx_.contact();
  if (!physics::needs_dynamics(kind)) return physics::guard_value(kind, ctx_.model, top, contact, y);
  return physics::guard_value(kind, ctx_.model, top, contact, y, cache_.at(t, top, y, ctx_.model, contact)) +
         (force ? ctx_.band : 0.0);
}

// |Δa| over [t0, t1] (sim/step_bound.hpp): 0 in the rotating axes; in the lab the arc
// R h max(|ω(t0)|, |ω(t1)|) of the motor's top (ω linear within a segment), at most the
// diameter 2R, which is all that is claimed for a tie's top.
double GuardEvents::top_travel(double t0, double t1) const {
  if (ctx_.axes.rotating) return 0.0;
  const double R = ctx_.schedule.radius();
  // A hand moves the top besides: |Δd| <= |ḋ|max h while it holds the top.
  const physics::HandPath* hand = ctx_.schedule.hand();
  const double by_hand = hand && t0 < hand->duration ? hand->speed_bound() * std::abs(t1 - t0) : 0.0;
  if (ctx_.model.layers.tie_clutch) return 2.0 * R + by_hand;
  double phi, w0, w1, wd;
  ctx_.schedule.phase(t0, phi, w0, wd);
  ctx_.schedule.phase(t1, phi, w1, wd);
  return std::min(2.0 * R, R * std::abs(t1 - t0) * std::max(std::abs(w0), std::abs(w1))) + by_hand;
}

void GuardEvents::arm() {
  specs_ = physics::guards(ctx_.model, ctx_.contact());
  events_.clear();
  cache_.valid = false;
  for (const auto& g : specs_) {
    const bool force = g.kind == Guard::SlipUp || g.kind == Guard::SlipDown || g.kind == Guard::Slacken;
    numerics::Event e{[this, kind = g.kind, force](double t, const Vec& y) { return value(kind, force, t, y); },
                      g.direction, {}};
    if (has_change_bound(g.kind))
      e.change_bound = [this, kind = g.kind](double t0, double t1, const Vec& /*y0*/, const Vec& ex) {
        return guard_change_bound(kind, top_travel(t0, t1), ex);
      };
    events_.push_back(std::move(e));
  }
}

}  // namespace ajx::sim
