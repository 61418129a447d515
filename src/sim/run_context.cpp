#include "sim/run_context.hpp"

#include "physics/rotating_axes.hpp"
#include "physics/tie.hpp"
#include "sim/step_bound.hpp"

namespace ajx::sim {

using numerics::Vec;

RunAxes RunAxes::choose(const physics::Model& model, const physics::MotorSchedule& schedule, Axes axes,
                        const State& s) {
  // A hand's top is not on the circle: the lab while it holds the top.
  const bool rotating =
      !model.layers.tie_clutch && !(schedule.hand() && schedule.hand()->holds(s.t)) &&
      (axes == Axes::Rotating ||
       (axes == Axes::Auto && corotates(physics::top_kinematics(model, schedule, s.contact, s.t, s.y), s.y)));
  return {model, schedule, rotating};
}

physics::TopKinematics RunContext::top_at(double t, const Vec& y) const {
  if (axes.rotating) return axes.top(s.contact, t, y);  // the top at φ = 0: nothing to remember
  TopMemo& m = top_memo;
  if (!(m.valid && t == m.t && s.contact == m.contact && y.size() == m.y.size() && (y.array() == m.y.array()).all())) {
    m.top = axes.top(s.contact, t, y);
    m.t = t;
    m.y = y;
    m.contact = s.contact;
    m.valid = true;
  }
  return m.top;
}

numerics::System RunAxes::system(const Contact& contact) const {
  const physics::Model& m = model;
  const physics::MotorSchedule& sched = schedule;
  if (rotating)
    return [&m, &sched, &contact](double t, const Vec& y, Vec& dydt) {
      physics::rhs_in_rotating_axes(m, sched, contact, t, y, dydt);
    };
  return [&m, &sched, &contact](double t, const Vec& y, Vec& dydt) { physics::rhs(m, sched, contact, t, y, dydt); };
}

}  // namespace ajx::sim
