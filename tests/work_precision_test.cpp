// The work-precision measurements: errors against the reference, tolerance proportionality
// of the achieved error, the reference floor and the sensitivity measure, on the shipped
// locked-circular scene over a short horizon (2 s, to keep the suite fast).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bench/scene_file.hpp"
#include "bench/work_precision.hpp"

namespace {

using namespace ajx;

bench::Scene locked(double horizon) {
  return bench::load_scene(std::string(ASTROJAX_SOURCE_DIR) + "/sweeps/scenes/locked_circular.toml", {}, horizon);
}

TEST(WorkPrecision, CompareTakesTheWorseBall) {
  physics::State a, b;
  b.y(physics::idx::r1 + 0) = 3e-3;   // |Δr1| = 5e-3 (3-4-5)
  b.y(physics::idx::r1 + 1) = 4e-3;
  b.y(physics::idx::r2 + 2) = -1e-3;  // |Δr2| = 1e-3
  b.y(physics::idx::v2 + 0) = 2.0;
  const bench::Errors e = bench::compare(a, b);
  EXPECT_DOUBLE_EQ(e.position, 5e-3);
  EXPECT_DOUBLE_EQ(e.velocity, 2.0);
  EXPECT_TRUE(e.same_mode);
  b.contact.mode = physics::Mode::Slack;
  EXPECT_FALSE(bench::compare(a, b).same_mode);
}

TEST(WorkPrecision, ReferenceIsResolvedAndTheLockedOrbitIsNotChaotic) {
  const bench::Scene s = locked(2.0);
  const bench::Reference ref = bench::reference(s);
  ASSERT_EQ(ref.run.status, "ok");
  EXPECT_EQ(ref.run.mode_switches, 0);  // the bead stays stuck: a smooth scene
  // DOPRI5 at rtol 1e-12 over ~1.5e4 steps accumulates at most ~1e-12 x |r| per unit time
  // (|r| ~ 0.8 m): the two references must agree far below the 1e-9 m figures we quote.
  EXPECT_LT(ref.floor, 1e-10);
  EXPECT_GT(ref.floor, 0.0);  // two different methods never agree bitwise
  // A damped, driven limit cycle: a kick neither grows exponentially nor vanishes in 2 s
  // (drag rate c_D/m ~ 0.1 /s).
  EXPECT_FALSE(ref.chaotic());
  EXPECT_GT(ref.amplification, 0.05);
  EXPECT_LT(ref.amplification, 1e2);
}

// The chaos detector (separation of nearby runs, bench::Separation) on a known regular scene
// and on the shipped chaotic one, over the benchmark's 10 s horizon. The locked orbit is a
// damped, driven limit cycle: a kick decays at about the drag rate (λ ≈ −0.06 /s measured),
// far below the threshold 3 ln 4 / 7.5 s = 0.55 /s. The tumbling swing is a double pendulum
// let go from high up: its kick grows exponentially (λ ≈ 1 /s measured, 2e4-fold in 10 s).
TEST(WorkPrecision, ChaosDetectorSaysRegularAndChaotic) {
  const bench::Separation regular = bench::separation(locked(10.0));
  EXPECT_FALSE(regular.chaotic()) << regular.lyapunov;
  EXPECT_LT(regular.lyapunov, 0.5 * regular.threshold);
  EXPECT_LT(regular.amplification, 10.0);
  const bench::Scene swing =
      bench::load_scene(std::string(ASTROJAX_SOURCE_DIR) + "/sweeps/scenes/tumbling_swing.toml", {}, 10.0);
  const bench::Separation chaos = bench::separation(swing);
  EXPECT_TRUE(chaos.chaotic()) << chaos.lyapunov;
  EXPECT_GT(chaos.lyapunov, 1.5 * chaos.threshold);
  EXPECT_GT(chaos.amplification, 1e3);
  EXPECT_GE(chaos.fitted, 4);
}

// A chaotic scene is measured by statistics: they converge where the pointwise error cannot.
TEST(WorkPrecision, StatisticsOfTheChaoticSceneConverge) {
  const bench::Scene swing =
      bench::load_scene(std::string(ASTROJAX_SOURCE_DIR) + "/sweeps/scenes/tumbling_swing.toml", {}, 10.0);
  const bench::Statistics ref = bench::statistics(swing, {"dop853/lab", 1e-13, 0.0});
  const bench::Statistics run = bench::statistics(swing, {"dopri5", 1e-8, 0.0});
  EXPECT_FALSE(ref.orbit_class.empty());
  EXPECT_EQ(run.orbit_class, ref.orbit_class);
  // The balls swing out to about the string length: mean radius some 0.3 m; at rtol 1e-8 it is
  // measured to 1e-7 m (4.5e-8 m measured), the pointwise position error being 2e-5 m.
  EXPECT_GT(ref.mean_radius, 0.1);
  EXPECT_LT(std::abs(run.mean_radius - ref.mean_radius), 1e-5);
  EXPECT_LT(std::abs(run.omega_ball - ref.omega_ball), 1e-4);
}

TEST(WorkPrecision, DormandPrinceErrorIsProportionalToTheTolerance) {
  const bench::Scene s = locked(2.0);
  const bench::Reference ref = bench::reference(s);
  double prev = INFINITY;
  for (double rtol : {1e-5, 1e-7, 1e-9}) {
    const bench::Outcome o = bench::run_point(s, {"dopri5", rtol, 0.0}, 1, 0.0);
    ASSERT_EQ(o.status, "ok");
    const double err = bench::compare(o.final, ref.run.final).position;
    // Tolerance proportionality: 100x tighter gives ~100x smaller global error; one decade
    // of slack either way for the step-size controller's safety factors.
    if (std::isfinite(prev)) {
      EXPECT_GT(prev / err, 10.0) << rtol;
      EXPECT_LT(prev / err, 1000.0) << rtol;
    }
    prev = err;
  }
}

TEST(WorkPrecision, FixedStepErrorFollowsTheOrderOfRk4) {
  const bench::Scene s = locked(2.0);
  const bench::Reference ref = bench::reference(s);
  // Steps where the RK4 error (1e-7..1e-9 m) is far above the reference floor.
  const double e1 = bench::compare(bench::run_point(s, {"rk4", 0.0, 4e-3}, 1, 0.0).final, ref.run.final).position;
  const double e2 = bench::compare(bench::run_point(s, {"rk4", 0.0, 2e-3}, 1, 0.0).final, ref.run.final).position;
  ASSERT_GT(e2, 1e3 * ref.floor);
  // Halving h divides the global error by 2^4; the projection after each step may only
  // help, so the observed order lies in [4 - 0.5, 5.5].
  const double order = std::log2(e1 / e2);
  EXPECT_GT(order, 3.5);
  EXPECT_LT(order, 5.5);
}

TEST(WorkPrecision, RepeatsAreBoundedByTheBudget) {
  const bench::Scene s = locked(0.5);
  EXPECT_EQ(bench::run_point(s, {"dopri5", 1e-6, 0.0}, 3, 100.0).repeats, 3);
  EXPECT_EQ(bench::run_point(s, {"dopri5", 1e-6, 0.0}, 3, 0.0).repeats, 1);
  const bench::Outcome o = bench::run_point(s, {"dopri5", 1e-6, 0.0}, 3, 100.0);
  EXPECT_LE(o.cpu_min, o.cpu_median);
}

TEST(WorkPrecision, CsvLineHasTheHeadersColumns) {
  const bench::Scene s = locked(0.5);
  bench::Reference ref;
  bench::Row row{s.name, "dopri5", "rtol", 1e-6, bench::run_point(s, {"dopri5", 1e-6, 0.0}, 1, 0.0), {}, 0.0, {}, true, NAN};
  const auto count = [](const std::string& x) { return std::count(x.begin(), x.end(), ','); };
  EXPECT_EQ(count(bench::csv_line(row, ref)), count(bench::csv_header()));
}

// The landing is extrapolated from the last sample before it with L2 + L̇2 τ = d, whose error
// is ½ L̈2 τ² / L̇2 with τ < sample_dt: the error in ω_fall falls as sample_dt², 100x per
// decade (30x..300x allows for where the landing falls inside the sample interval).
TEST(WorkPrecision, FallExtrapolationErrorIsQuadraticInTheSampleStep) {
  const bench::Scene s =
      bench::load_scene(std::string(ASTROJAX_SOURCE_DIR) + "/sweeps/scenes/fall_ramp.toml", {}, 25.0);
  const bench::Setting set{"dop853", 1e-10, 0.0};
  const bench::Fall fine = bench::first_fall(s, set, 1e-4);
  const bench::Fall mid = bench::first_fall(s, set, 1e-3);
  const bench::Fall coarse = bench::first_fall(s, set, 1e-2);
  ASSERT_TRUE(fine.found && mid.found && coarse.found);
  const double ratio = std::abs(coarse.omega - fine.omega) / std::abs(mid.omega - fine.omega);
  EXPECT_GT(ratio, 30.0);
  EXPECT_LT(ratio, 300.0);
  // The bead lands during the ramp (ω_m between 3 rad/s and 6π).
  EXPECT_GT(fine.omega, 3.0);
  EXPECT_LT(fine.omega, 6.0 * std::numbers::pi);
}

// The lock's loss is interpolated linearly in the lag λ between the two samples that bracket
// λ − λ0 = π. The crossing lies inside that interval, so t is within one sample step τ of the
// finest run's; the interpolation's error, ½ |λ̈| s (τ − s)/λ̇ for a crossing s after a sample, is
// second order: 100x per decade of τ when s/τ is the same in both runs, but s/τ differs between
// runs and moves one ratio by a few times either way, so at least 10x is asserted (23x measured).
// The lock is lost on the ramp (between 4π and 6π), after the 2 s hold.
TEST(WorkPrecision, LockLossInterpolationErrorIsQuadraticInTheSampleStep) {
  const bench::Scene s =
      bench::load_scene(std::string(ASTROJAX_SOURCE_DIR) + "/sweeps/scenes/lock_loss_ramp.toml", {}, 15.0);
  const bench::Setting set{"dop853", 1e-10, 0.0};
  const bench::Fall fine = bench::lock_loss(s, set, 1e-4);
  const bench::Fall mid = bench::lock_loss(s, set, 1e-3);
  const bench::Fall coarse = bench::lock_loss(s, set, 1e-2);
  ASSERT_TRUE(fine.found && mid.found && coarse.found);
  EXPECT_LT(std::abs(coarse.t - fine.t), 1e-2);
  EXPECT_LT(std::abs(mid.t - fine.t), 1e-3);
  EXPECT_GT(std::abs(coarse.omega - fine.omega) / std::abs(mid.omega - fine.omega), 10.0);
  EXPECT_GT(fine.t, 2.0);
  EXPECT_GT(fine.omega, 4.0 * std::numbers::pi);
  EXPECT_LT(fine.omega, 6.0 * std::numbers::pi);
}

}  // namespace
