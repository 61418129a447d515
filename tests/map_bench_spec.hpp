// The bisections of tests/bench/map_bisection.sh's map, as the tests and tools that reproduce it
// in C++ set them up: ω_fall down to 2.5π or ω1 up to 6.5π, from the locked orbit at 4π.
#pragma once
#include <numbers>

#include "sweep/bisection.hpp"

namespace ajx::sweep {

inline BisectSpec map_bench_spec(Threshold th, double width) {
  constexpr double pi = std::numbers::pi;
  BisectSpec spec;
  spec.threshold = th;
  spec.start_seed = "locked_orbit";
  spec.start_omega = spec.from = 4 * pi;
  spec.to = th == Threshold::Fall ? 2.5 * pi : 6.5 * pi;
  spec.width = width;
  return spec;
}

}  // namespace ajx::sweep
