// The stability scan: the held scene, the acceptance rule, and the scanner's contract.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bench/scene_file.hpp"
#include "bench/stability.hpp"

namespace {

using namespace ajx;

TEST(Stability, HeldSceneHoldsOmega) {
  bench::Scene base = bench::load_scene(std::string(ASTROJAX_SOURCE_DIR) + "/sweeps/spin_up.toml", {}, 3.0);
  const bench::Scene s = bench::held_at(base, 4.0 * std::numbers::pi);
  double phi, w, wd;
  s.schedule.phase(2.5, phi, w, wd);
  EXPECT_DOUBLE_EQ(w, 4.0 * std::numbers::pi);
  EXPECT_DOUBLE_EQ(wd, 0.0);
  EXPECT_GE(s.schedule.duration(), s.horizon);
}

TEST(Stability, AcceptanceRule) {
  const bench::StabilityCriteria c{1e-2};
  bench::Outcome o;
  bench::Errors e;
  o.energy_residual = -5e-3;
  EXPECT_TRUE(bench::acceptable(o, e, c));
  o.energy_residual = -2e-2;  // 2 % spurious energy
  EXPECT_FALSE(bench::acceptable(o, e, c));
  o.energy_residual = 0.0;
  e.same_mode = false;
  EXPECT_FALSE(bench::acceptable(o, e, c));
  e.same_mode = true;
  o.status = "integration failed";
  EXPECT_FALSE(bench::acceptable(o, e, c));
}

// The returned step passes with the next two smaller ones, and the step above it (if
// scanned) fails: the scan stops at the first run of three passes from above.
TEST(Stability, ScannerReturnsTheTopOfTheFirstRunOfPasses) {
  bench::Scene base = bench::load_scene(std::string(ASTROJAX_SOURCE_DIR) + "/sweeps/spin_up.toml", {}, 3.0);
  const bench::Scene s = bench::held_at(base, 8.0 * std::numbers::pi);
  const bench::Reference ref = bench::reference(s);
  std::vector<bench::StabilityRow> rows;
  const double h = bench::largest_stable_step(s, "rk4", ref, {1e-2}, 0.1, 1e-4, rows);
  ASSERT_GT(h, 0.0);
  ASSERT_GE(rows.size(), 3u);
  const std::size_t n = rows.size();
  EXPECT_DOUBLE_EQ(rows[n - 3].step, h);
  for (std::size_t k = n - 3; k < n; ++k) EXPECT_TRUE(rows[k].pass) << rows[k].step;
  if (n > 3) {
    EXPECT_FALSE(rows[n - 4].pass);
  }
  // RK4's stability interval on the imaginary axis is |hω| < 2.83: a step of 0.1 s cannot be
  // acceptable at 8π rad/s (hω = 2.5 at the drive frequency alone, and the pendulum's own
  // frequencies add), while 1/2000 s must be.
  EXPECT_LT(h, 0.1);
  EXPECT_GT(h, 5e-4);
}

}  // namespace
