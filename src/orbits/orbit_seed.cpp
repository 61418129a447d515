#include "orbits/orbit_seed.hpp"

#include <algorithm>

#include "orbits/orbit_families.hpp"
#include "orbits/orbit_stability.hpp"

namespace ajx::orbits {

std::optional<SeedOrbit> locked_orbit_seed(const physics::Model& m, double omega) {
  const OrbitCatalogue cat = find_orbits(m, omega, {41});
  const auto depth = [](const SteadyOrbit& o) { return std::min(o.margins.up, o.margins.down); };
  const auto is_stable = [&](const SteadyOrbit& o) { return stability({m, omega, o.closure, o.s}, unknowns(o)).stable; };
  std::optional<SeedOrbit> best;
  const auto consider = [&](const SteadyOrbit& o, int rank, bool stable) {
    if (!best || rank < best->rank || (rank == best->rank && depth(o) > depth(best->orbit))) best = SeedOrbit{o, stable, rank};
  };
  for (const auto& o : cat.stuck) {
    if (!o.admissible) continue;
    const bool st = is_stable(o);
    consider(o, st ? 1 : 2, st);
  }
  if (best) return best;
  for (const auto& o : cat.bottom) {
    if (!o.admissible) continue;
    const bool st = is_stable(o);
    if (!best || (st && !best->stable)) best = SeedOrbit{o, st, 3};
  }
  return best;
}

}  // namespace ajx::orbits
