#include "sim/event_location.hpp"

namespace ajx::sim {

using numerics::Vec;
using physics::Guard;

double GuardEvents::value(Guard kind, bool force, double t, const Vec& y) {
  const physics::TopKinematics top = ctx_.top_at(t, y);
  const Contact& contact = ctx_.contact();
  if (!physics::needs_dynamics(kind)) return physics::guard_value(kind, ctx_.model, top, contact, y);
  return physics::guard_value(kind, ctx_.model, top, contact, y, ctx_.evaluation.at(t, top, y, ctx_.model, contact)) +
         (force ? ctx_.band : 0.0);
}

void GuardEvents::arm() {
  specs_ = physics::guards(ctx_.model, ctx_.contact());
  events_.clear();
  ctx_.evaluation.clear();  // the mode may have changed
  for (const auto& g : specs_) {
    const bool force = g.kind == Guard::SlipUp || g.kind == Guard::SlipDown || g.kind == Guard::Slacken;
    events_.push_back({[this, kind = g.kind, force](double t, const Vec& y) { return value(kind, force, t, y); },
                       g.direction});
  }
}

}  // namespace ajx::sim
