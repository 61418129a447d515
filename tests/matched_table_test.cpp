// The matched comparison's bookkeeping (src/bench/matched_table.*): which point of a method
// counts at an error, and the ratios the targets are stated in. No timing is asserted: the
// CPU times here are made up, the rules are what is checked.
#include <gtest/gtest.h>

#include <cmath>

#include "bench/matched_table.hpp"

using ajx::bench::MatchedPoint;

namespace {
MatchedPoint point(std::string method, std::string family, double rtol, double error, double cpu_ms,
                   std::string status = "ok", bool same_mode = true) {
  MatchedPoint p;
  p.scene = "s";
  p.horizon = 10.0;
  p.method = std::move(method);
  p.family = std::move(family);
  p.rtol = rtol;
  p.error = error;
  p.status = std::move(status);
  p.same_mode = same_mode;
  p.cpu = {1e-3 * cpu_ms * 1.5, 1e-3 * cpu_ms, 1e-3 * cpu_ms * 1.2};  // the minimum is cpu_ms
  return p;
}
}  // namespace

TEST(MatchedTable, CheapestPointReachingTheError) {
  const std::vector<MatchedPoint> pts = {
      point("peer", "guarantee", 1e-5, 2e-6, 0.5),        // too inaccurate for 1e-6
      point("peer", "guarantee", 1e-6, 8e-7, 0.9),
      point("peer", "guarantee", 1e-7, 9e-8, 0.8),        // cheaper and more accurate: kept
      point("peer", "guarantee", 1e-8, 9e-9, 0.1, "failed"),          // failed: never counts
      point("peer", "guarantee", 1e-9, 9e-10, 0.2, "ok", false),      // wrong final mode: never counts
      point("peer", "no guarantee", 1e-5, 1e-7, 0.05),    // another family: not mixed in
  };
  const MatchedPoint* p = ajx::bench::cheapest(pts, "peer", "guarantee", 1e-6);
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->rtol, 1e-7);
  EXPECT_DOUBLE_EQ(p->cpu_min(), 0.8e-3);
  EXPECT_DOUBLE_EQ(p->cpu_median(), 0.96e-3);
  EXPECT_EQ(ajx::bench::cheapest(pts, "peer", "guarantee", 1e-9), nullptr);
}

TEST(MatchedTable, RatiosPerFamily) {
  const std::vector<MatchedPoint> pts = {
      point("astrojax dop853 (default)", "guarantee", 1e-6, 1e-7, 1.1),
      point("hand a", "guarantee", 1e-6, 1e-7, 2.2),
      point("hand b", "guarantee", 1e-6, 1e-7, 1.65),
      point("astrojax dop853 (k=0, no bound)", "no guarantee", 1e-6, 1e-7, 1.0),
      point("hand a", "no guarantee", 1e-6, 1e-7, 0.8),
      point("hand CVODE Adams + CVodeRootInit", "no guarantee", 1e-6, 1e-7, 12.0),
  };
  const ajx::bench::MatchedRatios r = ajx::bench::ratios(pts, 1e-6);
  EXPECT_DOUBLE_EQ(r.with_guarantee, 1.5);  // the fastest peer with the guarantee, b
  EXPECT_EQ(r.fastest_with, "hand b");
  EXPECT_DOUBLE_EQ(r.without_guarantee, 0.8);
  EXPECT_EQ(r.fastest_without, "hand a");
  EXPECT_DOUBLE_EQ(r.cvode_over_plain, 12.0);
  EXPECT_NEAR(r.cvode_over_default, 12.0 / 1.1, 1e-12);
  EXPECT_NEAR(r.guarantee_cost, 0.1, 1e-12);
  // Nothing reaches 1e-9: every ratio is NaN, not a number that looks like a result.
  const ajx::bench::MatchedRatios none = ajx::bench::ratios(pts, 1e-9);
  EXPECT_TRUE(std::isnan(none.with_guarantee) && std::isnan(none.guarantee_cost) && std::isnan(none.cvode_over_plain));
}
