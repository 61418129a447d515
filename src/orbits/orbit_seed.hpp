// A start on a locked orbit for the sweep's hold mode (seed "locked_orbit"): the pair on an
// equilibrium of the co-rotating frame at ω_m, so that hold points and down-ramps need no
// spin-up. Chosen, in this order, among the orbits of orbit_families.hpp (stuck family on a
// grid of kSeedGridPoints = 41 bead positions):
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
// The stuck family's grid of bead positions (orbit_families.hpp's stuck_grid).
inline constexpr int kSeedGridPoints = 41;

// std::nullopt when no orbit of the list exists at ω_m. Found by scan_locked_orbit_seed once per
// process for each (model, ω_m), bit for bit in every parameter and layer, then taken from
// memory: a pure function of its inputs, so a file does not depend on which rank, thread or
// order asked first.
std::optional<SeedOrbit> locked_orbit_seed(const physics::Model& m, double omega);

// The list above over the stuck orbits of the grid as orbits_at finds them (the catalogue's
// frictionless orbits and cone edges do not enter it), the bottom stop only when no stuck orbit
// holds: the definition, at the cost of 41 catalogue rows (0.03 s at the documented set; 0.5 s
// at R = 5 mm, where most directions fail the drag's homotopy).
std::optional<SeedOrbit> solve_locked_orbit_seed(const physics::Model& m, double omega);
// The same seed, bit for bit, at about half that: every row solved quickly (a quarter of the
// planar starts, the homotopy given up sooner), the rule applied to those, and the rows that can
// decide (the best's, and any with an orbit within 1e-9 of it or of a test's sign change) solved
// again as orbits_at solves them, until the best and its rivals all come from such rows. It
// relies on the quick rows finding the orbits orbits_at finds: tests/orbit_seed_test.cpp checks
// it against solve_locked_orbit_seed where a quicker row did not.
std::optional<SeedOrbit> scan_locked_orbit_seed(const physics::Model& m, double omega);

}  // namespace ajx::orbits
