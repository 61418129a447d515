// The implicit Radau IIA stepper: its order on a smooth problem, and what it is for, a stiff
// problem where explicit methods at the same step blow up.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "numerics/integrate.hpp"
#include "numerics/radau_iia.hpp"
#include "numerics_test_problems.hpp"

namespace {

using namespace ajx::numerics;

Vec run_fixed(const System& f, const char* method, Vec y, double T, double h) {
  auto s = make_stepper(method);
  IntegrateOptions opt;
  opt.h_fixed = h;
  integrate(f, *s, 0.0, y, T, {}, {}, {}, opt);
  return y;
}

TEST(RadauIIA, FactoryAndProperties) {
  auto s = make_stepper("radau_iia");
  EXPECT_EQ(s->name(), "radau_iia");
  EXPECT_EQ(s->order(), 5);
  EXPECT_FALSE(s->adaptive());
}

// Global order 2s - 1 = 5 on the oscillator over one period: halving h divides the error by
// 2^5. The steps keep the error between ~1e-4 and ~1e-10, far above round-off.
TEST(RadauIIA, GlobalOrderFive) {
  const System f = ajx::numerics::testing::oscillator;
  Vec y0(2);
  y0 << 1.0, 0.0;
  const double T = 2.0 * std::numbers::pi;
  double prev = 0.0;
  std::printf("Radau IIA global errors:");
  for (int n : {8, 16, 32, 64}) {
    const Vec y = run_fixed(f, "radau_iia", y0, T, T / n);
    Vec exact(2);
    exact << 1.0, 0.0;
    const double err = ajx::numerics::testing::max_abs_diff(y, exact);
    std::printf(" %.3e", err);
    if (prev > 0.0) {
      EXPECT_NEAR(std::log2(prev / err), 5.0, 0.3) << n;
    }
    prev = err;
  }
  std::printf("\n");
}

// Prothero-Robinson, y' = -λ (y - cos t) - sin t, y(0) = 1, exact y = cos t, λ = 1e6. At
// h = 0.05, hλ = 5e4: far outside any explicit method's stability region (RK4: |hλ| < 2.79),
// while the L-stable, stiffly accurate Radau IIA has a global error of the order of its stage
// order, O(h^(s+1)) = O(h^4) = 6e-6 at most; with hλ >> 1 it is smaller still.
TEST(RadauIIA, StiffProblemWhereExplicitMethodsBlowUp) {
  constexpr double lambda = 1e6;
  const System f = [](double t, const Vec& y, Vec& dy) {
    dy.resize(1);
    dy[0] = -lambda * (y[0] - std::cos(t)) - std::sin(t);
  };
  Vec y0(1);
  y0 << 1.0;
  const double h = 0.05, T = 1.0;
  const Vec y = run_fixed(f, "radau_iia", y0, T, h);
  EXPECT_LT(std::abs(y[0] - std::cos(T)), std::pow(h, 4));
  const Vec e = run_fixed(f, "rk4", y0, T, h);
  EXPECT_FALSE(std::isfinite(e[0]) && std::abs(e[0] - std::cos(T)) < 1.0);
}

}  // namespace
