// Constraint handling on the locked orbit (stuck: two constraints): what each variant must do.
#include <gtest/gtest.h>

#include "bench/constraint_study.hpp"
#include "bench/scene_file.hpp"

namespace {

using namespace ajx;

TEST(ConstraintStudy, BaumgarteDampsAndProjectionRemovesTheDrift) {
  const bench::Scene s =
      bench::load_scene(std::string(ASTROJAX_SOURCE_DIR) + "/sweeps/scenes/locked_circular.toml", {}, 5.0);
  const bench::Setting set{"dopri5", 1e-6, 0.0};
  const bench::ConstraintRun none = bench::run_constraint_variant(s, {"none", 0.0, false}, set, 1);
  const bench::ConstraintRun baum = bench::run_constraint_variant(s, {"baumgarte", 10.0, false}, set, 1);
  const bench::ConstraintRun proj = bench::run_constraint_variant(s, {"projection", 0.0, true}, set, 1);
  ASSERT_EQ(none.status, "ok");
  ASSERT_EQ(baum.status, "ok");
  ASSERT_EQ(proj.status, "ok");
  // Without stabilisation C̈ = 0 only up to the truncation error, which C integrates twice:
  // the drift grows over the run. With C̈ + 2αĊ + α²C = 0 it is damped at the rate α = 10/s
  // (a time constant of 0.1 s against 5 s): the drift at the end is far smaller.
  EXPECT_GT(none.end_drift, 1e-7);
  EXPECT_LT(baum.end_drift, 1e-2 * none.end_drift);
  // Projection leaves at most projection_tol (1e-12 m) after every step, the last included.
  EXPECT_LE(proj.end_drift, s.run.projection_tol);
}

}  // namespace
