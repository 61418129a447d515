// The regularised friction law tends to the kinetic (Filippov) model as ε -> 0.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "bench/friction_study.hpp"
#include "bench/scene_file.hpp"

namespace {

using namespace ajx;

TEST(FrictionStudy, RegularisedSceneHasNoStuckStart) {
  const bench::Scene base =
      bench::load_scene(std::string(ASTROJAX_SOURCE_DIR) + "/sweeps/scenes/stick_slip_passage.toml", {}, 1.0);
  ASSERT_EQ(base.initial.contact.mode, physics::Mode::Stuck);
  const bench::Scene r = bench::regularised(base, 1e-3);
  EXPECT_EQ(r.model.layers.friction, physics::Friction::Regularised);
  EXPECT_DOUBLE_EQ(r.model.layers.regularisation, 1e-3);
  EXPECT_EQ(r.initial.contact.mode, physics::Mode::Sliding);
  EXPECT_EQ(bench::kinetic(base).model.layers.friction, physics::Friction::Kinetic);
}

// tanh(ṡ/ε) differs from sgn ṡ only where |ṡ| <~ ε, and the creep where the kinetic model
// holds the bead is ṡ ~ ε: the deviation from the kinetic model is O(ε). 100x smaller ε must
// give a much smaller deviation (at least 10x, allowing for the O(ε) constant to vary).
TEST(FrictionStudy, RegularisedTendsToTheKineticModel) {
  const bench::Scene base =
      bench::load_scene(std::string(ASTROJAX_SOURCE_DIR) + "/sweeps/scenes/stick_slip_passage.toml", {}, 10.0);
  const bench::Scene kin = bench::kinetic(base);
  const bench::Outcome ref = bench::run_point(kin, {"dop853", 1e-11, 0.0}, 1, 0.0);
  ASSERT_EQ(ref.status, "ok");
  const double L1 = bench::bead_position(kin, ref.final);
  double dev[2];
  int k = 0;
  for (double eps : {1e-2, 1e-4}) {
    const bench::Scene r = bench::regularised(base, eps);
    const bench::Outcome o = bench::run_point(r, {"dop853", 1e-10, 0.0}, 1, 0.0);
    ASSERT_EQ(o.status, "ok");
    dev[k++] = std::abs(bench::bead_position(r, o.final) - L1);
  }
  EXPECT_LT(dev[1], 0.1 * dev[0]);
  EXPECT_LT(dev[1], 1e-3);  // 1 mm of the 0.83 m string
}

// The Stribeck law creeps at ṡ ~ ε where the stick-slip model holds the bead, so its deviation
// from the stick-slip model has an O(ε) part; its sliding coefficient exceeds μ_k by
// (μ_s − μ_k) e^{-(ṡ/v_s)²}, an O(v_s) part. With v_s = 10 ε both shrink together.
TEST(FrictionStudy, StribeckTendsToTheStickSlipModel) {
  const bench::Scene base =
      bench::load_scene(std::string(ASTROJAX_SOURCE_DIR) + "/sweeps/scenes/stick_slip_passage.toml", {}, 10.0);
  const bench::Outcome ref = bench::run_point(base, {"dop853", 1e-11, 0.0}, 1, 0.0);
  ASSERT_EQ(ref.status, "ok");
  const double L1 = bench::bead_position(base, ref.final);
  double dev[2];
  int k = 0;
  for (double eps : {1e-2, 1e-4}) {
    bench::Scene r = bench::regularised(base, eps, physics::Friction::Stribeck);
    r.model.layers.stribeck_speed = 10 * eps;
    const bench::Outcome o = bench::run_point(r, {"dop853", 1e-10, 0.0}, 1, 0.0);
    ASSERT_EQ(o.status, "ok");
    dev[k++] = std::abs(bench::bead_position(r, o.final) - L1);
  }
  std::printf("measured Stribeck (v_s = 10 ε) against stick-slip: |ΔL1| %.3e m at ε = 1e-2, %.3e m at 1e-4\n", dev[0],
              dev[1]);
  EXPECT_LT(dev[1], 0.1 * dev[0]);
  EXPECT_LT(dev[1], 1e-3);
}

}  // namespace
