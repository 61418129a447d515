// The starts of the paper's Table 1: for each orbit the positions of both balls at the first two
// steps of its scheme, q^(0) and q^(1) = q(h).
//
// Read from the table in cm, converted to m, and mirrored y -> -y: the table's circular orbits
// turn clockwise seen from above (x1 = -14.427 -> -14.427 cos θ, y1 = 0 -> +14.427 sin θ), the
// project's motor counter-clockwise (a = R (cos φ, sin φ, 0), φ growing); the mirror image of a
// solution is a solution with the motor reversed. θ of the circular orbits is the angle the orbit
// turns in one step, θ = ω h (ω the motor's speed at the start: a locked orbit). The table prints
// the bottom ball's q^(1) of the circular orbits as (11.924, -11.924), without the cos θ and sin θ
// that its bead row carries (a jump of 12 cm in one step); read as (11.924 cos θ, -11.924 sin θ).
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "sim/paper_scheme.hpp"

namespace ajx::sim {

// "circular1", "circular2", "flower1", "flower2", "flower3", "flower4".
const std::vector<std::string>& table1_orbits();

// The pair of orbit `name` for a scheme of step h, the circular ones turning at ω [rad/s]; t0 = 0.
// Throws std::invalid_argument naming the allowed orbits.
PairStart table1_pair(std::string_view name, double omega, double h);

}  // namespace ajx::sim
