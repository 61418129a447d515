// Thresholds predicted from the branches: every locked interval holds a stable admissible
// stuck orbit inside, and its ends are what they say they are.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fmt/format.h>
#include <numbers>

#include "orbits/orbit_families.hpp"
#include "orbits/orbit_stability.hpp"
#include "orbits/predicted_thresholds.hpp"

using namespace ajx;
using namespace ajx::orbits;

namespace {
constexpr double kPi = std::numbers::pi;
}

TEST(PredictedThresholds, LockedIntervalsHoldStableAdmissibleOrbitsAndEndAtTheirEvents) {
  const physics::Model m;
  PredictionOptions opt;
  opt.s_points = 3;
  opt.omega_hi = 16 * kPi;
  const Predictions P = predict_thresholds(m, opt);
  int stuck = 0;
  for (const auto& iv : P.intervals) {
    if (iv.s >= m.p.string_length - m.p.contact_distance) continue;  // bottom-stop intervals
    ++stuck;
    ASSERT_LT(iv.omega_lo, iv.omega_hi);
    // Inside: some orbit at s on the same branch is stable and admissible.
    const double mid = 0.5 * (iv.omega_lo + iv.omega_hi);
    bool held = false;
    for (const auto& o : orbits_at({m, mid, Closure::Stuck, iv.s}))
      held |= o.admissible && stability({m, mid, Closure::Stuck, iv.s}, unknowns(o)).stable;
    EXPECT_TRUE(held) << "s " << iv.s << " ω " << mid << " in [" << iv.omega_lo << " " << iv.ends_lo << ", " << iv.omega_hi << " " << iv.ends_hi << "] " << iv.branch;
    // A cone exit at an end: a static-cone margin of some orbit there vanishes (to the
    // bisection's resolution, far below 1e-6 N).
    for (const auto& [w, why] : {std::pair{iv.omega_lo, iv.ends_lo}, std::pair{iv.omega_hi, iv.ends_hi}}) {
      if (why.rfind("cone_exit", 0) != 0) continue;
      double best = 1e300;
      for (const auto& o : orbits_at({m, w, Closure::Stuck, iv.s}))
        best = std::min(best, std::min(std::abs(o.margins.up), std::abs(o.margins.down)));
      EXPECT_LT(best, 1e-6) << why << " at ω " << w;
    }
  }
  EXPECT_GT(stuck, 0);
  for (const auto& t : P.thresholds)
    std::printf("measured %s: predicted %.4fπ (paper %.2fπ): %s\n", t.symbol.c_str(), t.predicted / kPi,
                t.measured / kPi, t.mechanism.c_str());
}
