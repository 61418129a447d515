// The continuation's map of the (R, d) plane (issue 28's target: under 10 s of CPU on one core):
// at each of 16 contact distances d from 2.5 to 5 cm, the curves of ω1 (cone_up), ω_fall
// (cone_down) and the locked orbit's fold (orbits/threshold_curves.hpp) of the bead stuck at
// s = 0.4589 m, followed in R over [5, 25] mm from the documented set (R = 15 mm), each curve
// computed afresh (nothing reused between values of d). Prints the CPU time (std::clock: this
// process, one thread), the points, and the ratio to the 10 s target. Figures printed, never
// asserted.
// Run:  build/tests/bench/map_continuation
#include <cstdio>
#include <ctime>

#include "orbits/threshold_curves.hpp"

int main() {
  using namespace ajx::orbits;
  constexpr int kD = 16;
  const std::clock_t t0 = std::clock();
  std::size_t points = 0, curves = 0, meets = 0;
  for (int i = 0; i < kD; ++i) {
    ajx::physics::Model m;
    m.p.drive_radius = 0.015;
    m.p.contact_distance = 0.025 + 0.025 * i / (kD - 1);
    CurveOptions opt;
    opt.p_lo = 0.005;
    opt.p_hi = 0.025;
    for (const Curve& c :
         threshold_curves(m, "drive_radius", {CurveKind::ConeUp, CurveKind::ConeDown, CurveKind::Fold}, 0.4589, opt)) {
      ++curves;
      points += c.points.size();
      meets += c.meets.size();
    }
  }
  const double cpu = double(std::clock() - t0) / CLOCKS_PER_SEC;
  std::printf("continuation map of (R, d): %d values of d x curves in R over [5, 25] mm (cone_up, cone_down, fold)\n",
              kD);
  std::printf("  %zu curves, %zu points, %zu codimension-2 points\n", curves, points, meets);
  std::printf("  CPU %.2f s on one core; target 10 s: ratio %.3f (%s)\n", cpu, cpu / 10.0,
              cpu < 10.0 ? "met" : "missed");
  return 0;
}
