// Seed states of the hold mode: where a run at fixed ω_m starts, to find which orbits coexist
// at one ω_m without ramping.
//   hanging        both balls at rest below the top, the bead on the bottom ball;
//   circular_high  the paper's Table 1 orbit (bead at radius 14.4 cm, 52.5 cm down; bottom
//                  ball opposite at 11.9 cm, 62.4 cm down, scaled to the string length)
//                  turning rigidly at ω_m, projected onto the string: the bead high;
//   locked_orbit   a locked orbit found as an equilibrium of the co-rotating frame at ω_m
//                  (orbits/orbit_seed.hpp: stuck, held by friction and stable if there is one),
//                  turned to the top's phase, the bead stuck (or resting on the ball);
// and perturbation k >= 1 of any: a random velocity kick of rms `kick` on each component
// of both balls (deterministic: the generator is seeded with the seed name and k).
#pragma once
#include <string>

#include "physics/drive.hpp"
#include "physics/model.hpp"
#include "physics/state.hpp"

namespace ajx::sweep {

// Throws std::invalid_argument for an unknown seed name.
physics::State seed_state(const physics::Model& m, const physics::MotorSchedule& schedule, const std::string& seed,
                          double omega, int perturbation, double kick);

}  // namespace ajx::sweep
