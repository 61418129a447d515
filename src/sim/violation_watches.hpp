// Violations of omitted layers: a watch guard of physics/mode_transitions.hpp turns negative
// where a layer that is off would have acted.
// A violation is entered when its watch crosses into the bad side; its worst excess is then
// followed at every accepted step while inside. A new watch goes here (and its guard in
// physics/mode_transitions.cpp); the mode goes on in every case.
#pragma once
#include <utility>
#include <vector>

#include "physics/mode_transitions.hpp"
#include "sim/run_context.hpp"

namespace ajx::sim {

class ViolationWatches {
 public:
  explicit ViolationWatches(RunContext& ctx) : ctx_(ctx) {}

  // At a segment start with the mode's guards `specs`: a violation already present there is
  // never seen as a crossing, so it is checked here.
  void check_at_start(const std::vector<physics::GuardSpec>& specs);
  // The integrator stopped on watch guard g: entering or leaving its bad side.
  void on_crossing(physics::Guard g);
  // A mode switch at guard g is about to be made. The kinetic friction layer has no static
  // coefficient: where μ_s would have held the bead at rest, its assumption failed (whether
  // μ_k then holds it or lets it reverse).
  void before_switch(physics::Guard g);
  // After an accepted step at (t, y): the worst excess of the watches inside.
  void follow(double t, const numerics::Vec& y);
  // The violations entered so far, in the order first seen.
  std::vector<Violation> violations() const;

 private:
  struct Watch {
    Violation v;
    bool inside = false;
  };
  Watch& watch(physics::Guard g);
  void enter(physics::Guard g, double t, double excess);
  // The cone margin a stuck bead would have here: > 0 means a model with stick would hold it.
  double stick_margin(double t, const numerics::Vec& y) const;

  RunContext& ctx_;
  std::vector<std::pair<physics::Guard, Watch>> watches_;
};

}  // namespace ajx::sim
