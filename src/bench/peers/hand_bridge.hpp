// Between a project scene and the hand-written peer's model (bench/peers/hand_model.hpp): its
// parameters and contact mode from the scene, and how far the peer's right-hand side is from
// the project's at a state. The peer itself never sees the project's types.
#pragma once
#include "bench/peers/hand_model.hpp"
#include "bench/work_precision.hpp"

namespace ajx::bench {

// The hand-written model's parameters; throws for layers it does not model (only the default:
// capstan stick-slip, both stops, no tie clutch, no pair couple).
hand::Params hand_params(const Scene& s);
hand::Contact hand_contact(const physics::Contact& c);  // throws for a slack string
physics::Mode project_mode(hand::Mode m);
double phase(const Scene& s, double t);  // φ of the motor [rad]

// max |ẏ_hand − ẏ_project| / max |ẏ_project| over the 12 motion components, in the rotating
// axes, at a state given in the lab axes.
double rhs_mismatch(const Scene& s, const hand::Params& h, const physics::State& lab);

// CPU time of one right-hand-side evaluation at the state lab, the project's
// (physics::rhs_in_rotating_axes through numerics::System, as a stepper calls it) and the peer's
// (hand::rhs), each the least of 5 interleaved batches of n calls at a new time each call [s].
struct RhsCost {
  double project, hand;
};
RhsCost rhs_cost(const Scene& s, const hand::Params& h, const physics::State& lab, long n = 200000);

}  // namespace ajx::bench
