// The guards of the current mode as the integrator's events: located as sign changes inside
// the steps (numerics/integrate.hpp), the force guards shifted by the chatter band.
#pragma once
#include <span>
#include <vector>

#include "numerics/integrate.hpp"
#include "physics/mode_transitions.hpp"
#include "sim/run_context.hpp"

namespace ajx::sim {

class GuardEvents {
 public:
  explicit GuardEvents(RunContext& ctx) : ctx_(ctx) {}
  GuardEvents(const GuardEvents&) = delete;
  GuardEvents& operator=(const GuardEvents&) = delete;

  // The guards of the present mode (ctx.contact()), at a segment start.
  void arm();
  const std::vector<physics::GuardSpec>& specs() const { return specs_; }
  std::span<const numerics::Event> events() const { return events_; }
  // The guard behind the integrator's event index.
  physics::Guard kind(int event_index) const { return specs_[std::size_t(event_index)].kind; }

 private:
  // The force guards of a mode (two cone margins, the tensions) share one evaluation at (t, y);
  // the top they share is RunContext::top_at's. The mode is fixed between two arm() calls.
  struct DynamicsCache {
    bool valid = false;
    double t = 0.0;
    numerics::Vec y;
    physics::Dynamics d;
    const physics::Dynamics& at(double tq, const physics::TopKinematics& top, const numerics::Vec& yq,
                                const physics::Model& m, const Contact& c);
  };
  double value(physics::Guard kind, bool force, double t, const numerics::Vec& y);
  double top_travel(double t0, double t1) const;

  RunContext& ctx_;
  DynamicsCache cache_;
  std::vector<physics::GuardSpec> specs_;
  std::vector<numerics::Event> events_;
};

}  // namespace ajx::sim
