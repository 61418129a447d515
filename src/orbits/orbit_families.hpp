// All locked circular orbits at one ω_m: the stuck family sampled along the string, its
// frictionless members (T1 = T2), the edges of the static cone, and the bead on the bottom
// stop. Starting guesses come from the planar, drag-free balance of a double pendulum whose
// top sits at x = R (θ from the downward vertical, x1 = R + L1 sin θ1, x2 = x1 + L2 sin θ2):
//   (m1 + m2) g sin θ1 = ω² (m1 x1 + m2 x2) cos θ1,   g sin θ2 = ω² x2 cos θ2,
// solved by Newton from a grid over (−π/2, π/2)² (tensions positive need cos θ > 0); each root
// is then polished in 3-D with drag by steady_orbit.hpp's Newton.
#pragma once
#include <vector>

#include "orbits/steady_orbit.hpp"

namespace ajx::orbits {

// X of an orbit described earlier.
Vec9 unknowns(const SteadyOrbit& o);

// The distinct drag-free planar roots (θ1, θ2) for segment lengths L1, L2, as guesses X.
// Newton from the centres of an n × n grid of starts (24: the catalogue's).
std::vector<Vec9> planar_guesses(const physics::Model& m, double omega, double L1, double L2, int n = 24);

// How hard orbits_at looks: Newton from an n × n grid of planar starts, and a start Newton
// misses continued from zero drag to the model's, given up once the continuation's step falls
// to homotopy_min_step. The defaults are the catalogue's.
struct SolveEffort {
  int starts = 24;
  double homotopy_min_step = 1.0 / 4096;
};

// Every orbit of the closure Stuck (at s_star) or BottomStop found from the planar guesses.
std::vector<SteadyOrbit> orbits_at(const OrbitProblem& pb, const SolveEffort& effort = {});

// The bead positions s of the stuck family's grid: n points from the top stop (or 1e-3 l
// without it) to the bottom stop (or (1 − 1e-3) l), ends included.
std::vector<double> stuck_grid(const physics::Model& m, int n);

struct CatalogueOptions {
  int s_points = 81;  // grid along the string from the top stop to the bottom stop
};
struct OrbitCatalogue {
  std::vector<SteadyOrbit> stuck;         // the family on the s grid (admissible or not)
  std::vector<SteadyOrbit> bottom;        // the bead on the bottom stop
  std::vector<SteadyOrbit> frictionless;  // T1 = T2
  std::vector<SteadyOrbit> edges;         // T1 = κ_lo T2 or κ_hi T2: where admissible s begin and end
};
OrbitCatalogue find_orbits(const physics::Model& m, double omega, const CatalogueOptions& opt = {});

}  // namespace ajx::orbits
