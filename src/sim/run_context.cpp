#include "sim/run_context.hpp"

#include "physics/rotating_axes.hpp"
#include "physics/tie.hpp"
#include "sim/step_bound.hpp"

namespace ajx::sim {

using numerics::Vec;

RunAxes RunAxes::choose(const physics::Model& model, const physics::MotorSchedule& schedule, Axes axes,
                        const State& s) {
  const bool rotating =
      !model.layers.tie_clutch &&
      (axes == Axes::Rotating ||
       (axes == Axes::Auto && corotates(physics::top_kinematics(model, schedule, s.contact, s.t, s.y), s.y)));
  return {model, schedule, rotating};
}

bool SharedEvaluation::same_state(const Vec& y) const {
  return y.size() == y_.size() && (y.array() == y_.array()).all();
}

numerics::System RunAxes::system(const Contact& contact, const SharedEvaluation& shared) const {
  const physics::Model& m = model;
  const physics::MotorSchedule& sched = schedule;
  if (rotating)
    return [&m, &sched, &contact, &shared](double t, const Vec& y, Vec& dydt) {
      const physics::Dynamics* d = shared.find(t, y);
      if (!d) [[likely]]
        return physics::rhs_in_rotating_axes(m, sched, contact, t, y, dydt);
      physics::rates_in_rotating_axes(physics::top_in_rotating_axes(sched, m.p.drive_radius, t), *d, y, dydt);
    };
  return [&m, &sched, &contact, &shared](double t, const Vec& y, Vec& dydt) {
    const physics::Dynamics* d = shared.find(t, y);
    if (!d) [[likely]]
      return physics::rhs(m, sched, contact, t, y, dydt);
    physics::rates(physics::top_kinematics(m, sched, contact, t, y), *d, y, dydt);
  };
}

}  // namespace ajx::sim
