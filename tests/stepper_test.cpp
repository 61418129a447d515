// Steppers in isolation: factory, error norm, measured orders of the propagated solution
// (global and local) and of the dense output, FSAL bookkeeping and reset().
#include "numerics/stepper.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "numerics_test_problems.hpp"

namespace ajx::numerics {
namespace {

using testing::Kepler;
using testing::max_abs_diff;
using testing::oscillator;

// Tolerances that make an embedded error estimate irrelevant (pure fixed-step use).
const Tolerances kLoose{1e300, 1e300};

// Fixed-step run: N steps of h = T/N on the grid t_k = k h, by attempt/accept only.
Vec run_fixed(Stepper& s, const System& f, Vec y, double T, int N) {
  const double h = T / N;
  Vec y_new(y.size());
  for (int k = 0; k < N; ++k) {
    s.attempt(f, k * h, y, h, y_new, kLoose);
    s.accept(f);
    y = y_new;
  }
  return y;
}

// Orders log2(e_i / e_{i+1}) between successive halvings.
std::vector<double> orders(const std::vector<double>& errs) {
  std::vector<double> p;
  for (std::size_t i = 0; i + 1 < errs.size(); ++i) p.push_back(std::log2(errs[i] / errs[i + 1]));
  return p;
}

void print_row(const std::string& what, const std::vector<double>& errs) {
  std::printf("  %-34s errors:", what.c_str());
  for (double e : errs) std::printf(" %.3e", e);
  std::printf("  orders:");
  for (double p : orders(errs)) std::printf(" %.3f", p);
  std::printf("\n");
}

TEST(StepperFactory, KnownNamesAndProperties) {
  struct Expect {
    const char* name;
    int order;
    bool adaptive;
  };
  for (auto [name, order, adaptive] : {Expect{"euler", 1, false}, Expect{"rk4", 4, false},
                                       Expect{"dopri5", 5, true}, Expect{"dop853", 8, true}}) {
    auto s = make_stepper(name);
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(s->name(), name);
    EXPECT_EQ(s->order(), order);
    EXPECT_EQ(s->adaptive(), adaptive);
    EXPECT_EQ(s->rhs_evals(), 0);
    EXPECT_NE(stepper_names().find(name), std::string_view::npos);
  }
}

TEST(StepperFactory, UnknownNameThrowsListingAllowedValues) {
  try {
    make_stepper("rk45");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("rk45"), std::string::npos) << msg;
    for (const char* n : {"euler", "rk4", "dopri5", "dop853"})
      EXPECT_NE(msg.find(n), std::string::npos) << msg;
  }
}

TEST(ErrorNorm, MixedRmsByHand) {
  Vec err(2), y(2), yn(2);
  err << 1e-6, -3e-6;
  y << 1.0, -2.0;
  yn << 3.0, 0.5;
  const Tolerances tol{1e-3, 1e-6};
  // s = atol + rtol max(|y|, |y_new|) = (1e-6 + 3e-3, 1e-6 + 2e-3).
  const double r0 = 1e-6 / 3.001e-3, r1 = 3e-6 / 2.001e-3;
  EXPECT_NEAR(error_norm(err, y, yn, tol), std::sqrt(0.5 * (r0 * r0 + r1 * r1)), 1e-15);
  EXPECT_EQ(error_norm(Vec::Zero(2), y, yn, tol), 0.0);
}

// Global order p: the error after a fixed time T scales as h^p. Step ranges are chosen from
// measured error tables (printed) so that (a) the higher-order terms h^(p+1) are already
// small (the pairwise order has settled) and (b) the smallest error is >= ~1e4 x the
// round-off floor (~1e-15 relative for these N). The Kepler orbit with e = 0.5 has its
// nearest complex singularity only ~0.45 time units from the pericentre, so DOP853's
// asymptotic range there (h << 0.45) lies entirely below round-off in double precision
// (measured pairwise orders 7.9, 6.9, 7.6, then round-off); its global order is therefore
// measured on the oscillator, where the range h = 0.79..0.2 is clean, and its nonlinear order
// conditions are checked by the local-error test below.
TEST(StepperOrder, GlobalConvergenceOrder) {
  struct Case {
    const char* method;
    bool kepler;  // else the oscillator over 10 periods
    std::vector<int> N;
  };
  const std::vector<Case> cases = {
      // Kepler e = 0.5, one period (the state returns to the start).
      {"euler", true, {65536, 131072, 262144}},  // pre-asymptotic below N ~ 3e4
      {"rk4", true, {1024, 2048, 4096}},         // errors 7e-8 .. 3e-10
      {"dopri5", true, {512, 1024, 2048}},       // errors 5e-9 .. 4e-12
      // Oscillator y'' = -y over 10 periods (T = 20 pi).
      {"euler", false, {81920, 163840, 327680}},
      {"rk4", false, {1280, 2560, 5120}},
      {"dopri5", false, {1280, 2560, 5120}},  // errors 5e-9 .. 5e-12
      {"dop853", false, {80, 160, 320}},      // errors 6e-7 .. 9e-12 (640: 3e-14, round-off)
  };
  const Kepler kp;
  std::printf("Global order (fixed step)\n");
  for (const auto& c : cases) {
    auto s = make_stepper(c.method);
    std::vector<double> errs;
    for (int N : c.N) {
      if (c.kepler) {
        const Vec y = run_fixed(*s, kp, kp.exact(0.0), Kepler::period, N);
        errs.push_back(max_abs_diff(y, kp.exact(Kepler::period)));
      } else {
        Vec y0(2), ex(2);
        y0 << 1.0, 0.0;
        const double T = 20.0 * std::numbers::pi;
        ex << std::cos(T), -std::sin(T);
        errs.push_back(max_abs_diff(run_fixed(*s, oscillator, y0, T, N), ex));
      }
    }
    print_row(std::string(c.method) + (c.kepler ? " kepler e=0.5" : " oscillator"), errs);
    for (double p : orders(errs)) EXPECT_LT(std::abs(p - s->order()), 0.3) << c.method;
  }
}

// Local error of one step from the exact state: O(h^(p+1)). On the nonlinear Kepler problem
// this depends on every order condition (all rooted trees up to order p), not only on the
// stability polynomial as for the oscillator. Start at the apocentre (t = pi), where the
// solution is smoothest; ranges again from measured tables (smallest error ~1e-13 for DOP853,
// ~500 x the round-off of one step).
TEST(StepperOrder, LocalErrorOrderOnKepler) {
  struct Case {
    const char* method;
    std::vector<double> h;
  };
  const std::vector<Case> cases = {{"euler", {0.5, 0.25, 0.125}},
                                   {"rk4", {0.125, 0.0625, 0.03125}},
                                   {"dopri5", {0.25, 0.125, 0.0625}},
                                   {"dop853", {0.5, 0.25}}};
  const Kepler kp;
  const double t0 = std::numbers::pi;
  std::printf("Local error order (one step from the apocentre), expect p+1\n");
  for (const auto& c : cases) {
    auto s = make_stepper(c.method);
    std::vector<double> errs;
    for (double h : c.h) {
      Vec y1(4);
      s->attempt(kp, t0, kp.exact(t0), h, y1, kLoose);
      errs.push_back(max_abs_diff(y1, kp.exact(t0 + h)));
    }
    print_row(c.method, errs);
    for (double p : orders(errs)) EXPECT_LT(std::abs(p - (s->order() + 1)), 0.3) << c.method;
  }
}

// Dense output at theta in (0, 1) over one step from the exact state: the interpolant of
// order q has error O(h^(q+1)) when the step's own error is smaller: Hermite (q = 3) on RK4:
// h^4 (the endpoint error h^5 is negligible); Dopri5's continuous extension (q = 4): h^5;
// DOP853's (q = 7): h^8. For Euler the endpoint error O(h^2) dominates the Hermite
// interpolant, so the observed order is min(p + 1, q + 1) = 2.
TEST(StepperOrder, DenseOutputOrder) {
  struct Case {
    const char* method;
    int expected;  // exponent of h in the interpolation error
    std::vector<double> h;
  };
  const std::vector<Case> cases = {{"euler", 2, {0.25, 0.125, 0.0625}},
                                   {"rk4", 4, {0.25, 0.125, 0.0625}},
                                   {"dopri5", 5, {0.25, 0.125, 0.0625}},
                                   {"dop853", 8, {0.5, 0.25}}};  // 0.125: 6e-15, round-off
  const Kepler kp;
  const double t0 = std::numbers::pi;
  std::printf("Dense output order at mid-step (one step from the apocentre)\n");
  for (const auto& c : cases) {
    for (double theta : {0.5, 0.3}) {
      auto s = make_stepper(c.method);
      std::vector<double> errs;
      for (double h : c.h) {
        Vec y1(4), yd(4);
        s->attempt(kp, t0, kp.exact(t0), h, y1, kLoose);
        s->accept(kp);
        s->dense(kp, theta, yd);
        errs.push_back(max_abs_diff(yd, kp.exact(t0 + theta * h)));
      }
      print_row(std::string(c.method) + " theta=" + std::to_string(theta).substr(0, 3), errs);
      for (double p : orders(errs)) EXPECT_LT(std::abs(p - c.expected), 0.3) << c.method;
    }
  }
}

TEST(StepperDense, InterpolatesStepEnds) {
  const Kepler kp;
  for (const char* m : {"euler", "rk4", "dopri5", "dop853"}) {
    auto s = make_stepper(m);
    const Vec y0 = kp.exact(0.3);
    Vec y1(4), d(4);
    s->attempt(kp, 0.3, y0, 0.1, y1, kLoose);
    s->accept(kp);
    s->dense(kp, 0.0, d);
    EXPECT_EQ(max_abs_diff(d, y0), 0.0) << m;
    s->dense(kp, 1.0, d);
    EXPECT_LT(max_abs_diff(d, y1), 1e-15) << m;
  }
}

// DOP853's cheap interpolant (for guard samples) is the cubic Hermite through (y0, f0) and
// (y1, f1). On y' = 4t³ from 0 (y = t⁴, integrated exactly by the order-8 step and by the
// order-7 dense output), Hermite interpolation misses by exactly (y⁽⁴⁾/4!) h⁴ θ²(1 − θ)² =
// h⁴ θ²(1 − θ)², so its value is (θh)⁴ − h⁴ θ²(1 − θ)², to round-off; on y' = 3t² (a cubic) it
// is exact. No stage beyond f(t1, y1) is spent: that one is the next step's k1.
TEST(StepperDense, Dop853CheapInterpolantIsTheCubicHermite) {
  for (int degree : {3, 4}) {
    const System f = [degree](double t, const Vec&, Vec& d) { d[0] = degree * std::pow(t, degree - 1); };
    auto s = make_stepper("dop853");
    const double h = 0.5;
    Vec y0 = Vec::Zero(1), y1(1), out(1), dense(1);
    s->attempt(f, 0.0, y0, h, y1, kLoose);
    s->accept(f);
    const long evals = s->rhs_evals();
    for (double theta : {0.0, 0.25, 0.5, 0.8, 1.0}) {
      ASSERT_TRUE(s->cheap_interpolant(f, theta, out));
      const double exact = std::pow(theta * h, degree);
      const double miss = degree == 4 ? std::pow(h, 4) * theta * theta * (1 - theta) * (1 - theta) : 0.0;
      EXPECT_NEAR(out[0], exact - miss, 1e-15) << degree << " theta " << theta;
    }
    EXPECT_EQ(s->rhs_evals(), evals + 1) << "only f(t1, y1)";
    s->dense(f, 0.5, dense);
    EXPECT_NEAR(dense[0], std::pow(0.5 * h, degree), 1e-15);
  }
  for (const char* m : {"euler", "rk4", "dopri5", "radau_iia"}) {
    Vec out(1);
    EXPECT_FALSE(make_stepper(m)->cheap_interpolant({}, 0.5, out)) << m;
  }
}

// RHS evaluations per step: Euler 1, RK4 4, Dopri5 6 (+1 on the first step, FSAL), DOP853
// 12 (its f(t1, y1) is the next k1). Lazy dense output: +1 (Hermite f1, then reused as the
// next k1, so a step with dense output costs no more than without overall), +3 for DOP853 (its
// stage 13 = f(t1, y1) again becomes the next k1).
TEST(StepperCount, RhsEvaluationsAndFsal) {
  const Kepler kp;
  struct Case {
    const char* m;
    long first, next;
  };
  for (auto [m, first, next] :
       {Case{"euler", 1, 1}, Case{"rk4", 4, 4}, Case{"dopri5", 7, 6}, Case{"dop853", 12, 12}}) {
    auto s = make_stepper(m);
    Vec y = kp.exact(0.0), y1(4), d(4);
    const double h = 0.01;
    s->attempt(kp, 0.0, y, h, y1, kLoose);
    s->accept(kp);
    EXPECT_EQ(s->rhs_evals(), first) << m;
    y = y1;
    s->attempt(kp, h, y, h, y1, kLoose);
    s->accept(kp);
    EXPECT_EQ(s->rhs_evals(), first + next) << m;
    // Dense output over the second step, twice: lazy extra stages are computed once.
    s->dense(kp, 0.5, d);
    s->dense(kp, 0.7, d);
    const long extra = std::string(m) == "dop853" ? 4 : (s->adaptive() ? 0 : 1);
    EXPECT_EQ(s->rhs_evals(), first + next + extra) << m;
    // The next step reuses f(t1, y1) whenever it was computed.
    y = y1;
    s->attempt(kp, 2 * h, y, h, y1, kLoose);
    const long reused = std::string(m) == "dopri5" ? 6 : (extra > 0 ? next - 1 : next);
    EXPECT_EQ(s->rhs_evals(), first + next + extra + reused) << m;
  }
}

// A rejected attempt is retried from the same (t, y): k1 is not evaluated again.
TEST(StepperCount, RetryAfterRejectionReusesFirstStage) {
  const Kepler kp;
  for (const char* m : {"dopri5", "dop853"}) {
    auto s = make_stepper(m);
    const Vec y = kp.exact(0.0);
    Vec y1(4);
    s->attempt(kp, 0.0, y, 0.5, y1, Tolerances{1e-12, 1e-12});
    const long after_first = s->rhs_evals();
    s->attempt(kp, 0.0, y, 0.1, y1, Tolerances{1e-12, 1e-12});
    EXPECT_EQ(s->rhs_evals() - after_first, after_first - 1) << m;
  }
}

// After reset() (a mode switch: new f, same state) the FSAL stage of the old f must not be
// used: the step equals the one of a fresh stepper with the new f. Without reset the stepper
// only recognises a changed state, not a changed f (documented in derivative_cache.hpp).
TEST(StepperReset, FsalStageDroppedAfterReset) {
  const Kepler kp;
  // The "new mode": Kepler with a doubled central mass.
  const System f2 = [&](double t, const Vec& y, Vec& dy) {
    kp(t, y, dy);
    dy.tail(2) *= 2.0;
  };
  for (const char* m : {"euler", "rk4", "dopri5", "dop853"}) {
    auto s = make_stepper(m);
    const Vec y0 = kp.exact(0.0);
    Vec y1(4), d(4), a(4), b(4);
    const double h = 0.05;
    s->attempt(kp, 0.0, y0, h, y1, kLoose);
    s->accept(kp);
    s->dense(kp, 0.5, d);  // makes f(t1, y1) available to all methods
    s->reset();
    s->attempt(f2, h, y1, h, a, kLoose);
    auto fresh = make_stepper(m);
    fresh->attempt(f2, h, y1, h, b, kLoose);
    EXPECT_EQ(max_abs_diff(a, b), 0.0) << m;
  }
}

// A state changed behind the stepper's back (no reset) is still detected by the key check:
// a projected y must not start from the stale FSAL stage.
TEST(StepperReset, ChangedStateIsNotReused) {
  const Kepler kp;
  auto s = make_stepper("dopri5");
  Vec y1(4), a(4), b(4);
  s->attempt(kp, 0.0, kp.exact(0.0), 0.05, y1, kLoose);
  s->accept(kp);
  y1[0] += 1e-3;
  s->attempt(kp, 0.05, y1, 0.05, a, kLoose);
  auto fresh = make_stepper("dopri5");
  fresh->attempt(kp, 0.05, y1, 0.05, b, kLoose);
  EXPECT_EQ(max_abs_diff(a, b), 0.0);
}

// attempt(f, t, y, h, y, tol) with y_new aliasing y gives the same result.
TEST(StepperAlias, OutputMayAliasInput) {
  const Kepler kp;
  for (const char* m : {"euler", "rk4", "dopri5", "dop853"}) {
    auto s1 = make_stepper(m), s2 = make_stepper(m);
    Vec y = kp.exact(0.0), ref(4);
    s1->attempt(kp, 0.0, y, 0.05, ref, kLoose);
    s2->attempt(kp, 0.0, y, 0.05, y, kLoose);
    EXPECT_EQ(max_abs_diff(y, ref), 0.0) << m;
  }
}

// Embedded error estimates are asymptotically of the stated orders: Dopri5's 4th-order
// estimate scales as h^5, DOP853's combined estimate err5^2 / sqrt(err5^2 + 0.01 err3^2) as
// h^8 once 0.01 err3^2 dominates (h <~ 0.1 here; measured 10.9, 9.2, 8.4 above that).
TEST(StepperError, EmbeddedEstimateScaling) {
  const Kepler kp;
  struct Case {
    const char* m;
    int expected;
    double t0;
    std::vector<double> h;
  };
  for (const auto& c : {Case{"dopri5", 5, std::numbers::pi, {0.2, 0.1, 0.05}},
                        Case{"dop853", 8, 0.0, {0.1, 0.05, 0.025}}}) {
    auto s = make_stepper(c.m);
    std::vector<double> errs;
    for (double h : c.h) {
      Vec y1(4);
      errs.push_back(s->attempt(kp, c.t0, kp.exact(c.t0), h, y1, Tolerances{0.0, 1.0}));
    }
    print_row(std::string(c.m) + " error estimate", errs);
    for (double p : orders(errs)) EXPECT_LT(std::abs(p - c.expected), 0.3) << c.m;
  }
}

// Throughput (printed, not asserted): ns per step and per RHS call on Kepler.
TEST(StepperTiming, NanosecondsPerStep) {
  const Kepler kp;
  const System f = kp;
  for (const char* m : {"euler", "rk4", "dopri5", "dop853"}) {
    auto s = make_stepper(m);
    const int N = 200000;
    const auto t0 = std::chrono::steady_clock::now();
    const Vec y = run_fixed(*s, f, kp.exact(0.0), 100 * Kepler::period, N);
    const double ns =
        std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
    std::printf("  %-7s %7.1f ns/step, %5.1f ns per RHS call (incl. stepper overhead)\n", m, ns / N,
                ns / s->rhs_evals());
    EXPECT_TRUE(y.allFinite());
  }
}

}  // namespace
}  // namespace ajx::numerics
