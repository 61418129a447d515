// A start on a locked orbit for the sweep's hold mode (seed "locked_orbit"): the pair on an
// equilibrium of the co-rotating frame at ω_m, so that hold points and down-ramps need no
// spin-up. Chosen, in this order, among the orbits of orbit_families.hpp (stuck family on a
// grid of 41 bead positions):
//   1. a stuck orbit that friction holds and that is linearly stable, with the largest
//      smaller cone margin (the one deepest inside the cone);
//   2. else a stuck orbit that friction holds (unstable: it shows where it goes);
//   3. else a stable orbit on the bottom stop, else any admissible one on the bottom stop.
#pragma once
#include <optional>

#include "orbits/steady_orbit.hpp"

namespace ajx::orbits {

struct SeedOrbit {
  SteadyOrbit orbit;   // positions in the co-rotating frame, top at (R, 0, 0)
  bool stable = false;
  int rank = 0;        // which rule of the list above chose it (1..3)
};
// std::nullopt when no orbit of the list exists at ω_m.
std::optional<SeedOrbit> locked_orbit_seed(const physics::Model& m, double omega);

}  // namespace ajx::orbits
