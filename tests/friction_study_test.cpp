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

// The stick-slip passage over 10 s, and the bead's end position L1 from dop853 at rtol.
bench::Scene passage() {
  return bench::load_scene(std::string(ASTROJAX_SOURCE_DIR) + "/sweeps/scenes/stick_slip_passage.toml", {}, 10.0);
}
double end_L1(const bench::Scene& s, double rtol) {
  const bench::Outcome o = bench::run_point(s, {"dop853", rtol, 0.0}, 1, 0.0);
  EXPECT_EQ(o.status, "ok");
  return bench::bead_position(s, o.final);
}

// tanh(ṡ/ε) differs from sgn ṡ only where |ṡ| <~ ε, and the creep where the kinetic model
// holds the bead is ṡ ~ ε: the deviation from the kinetic model is O(ε). 100x smaller ε must
// give a much smaller deviation (at least 10x, allowing for the O(ε) constant to vary).
TEST(FrictionStudy, RegularisedTendsToTheKineticModel) {
  const bench::Scene base = passage();
  const double L1 = end_L1(bench::kinetic(base), 1e-11);
  double dev[2];
  int k = 0;
  for (double eps : {1e-2, 1e-4}) dev[k++] = std::abs(end_L1(bench::regularised(base, eps), 1e-10) - L1);
  EXPECT_LT(dev[1], 0.1 * dev[0]);
  EXPECT_LT(dev[1], 1e-3);  // 1 mm of the 0.83 m string
}

// The Stribeck law differs from stick-slip in three ways: it creeps at ṡ ~ ε where stick-slip
// holds the bead (O(ε)); its peak falls short of μ_s by ~ Δ (kε/v_s)² with k a few (an earlier
// breakaway); and while sliding its coefficient exceeds μ_k by Δ e^{-(ṡ/v_s)²} (O(v_s)). With
// ε = v_s/100 the first and the last shrink with v_s and the second stays at ~ Δ (5/100)² ≈ 2e-4:
// 10x smaller v_s must bring the bead's end position much closer to the event-driven one.
TEST(FrictionStudy, StribeckTendsToTheStickSlipModel) {
  const bench::Scene base = passage();
  const double L1 = end_L1(base, 1e-11);
  double dev[2];
  int k = 0;
  for (double v_s : {1e-2, 1e-3}) {
    bench::Scene r = bench::regularised(base, v_s / 100, physics::Friction::Stribeck);
    r.model.layers.stribeck_speed = v_s;
    dev[k++] = std::abs(end_L1(r, 1e-8) - L1);
  }
  std::printf("measured Stribeck (ε = v_s/100) against stick-slip: |ΔL1| %.3e m at v_s = 1e-2, %.3e m at 1e-3\n",
              dev[0], dev[1]);
  EXPECT_LT(dev[1], 0.1 * dev[0]);
  EXPECT_LT(dev[1], 1e-3);  // 1 mm of the 0.83 m string
}

}  // namespace
