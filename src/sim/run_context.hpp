// What the stages of one run share (sim/simulation.cpp's loop): the model, the axes the
// integrator sees, the trajectory being advanced and its summary, and the chatter resolution.
#pragma once
#include "numerics/integrate.hpp"
#include "physics/mode_transitions.hpp"
#include "physics/rotating_axes.hpp"
#include "physics/tie.hpp"
#include "sim/simulation.hpp"

namespace ajx::sim {

// The axes of one run (physics/rotating_axes.hpp). In rotating axes every physics function
// takes the top at φ = 0 and the rotated state y' (they are invariant under rotations about z).
struct RunAxes {
  const physics::Model& model;
  const physics::MotorSchedule& schedule;
  bool rotating = false;

  // Rotating unless the options ask for the lab, Auto deciding from the state s (corotates(),
  // sim/step_bound.hpp). A tie that may slip on the rod is not at φ: with it the run stays in
  // the lab.
  static RunAxes choose(const physics::Model& model, const physics::MotorSchedule& schedule, Axes axes,
                        const State& s);
  // The top of the string: the motor's a(t), or the tie's, for the bead's mode c (a slipping
  // tie's χ̈ depends on the string's pull in that mode).
  // (Inline: called at every guard evaluation.)
  physics::TopKinematics top(const Contact& c, double t, const numerics::Vec& y) const {
    return rotating ? physics::top_in_rotating_axes(schedule, t)
                    : physics::top_kinematics(model, schedule, c, t, y);
  }
  // The angle from the integrator's axes to the lab's: φ(t), or 0 in the lab.
  double angle(double t) const {
    if (!rotating) return 0.0;
    double phi, w, wd;
    schedule.phase(t, phi, w, wd);
    return phi;
  }
  // ẏ = f(t, y) in these axes for the mode `contact` holds when f is called.
  numerics::System system(const Contact& contact) const;
};

struct RunContext {
  const physics::Model& model;
  const physics::MotorSchedule& schedule;
  const RunOptions& opt;
  RunAxes axes;
  State& s;          // the trajectory: s.t, s.y (in the integrator's axes), s.contact
  RunSummary& sum;
  // Chatter resolution (sim/chatter.hpp): force guards switch only past this band [N], and
  // taut impacts have this restitution.
  double band = 0.0;
  double restitution = 0.0;

  Contact& contact() { return s.contact; }
  const Contact& contact() const { return s.contact; }
  // The top for the current mode at (t, y). In the lab it is remembered for the last (t, y, mode):
  // the guards, the step bound and the projection all ask for it at a step's end, and a slipping
  // tie's top costs two evaluations of the dynamics (physics/tie.hpp).
  physics::TopKinematics top_at(double t, const numerics::Vec& y) const;

  // top_at's memory (kept a member of this aggregate; nothing else reads it).
  struct TopMemo {
    bool valid = false;
    double t = 0.0;
    numerics::Vec y;
    Contact contact;
    physics::TopKinematics top;
  };
  mutable TopMemo top_memo = {};
};

}  // namespace ajx::sim
