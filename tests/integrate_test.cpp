// The integration driver: step-size control, fixed-step grid, events on the dense output,
// observers, post-step projection with reset, and the failure statuses.
#include "numerics/integrate.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <limits>
#include <new>
#include <numbers>
#include <string>
#include <vector>

#include "numerics_test_problems.hpp"

// Heap-allocation counter for the no-allocation test: replaces the global operator new.
namespace {
std::atomic<long> g_heap_allocs{0};
std::atomic<bool> g_count_allocs{false};
}  // namespace

// GCC pairs the builtin operator new with free() when it inlines these and warns
// (-Wmismatched-new-delete); both sides are replaced here, so the pairing is correct.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t n) {
  if (g_count_allocs.load(std::memory_order_relaxed)) ++g_heap_allocs;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace ajx::numerics {
namespace {

using testing::Kepler;
using testing::max_abs_diff;
using testing::oscillator;

constexpr double kPi = std::numbers::pi;

Vec osc_exact(double t) {
  Vec v(2);
  v << std::cos(t), -std::sin(t);
  return v;
}

Vec osc_start() { return osc_exact(0.0); }

IntegrateResult run(const System& f, Stepper& s, double t0, Vec& y, double t1,
                    const IntegrateOptions& opt, std::span<const Event> ev = {},
                    const StepObserver& obs = {}, const PostStep& post = {}) {
  return integrate(f, s, t0, y, t1, ev, obs, post, opt);
}

IntegrateOptions tight(double tol) {
  IntegrateOptions o;
  o.tol = {tol, tol};
  o.h_max = 10.0;
  return o;
}

// ---------------------------------------------------------------- fixed step

TEST(IntegrateFixed, GridLandsExactlyOnEnd) {
  // y' = 1: every method is exact, so only the grid is tested.
  const System one = [](double, const Vec&, Vec& d) { d[0] = 1.0; };
  for (const char* m : {"euler", "rk4"}) {
    auto s = make_stepper(m);
    IntegrateOptions o;
    o.h_fixed = 0.3;
    std::vector<double> ends;
    const StepObserver obs = [&](const StepView& v) {
      if (!ends.empty()) {
        EXPECT_EQ(v.t0(), ends.back());  // contiguous steps
      }
      ends.push_back(v.t1());
      return true;
    };
    Vec y(1);
    y << 2.0;
    const auto r = run(one, *s, 0.0, y, 1.0, o, {}, obs);
    EXPECT_EQ(r.status, IntegrateStatus::Reached);
    EXPECT_EQ(r.t, 1.0);
    ASSERT_EQ(r.steps, 4);  // 0.3, 0.6, 0.9, then the shortened last step to 1.0
    EXPECT_NEAR(ends[2], 0.9, 1e-15);
    EXPECT_EQ(ends[3], 1.0);
    EXPECT_NEAR(y[0], 3.0, 1e-14);

    // h = 0.1 over [0, 1]: 10 * 0.1 rounds above 1; no sliver step is added.
    o.h_fixed = 0.1;
    y << 0.0;
    const auto r2 = run(one, *s, 0.0, y, 1.0, o);
    EXPECT_EQ(r2.steps, 10);
    EXPECT_EQ(r2.t, 1.0);
  }
}

TEST(IntegrateFixed, DefaultStepIsThePapersHalfMillisecond) {
  auto s = make_stepper("rk4");
  Vec y = osc_start();
  const auto r = run(oscillator, *s, 0.0, y, 1.0, IntegrateOptions{});
  EXPECT_EQ(r.status, IntegrateStatus::Reached);
  EXPECT_EQ(r.steps, 2000);
  // RK4 global error ~ C h^4 T with C ~ 1/120 for the oscillator: ~1e-15 here.
  EXPECT_LT(max_abs_diff(y, osc_exact(1.0)), 1e-13);
}

// ---------------------------------------------------------------- adaptive control

// Tolerance proportionality: both methods propagate the higher-order solution, so the local
// error is O(tol^((p+1)/p)) per step and the number of steps O(tol^(-1/p)): the global error
// is then O(tol). Measured on one Kepler period (e = 0.5, rtol = atol = tol); the fitted
// exponent of err ~ tol^k must be close to 1.
// Size of err/tol: the control is per step, so the global error sums ~N local errors and the
// Kepler flow turns each energy error dE into a phase drift (period T ~ E^(-3/2)) that is
// swept at the pericentre speed sqrt(3): measured err/tol ~ 150 for Dopri5 (~180 steps at
// tol 1e-10; 12 even on a circular orbit) and ~7 for DOP853 (41 steps). The bounds below
// allow 2x (Dopri5) and 4x (DOP853) over that.
TEST(IntegrateAdaptive, GlobalErrorProportionalToTolerance) {
  const Kepler kp;
  for (const char* m : {"dopri5", "dop853"}) {
    std::vector<double> tols = {1e-6, 1e-8, 1e-10, 1e-12}, errs;
    std::printf("  %s:", m);
    for (double tol : tols) {
      auto s = make_stepper(m);
      Vec y = kp.exact(0.0);
      const auto r = run(kp, *s, 0.0, y, Kepler::period, tight(tol));
      ASSERT_EQ(r.status, IntegrateStatus::Reached);
      EXPECT_EQ(r.t, Kepler::period);
      errs.push_back(max_abs_diff(y, kp.exact(Kepler::period)));
      std::printf(" tol %.0e: err %.2e (%ld steps, %ld rejected, %ld rhs)", tol, errs.back(),
                  r.steps, r.rejected, s->rhs_evals());
    }
    std::printf("\n");
    // Least-squares slope of log err against log tol.
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const double n = static_cast<double>(tols.size());
    for (std::size_t i = 0; i < tols.size(); ++i) {
      const double x = std::log10(tols[i]), yv = std::log10(errs[i]);
      sx += x;
      sy += yv;
      sxx += x * x;
      sxy += x * yv;
    }
    const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    std::printf("  %s: fitted exponent err ~ tol^%.3f\n", m, slope);
    EXPECT_NEAR(slope, 1.0, 0.2) << m;
    // Each 100x tighter tolerance gains at least 30x and at most 300x in accuracy.
    for (std::size_t i = 0; i + 1 < errs.size(); ++i) {
      EXPECT_GT(errs[i] / errs[i + 1], 30.0) << m;
      EXPECT_LT(errs[i] / errs[i + 1], 300.0) << m;
    }
    // rtol = atol = 1e-10: the achieved global error is within a small factor of the
    // tolerance (see above), and not suspiciously far below it (a wasteful controller).
    const double factor = std::string(m) == "dopri5" ? 300.0 : 30.0;
    EXPECT_LT(errs[2], factor * 1e-10) << m;
    EXPECT_GT(errs[2], 1e-10 / 100.0) << m;
  }
}

TEST(IntegrateAdaptive, InitialStepHeuristicAndUserStep) {
  const Kepler kp;
  auto s = make_stepper("dopri5");
  Vec y = kp.exact(0.0);
  IntegrateOptions o = tight(1e-9);
  const auto r = run(kp, *s, 0.0, y, Kepler::period, o);
  ASSERT_EQ(r.status, IntegrateStatus::Reached);
  // A sensible start: the first attempts are not all rejected.
  EXPECT_LT(r.rejected, r.steps / 5 + 3);
  EXPECT_GT(r.h_next, 0.0);
  // h_init given: used as is (a too large one is rejected and cut, not a failure).
  auto s2 = make_stepper("dopri5");
  Vec y2 = kp.exact(0.0);
  o.h_init = 1.0;
  const auto r2 = run(kp, *s2, 0.0, y2, Kepler::period, o);
  EXPECT_EQ(r2.status, IntegrateStatus::Reached);
  EXPECT_GE(r2.rejected, 1);
  // Same accuracy class as with the heuristic start (err/tol ~ 200 on this orbit, see above).
  EXPECT_LT(max_abs_diff(y2, kp.exact(Kepler::period)),
            3.0 * max_abs_diff(y, kp.exact(Kepler::period)));
}

TEST(IntegrateAdaptive, StepBoundedByHmax) {
  auto s = make_stepper("dop853");
  Vec y = osc_start();
  IntegrateOptions o;
  o.tol = {1e-3, 1e-3};
  o.h_max = 0.05;
  double hmax_seen = 0.0;
  const StepObserver obs = [&](const StepView& v) {
    hmax_seen = std::max(hmax_seen, v.t1() - v.t0());
    return true;
  };
  const auto r = run(oscillator, *s, 0.0, y, 1.0, o, {}, obs);
  EXPECT_EQ(r.status, IntegrateStatus::Reached);
  EXPECT_LE(hmax_seen, 0.05 * 1.01 + 1e-15);  // the last step may be stretched by <= 1%
  EXPECT_GE(r.steps, 20);
}

TEST(IntegrateAdaptive, BackwardInTime) {
  for (const char* m : {"dopri5", "dop853", "rk4"}) {
    auto s = make_stepper(m);
    Vec y = osc_start();
    IntegrateOptions o = tight(1e-11);
    o.h_fixed = 1e-3;
    const auto r = run(oscillator, *s, 0.0, y, -2.0, o);
    EXPECT_EQ(r.status, IntegrateStatus::Reached) << m;
    EXPECT_EQ(r.t, -2.0);
    EXPECT_LT(max_abs_diff(y, osc_exact(-2.0)), 1e-9) << m;
  }
}

TEST(IntegrateAdaptive, ZeroLengthIntervalIsANoOp) {
  auto s = make_stepper("dopri5");
  Vec y = osc_start();
  const auto r = run(oscillator, *s, 1.0, y, 1.0, IntegrateOptions{});
  EXPECT_EQ(r.status, IntegrateStatus::Reached);
  EXPECT_EQ(r.steps, 0);
  EXPECT_EQ(y, osc_start());
}

// ---------------------------------------------------------------- observers

TEST(IntegrateObserver, StepViewInterpolatesAndStopEndsIntegration) {
  for (const char* m : {"euler", "rk4", "dopri5", "dop853"}) {
    auto s = make_stepper(m);
    Vec y = osc_start();
    IntegrateOptions o = tight(1e-10);
    o.h_max = 0.1;
    o.h_fixed = 1e-3;
    int calls = 0;
    double worst = 0.0, last_t1 = 0.0;
    const StepObserver obs = [&](const StepView& v) {
      EXPECT_EQ(v.t0(), last_t1);
      last_t1 = v.t1();
      Vec mid(2);
      const double tm = 0.5 * (v.t0() + v.t1());
      v.at(tm, mid);
      worst = std::max(worst, max_abs_diff(mid, osc_exact(tm)));
      return ++calls < 25;
    };
    const auto r = run(oscillator, *s, 0.0, y, 100.0, o, {}, obs);
    EXPECT_EQ(r.status, IntegrateStatus::Stopped) << m;
    EXPECT_EQ(r.steps, 25) << m;
    EXPECT_EQ(r.t, last_t1) << m;
    // Euler: h = 1e-3, global error ~ t h / 2 and interpolation ~ h^2: < 1e-4 at t = 0.025.
    EXPECT_LT(worst, std::string(m) == "euler" ? 1e-4 : 1e-9) << m;
    EXPECT_LT(max_abs_diff(y, osc_exact(r.t)), std::string(m) == "euler" ? 1e-4 : 1e-9) << m;
  }
}

// ---------------------------------------------------------------- events

// y'' = -y from y = 1: y = cos t. The first falling zero of y is at pi/2.
TEST(IntegrateEvents, FirstFallingZeroOfCosine) {
  for (const char* m : {"dopri5", "dop853"}) {
    auto s = make_stepper(m);
    Vec y = osc_start();
    const Event ev[] = {{[](double, const Vec& v) { return v[0]; }, -1}};
    double last_obs_t1 = -1.0;
    const StepObserver obs = [&](const StepView& v) {
      last_obs_t1 = v.t1();
      return true;
    };
    const auto r = run(oscillator, *s, 0.0, y, 10.0, tight(1e-12), ev, obs);
    ASSERT_EQ(r.status, IntegrateStatus::Event) << m;
    EXPECT_EQ(r.event_index, 0);
    EXPECT_NEAR(r.t, kPi / 2, 1e-10) << m;
    EXPECT_LT(max_abs_diff(y, osc_exact(r.t)), 1e-10) << m;
    // The returned state lies on the far side of the crossing (or on it), to event_tol.
    EXPECT_LE(y[0], 0.0);
    EXPECT_EQ(last_obs_t1, r.t);  // the observer saw the truncated step
    std::printf("  %s: event at pi/2 %+.2e, %ld steps\n", m, r.t - kPi / 2, r.steps);
  }
}

TEST(IntegrateEvents, FixedStepMethodsLocateOnHermite) {
  // RK4 at h = 1e-3: Hermite interpolation error ~ h^4 / 384 ~ 3e-15.
  auto s = make_stepper("rk4");
  Vec y = osc_start();
  IntegrateOptions o;
  o.h_fixed = 1e-3;
  const Event ev[] = {{[](double, const Vec& v) { return v[0]; }, 0}};
  const auto r = run(oscillator, *s, 0.0, y, 10.0, o, ev);
  ASSERT_EQ(r.status, IntegrateStatus::Event);
  EXPECT_NEAR(r.t, kPi / 2, 1e-12);
}

TEST(IntegrateEvents, DirectionFilter) {
  for (const char* m : {"dopri5", "dop853"}) {
    auto s = make_stepper(m);
    Vec y = osc_start();
    // Rising zeros only: the falling one at pi/2 is skipped, the rising one at 3 pi/2 fires.
    const Event ev[] = {{[](double, const Vec& v) { return v[0]; }, +1}};
    const auto r = run(oscillator, *s, 0.0, y, 10.0, tight(1e-12), ev);
    ASSERT_EQ(r.status, IntegrateStatus::Event) << m;
    EXPECT_NEAR(r.t, 1.5 * kPi, 1e-10) << m;
    EXPECT_GT(y[1], 0.99);  // y' = -sin t = +1 there
  }
}

TEST(IntegrateEvents, EarliestOfTwoIsChosen) {
  // cos t = c falls at acos(c). Pairs: far apart (pi/3, pi/2: usually different steps) and
  // 1.2e-6 apart (always the same step, so the second root search is confined to
  // [t0, first root]).
  struct Pair {
    double c_early, c_late;
  };
  for (const char* m : {"dopri5", "dop853"}) {
    for (auto [c_early, c_late] : {Pair{0.5, 0.0}, Pair{0.5 + 1e-6, 0.5}}) {
      for (int order = 0; order < 2; ++order) {
        auto s = make_stepper(m);
        Vec y = osc_start();
        const auto g = [](double c) { return [c](double, const Vec& v) { return v[0] - c; }; };
        const Event early{g(c_early), 0}, late{g(c_late), 0};
        const Event ev[] = {order == 0 ? late : early, order == 0 ? early : late};
        const auto r = run(oscillator, *s, 0.0, y, 10.0, tight(1e-12), ev);
        ASSERT_EQ(r.status, IntegrateStatus::Event);
        EXPECT_EQ(r.event_index, order == 0 ? 1 : 0) << m;
        EXPECT_NEAR(r.t, std::acos(c_early), 1e-10) << m;
      }
    }
  }
}

// A g that is exactly 0 at t0 does not fire there; only a genuine crossing after leaving zero
// counts. g = y' = -sin t starts at 0, leaves it downwards and crosses upwards at pi.
TEST(IntegrateEvents, ZeroAtStartDoesNotFire) {
  for (const char* m : {"dopri5", "dop853", "rk4", "euler"}) {
    auto s = make_stepper(m);
    Vec y = osc_start();
    IntegrateOptions o = tight(1e-12);
    o.h_fixed = 1e-4;
    const Event ev[] = {{[](double, const Vec& v) { return v[1]; }, 0}};
    const auto r = run(oscillator, *s, 0.0, y, 10.0, o, ev);
    ASSERT_EQ(r.status, IntegrateStatus::Event) << m;
    // Euler: the zero of y' moves by O(h) (y' error ~ h t / 2).
    EXPECT_NEAR(r.t, kPi, std::string(m) == "euler" ? 1e-3 : 1e-9) << m;
  }
}

// The same when the crossing lies inside the very first step: the sign just after t0 is
// probed on the dense output, so the crossing at pi inside [0, 4] is found.
TEST(IntegrateEvents, ZeroAtStartCrossingInsideFirstStep) {
  auto s = make_stepper("dop853");
  Vec y = osc_start();
  IntegrateOptions o = tight(1e-2);
  o.h_init = 4.0;
  const Event ev[] = {{[](double, const Vec& v) { return v[1]; }, 0}};
  const auto r = run(oscillator, *s, 0.0, y, 10.0, o, ev);
  ASSERT_EQ(r.status, IntegrateStatus::Event);
  EXPECT_EQ(r.steps, 1);
  EXPECT_NEAR(r.t, kPi, 1e-2);
}

// Restarting at a located root does not see the same crossing again: the returned state is
// past the crossing. The next zero of cos, at 3 pi/2, is found instead.
TEST(IntegrateEvents, RestartAtEventFindsNextCrossing) {
  for (const char* m : {"dopri5", "dop853"}) {
    auto s = make_stepper(m);
    Vec y = osc_start();
    const Event ev[] = {{[](double, const Vec& v) { return v[0]; }, 0}};
    const auto r1 = run(oscillator, *s, 0.0, y, 10.0, tight(1e-12), ev);
    ASSERT_EQ(r1.status, IntegrateStatus::Event);
    IntegrateOptions o = tight(1e-12);
    o.h_init = r1.h_next;
    const auto r2 = run(oscillator, *s, r1.t, y, 10.0, o, ev);
    ASSERT_EQ(r2.status, IntegrateStatus::Event);
    EXPECT_NEAR(r2.t, 1.5 * kPi, 1e-10) << m;
  }
}

// A mode switch at an event: a new f from the event state (integrate resets the stepper, so
// no FSAL stage of the old f is reused). y'' = -y until y = 0 at pi/2 (y' = -1), then
// y'' = -4 y: y = -sin(2 (t - pi/2)) / 2.
TEST(IntegrateEvents, ModeSwitchAtEvent) {
  const System stiffer = [](double, const Vec& v, Vec& d) {
    d[0] = v[1];
    d[1] = -4.0 * v[0];
  };
  for (const char* m : {"dopri5", "dop853"}) {
    auto s = make_stepper(m);
    Vec y = osc_start();
    const Event ev[] = {{[](double, const Vec& v) { return v[0]; }, -1}};
    const auto r1 = run(oscillator, *s, 0.0, y, 10.0, tight(1e-12), ev);
    ASSERT_EQ(r1.status, IntegrateStatus::Event);
    const auto r2 = run(stiffer, *s, r1.t, y, 3.0, tight(1e-12));
    ASSERT_EQ(r2.status, IntegrateStatus::Reached);
    const double u = 2.0 * (3.0 - kPi / 2);
    EXPECT_NEAR(y[0], -0.5 * std::sin(u), 1e-10) << m;
    EXPECT_NEAR(y[1], -std::cos(u), 1e-10) << m;
  }
}

TEST(IntegrateEvents, BackwardIntegrationDirectionIsAlongTheIntegration) {
  auto s = make_stepper("dopri5");
  Vec y = osc_start();
  // Going backwards from t = 0, cos falls through zero at t = -pi/2 (along the integration).
  const Event ev[] = {{[](double, const Vec& v) { return v[0]; }, -1}};
  const auto r = run(oscillator, *s, 0.0, y, -10.0, tight(1e-12), ev);
  ASSERT_EQ(r.status, IntegrateStatus::Event);
  EXPECT_NEAR(r.t, -kPi / 2, 1e-10);
}

TEST(IntegrateEvents, TimeEventIsExact) {
  // g = t - 1.234: located to event_tol.
  auto s = make_stepper("dop853");
  Vec y = osc_start();
  const Event ev[] = {{[](double t, const Vec&) { return t - 1.234; }, 0}};
  IntegrateOptions o = tight(1e-8);
  const auto r = run(oscillator, *s, 0.0, y, 10.0, o, ev);
  ASSERT_EQ(r.status, IntegrateStatus::Event);
  EXPECT_NEAR(r.t, 1.234, 2 * o.event_tol);
  EXPECT_GE(r.t, 1.234);  // far side of the crossing
}

// ---------------------------------------------------------------- post-step hook and reset

// Guard samples inside a step (IntegrateOptions::event_samples). y = (t, t²) is integrated
// exactly by every method and its dense output (polynomials of degree <= 2), so the error control
// lets one step span [0, 1]. g = 0.01 − (y0 − 0.5)² is negative at both step ends and positive on
// (0.4, 0.6): an excursion strictly inside the step, seen only if a sample falls in (0.4, 0.6).
// k equally spaced interior samples sit at j / (k + 1): k = 2 puts them at 1/3 and 2/3 (both
// outside), k = 5 puts one at 1/2.
namespace excursion {
const System f = [](double t, const Vec&, Vec& d) {
  d[0] = 1.0;
  d[1] = 2.0 * t;
};
double g(double, const Vec& v) { return 0.01 - (v[0] - 0.5) * (v[0] - 0.5); }
IntegrateOptions one_step(int samples) {
  IntegrateOptions o;
  o.tol = {1e-6, 1e-6};
  o.h_init = 1.0;
  o.h_fixed = 1.0;
  o.h_max = 1.0;
  o.event_samples = samples;
  return o;
}
}  // namespace excursion

TEST(IntegrateEvents, InteriorSamplesSeeAnExcursionInsideOneStep) {
  for (const char* m : {"rk4", "dopri5", "dop853"}) {
    for (int dirn : {0, +1, -1}) {
      const Event ev[] = {{excursion::g, dirn}};
      for (int k : {0, 2}) {
        auto s = make_stepper(m);
        Vec y = Vec::Zero(2);
        const auto r = run(excursion::f, *s, 0.0, y, 1.0, excursion::one_step(k), ev);
        EXPECT_EQ(r.status, IntegrateStatus::Reached) << m << " k = " << k << ": no sample in (0.4, 0.6)";
        EXPECT_EQ(r.steps, 1) << m;
      }
      auto s = make_stepper(m);
      Vec y = Vec::Zero(2);
      const auto r = run(excursion::f, *s, 0.0, y, 1.0, excursion::one_step(5), ev);
      ASSERT_EQ(r.status, IntegrateStatus::Event) << m << " direction " << dirn;
      // Rising at 0.4 (direction 0 or +1: the first crossing); falling at 0.6 (direction -1).
      const double root = dirn < 0 ? 0.6 : 0.4;
      EXPECT_NEAR(r.t, root, 2 * excursion::one_step(5).event_tol) << m;
      // The far side of the crossing: g has changed sign (or is 0) at the returned state.
      const double g_end = excursion::g(r.t, y);
      EXPECT_TRUE(dirn < 0 ? g_end <= 0.0 : g_end >= 0.0) << m << " g = " << g_end;
      EXPECT_NEAR(y[0], r.t, 1e-14) << m;  // the state is the dense output there
      EXPECT_EQ(r.steps, 1) << m;
    }
  }
}

// With h_bound, a step uses the fewest samples that keep them h_bound / (k + 1) apart: a bound of
// 6 s with k = 5 asks for samples 1 s apart, which the step of 1 s already satisfies (none
// taken, the excursion stays hidden); a bound of 1 s asks for all five.
TEST(IntegrateEvents, InteriorSamplesFollowTheStepBound) {
  const Event ev[] = {{excursion::g, 0}};
  for (double bound : {6.0, 1.0}) {
    auto s = make_stepper("dop853");
    Vec y = Vec::Zero(2);
    IntegrateOptions o = excursion::one_step(5);
    o.h_bound = [bound](double, const Vec&) { return bound; };
    const auto r = run(excursion::f, *s, 0.0, y, 1.0, o, ev);
    EXPECT_EQ(r.status, bound > 1.0 ? IntegrateStatus::Reached : IntegrateStatus::Event) << bound;
    if (bound == 1.0) {
      EXPECT_NEAR(r.t, 0.4, 2 * o.event_tol);
    }
  }
}

// Of two events, the one crossing in the earlier sub-interval ends the step, even if the other
// would have crossed between the step's ends only (the old rule would have found just that one).
TEST(IntegrateEvents, InteriorSamplesFindTheEarliestCrossing) {
  const Event ev[] = {{[](double, const Vec& v) { return v[0] - 0.9; }, 0}, {excursion::g, 0}};
  for (int k : {0, 5}) {
    auto s = make_stepper("dop853");
    Vec y = Vec::Zero(2);
    const auto r = run(excursion::f, *s, 0.0, y, 1.0, excursion::one_step(k), ev);
    ASSERT_EQ(r.status, IntegrateStatus::Event);
    EXPECT_EQ(r.event_index, k == 0 ? 0 : 1) << k;
    EXPECT_NEAR(r.t, k == 0 ? 0.9 : 0.4, 2e-13) << k;
  }
}

// Guard samples are first taken on the stepper's cheap interpolant (DOP853: cubic Hermite) and a
// step goes on to the dense output only when they show a sign change. A stepper whose cheap
// interpolant lies shows what each half does: one that invents a sign change (y moved to the
// centre of an excursion the trajectory never reaches) still ends without an event, because the
// dense output confirms nothing; one that hides the excursion (always y0) misses it, so the
// detection really runs on the cheap interpolant. The honest DOP853 finds it at 0.4
// (InteriorSamplesSeeAnExcursionInsideOneStep).
namespace lying {
class Stepper final : public numerics::Stepper {
 public:
  explicit Stepper(std::function<void(double theta, Vec& out)> cheap)
      : inner_(make_stepper("dop853")), cheap_(std::move(cheap)) {}
  std::string_view name() const override { return "lying dop853"; }
  int order() const override { return inner_->order(); }
  bool adaptive() const override { return inner_->adaptive(); }
  double attempt(const System& f, double t, const Vec& y, double h, Vec& y_new, const Tolerances& tol) override {
    y0_ = y;
    return inner_->attempt(f, t, y, h, y_new, tol);
  }
  void accept(const System& f) override { inner_->accept(f); }
  void dense(const System& f, double theta, Vec& out) override { inner_->dense(f, theta, out); }
  bool cheap_interpolant(const System&, double theta, Vec& out) override {
    out = y0_;
    cheap_(theta, out);
    return true;
  }
  void reset() override { inner_->reset(); }

 private:
  std::unique_ptr<numerics::Stepper> inner_;
  std::function<void(double, Vec&)> cheap_;
  Vec y0_;
};
}  // namespace lying

TEST(IntegrateEvents, CheapSamplesAreConfirmedOnTheDenseOutput) {
  // Positive only for y0 in (1.4, 1.6); the trajectory has y0 = t <= 1.
  const Event far[] = {{[](double, const Vec& v) { return 0.01 - (v[0] - 1.5) * (v[0] - 1.5); }, 0}};
  lying::Stepper invents([](double, Vec& out) { out[0] = 1.5; });
  Vec y = Vec::Zero(2);
  const auto r = run(excursion::f, invents, 0.0, y, 1.0, excursion::one_step(5), far);
  EXPECT_EQ(r.status, IntegrateStatus::Reached) << "an event the trajectory does not have, at " << r.t;

  const Event ev[] = {{excursion::g, 0}};
  lying::Stepper hides([](double, Vec&) {});
  y = Vec::Zero(2);
  EXPECT_EQ(run(excursion::f, hides, 0.0, y, 1.0, excursion::one_step(5), ev).status, IntegrateStatus::Reached);
}

// Conservative advancement (Event::change_bound). x' = 1 is integrated exactly, so only h_bound
// (0.2 s, k = 3: samples 0.05 s apart) keeps the steps short; g = 0.01 − (x − 5)² is positive on
// (4.9, 5.1) only, a crossing and a recrossing 0.2 s apart. |Δg| = |Δx| |2 (x0 − 5) + Δx| ≤
// e (2 |x0 − 5| + e) bounds its change over a step whose interpolant moves x by at most e. Far
// from 5 the steps are certified and grow past the bound; the step that holds the excursion is
// not, and its samples (0.05 s apart however long it is) see the rise at 4.9. A certificate that
// lies (0: nothing can change) lets that step go unsampled, and the excursion is missed.
TEST(IntegrateEvents, ConservativeAdvancementSkipsOnlyStepsThatCannotCross) {
  const System f = [](double, const Vec&, Vec& d) { d[0] = 1.0; };
  const auto g = [](double, const Vec& v) { return 0.01 - (v[0] - 5.0) * (v[0] - 5.0); };
  const auto bound = [](double, double, const Vec& y0, const Vec& e) {
    return e[0] * (2.0 * std::abs(y0[0] - 5.0) + e[0]);
  };
  const auto lie = [](double, double, const Vec&, const Vec&) { return 0.0; };
  IntegrateOptions o;
  o.tol = {1e-9, 1e-9};
  o.h_init = 0.01;
  o.h_max = 100.0;
  o.event_samples = 3;
  o.h_bound = [](double, const Vec&) { return 0.2; };
  const auto solve = [&](const Event& ev) {
    auto s = make_stepper("dop853");
    Vec y = Vec::Zero(1);
    return run(f, *s, 0.0, y, 10.0, o, std::span<const Event>(&ev, 1));
  };
  const auto capped = solve({g, 0, {}});
  ASSERT_EQ(capped.status, IntegrateStatus::Event);
  EXPECT_NEAR(capped.t, 4.9, 1e-12);
  const auto certified = solve({g, 0, bound});
  ASSERT_EQ(certified.status, IntegrateStatus::Event) << "the certified steps skipped the crossing";
  EXPECT_NEAR(certified.t, 4.9, 1e-12);
  EXPECT_GE(capped.steps, 4.9 / 0.2);  // every step bounded by 0.2 s
  EXPECT_LT(4 * certified.steps, capped.steps) << "the certified steps were still bounded";
  EXPECT_EQ(solve({g, 0, lie}).status, IntegrateStatus::Reached);  // the samples were needed
}

// A unit vector rotating at angular speed w: y' = w (-y2, y1). The projection y <- y/|y|
// after every step keeps |y| = 1 to round-off, every step starts from the projected state
// (seen through the observer at the step start), and the phase stays accurate.
TEST(IntegratePostStep, ProjectionKeepsUnitNormAndResetsFsal) {
  const double w = 3.0;
  const System rot = [w](double, const Vec& v, Vec& d) {
    d[0] = -w * v[1];
    d[1] = w * v[0];
  };
  for (const char* m : {"euler", "rk4", "dopri5", "dop853"}) {
    auto s = make_stepper(m);
    Vec y(2);
    y << 1.0, 0.0;
    IntegrateOptions o = tight(1e-10);
    o.h_max = 0.1;
    o.h_fixed = 1e-3;
    double worst_start = 0.0;
    long projections = 0;
    const StepObserver obs = [&](const StepView& v) {
      Vec a(2);
      v.at(v.t0(), a);
      worst_start = std::max(worst_start, std::abs(a.norm() - 1.0));
      return true;
    };
    const PostStep project = [&](double, Vec& v) {
      v /= v.norm();
      ++projections;
      return true;
    };
    const double T = 5.0;
    const auto r = run(rot, *s, 0.0, y, T, o, {}, obs, project);
    ASSERT_EQ(r.status, IntegrateStatus::Reached) << m;
    EXPECT_EQ(projections, r.steps);
    EXPECT_LT(worst_start, 1e-14) << m;
    EXPECT_LT(std::abs(y.norm() - 1.0), 1e-14) << m;
    // Phase: euler O(h) = w^2 h T / 2 ~ 2e-2 radians; the others as the tolerance.
    const double phase = std::atan2(y[1], y[0]) - std::remainder(w * T, 2 * kPi);
    EXPECT_LT(std::abs(std::remainder(phase, 2 * kPi)), std::string(m) == "euler" ? 3e-2 : 1e-8)
        << m;
    if (std::string(m) == "dopri5") {
      // Every step starts cold after reset(): 7 evaluations per accepted step, 6 per rejected
      // retry (k1 kept), plus 2 for the initial-step heuristic.
      EXPECT_EQ(s->rhs_evals(), 2 + 7 * r.steps + 6 * r.rejected);
    }
  }
}

// Without a reset (hook returns false) Dopri5 reuses its FSAL stage: 6 evaluations per
// attempt after the first. A hook that claims a change without making one only costs
// evaluations; the result is identical.
TEST(IntegratePostStep, NoResetKeepsFsalAndSpuriousResetIsHarmless) {
  const Kepler kp;
  auto s1 = make_stepper("dopri5"), s2 = make_stepper("dopri5");
  Vec y1 = kp.exact(0.0), y2 = kp.exact(0.0);
  const auto o = tight(1e-9);
  const auto r1 =
      run(kp, *s1, 0.0, y1, Kepler::period, o, {}, {}, [](double, Vec&) { return false; });
  const auto r2 =
      run(kp, *s2, 0.0, y2, Kepler::period, o, {}, {}, [](double, Vec&) { return true; });
  EXPECT_EQ(s1->rhs_evals(), 2 + 1 + 6 * (r1.steps + r1.rejected));
  EXPECT_EQ(r1.steps, r2.steps);
  EXPECT_EQ(max_abs_diff(y1, y2), 0.0);
  EXPECT_GT(s2->rhs_evals(), s1->rhs_evals());
}

// ---------------------------------------------------------------- failures

// y' = 1 until t = 0.5, NaN after: NonFinite, y is the last good state (y = 1 + t exactly,
// the methods are exact for y' = 1), reached close to 0.5.
TEST(IntegrateFailure, NaNRhsGivesNonFiniteWithLastGoodState) {
  const System f = [](double t, const Vec&, Vec& d) {
    d[0] = t < 0.5 ? 1.0 : std::numeric_limits<double>::quiet_NaN();
  };
  for (const char* m : {"euler", "rk4", "dopri5", "dop853"}) {
    auto s = make_stepper(m);
    Vec y(1);
    y << 1.0;
    IntegrateOptions o;
    o.h_fixed = 0.01;
    const auto r = run(f, *s, 0.0, y, 1.0, o);
    EXPECT_EQ(r.status, IntegrateStatus::NonFinite) << m;
    EXPECT_TRUE(y.allFinite()) << m;
    EXPECT_LE(r.t, 0.5) << m;
    EXPECT_GT(r.t, s->adaptive() ? 0.5 - 1e-9 : 0.5 - 0.02) << m;
    EXPECT_NEAR(y[0], 1.0 + r.t, 1e-13) << m;
  }
}

TEST(IntegrateFailure, NonFiniteInitialState) {
  auto s = make_stepper("dopri5");
  Vec y = osc_start();
  y[1] = std::numeric_limits<double>::infinity();
  const auto r = run(oscillator, *s, 0.0, y, 1.0, IntegrateOptions{});
  EXPECT_EQ(r.status, IntegrateStatus::NonFinite);
  EXPECT_EQ(r.steps, 0);
}

// y' = y^2, y(0) = 1: y = 1/(1 - t) blows up at t = 1. Integrating towards t = 2 must end
// with a failure status near the singularity, in bounded work, never hang. Fixed-step methods
// step over t = 1 and overflow (NonFinite); adaptive ones follow the solution into the
// singularity with h ~ (1 - t) until h < h_min (StepUnderflow). Their blow-up time is off by
// ~1e-10 (global error at tol 1e-9), so the end may lie slightly beyond 1.
TEST(IntegrateFailure, BlowUpEndsWithUnderflowOrNonFinite) {
  const System f = [](double, const Vec& v, Vec& d) { d[0] = v[0] * v[0]; };
  for (const char* m : {"euler", "rk4", "dopri5", "dop853"}) {
    auto s = make_stepper(m);
    Vec y(1);
    y << 1.0;
    double worst_rel = 0.0;  // relative error of y while 1 - t > 1e-3
    const StepObserver obs = [&](const StepView& v) {
      if (1.0 - v.t1() > 1e-3) {
        Vec a(1);
        v.at(v.t1(), a);
        worst_rel = std::max(worst_rel, std::abs(a[0] * (1.0 - v.t1()) - 1.0));
      }
      return true;
    };
    const auto t_start = std::chrono::steady_clock::now();
    const auto r = run(f, *s, 0.0, y, 2.0, IntegrateOptions{}, {}, obs);
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    EXPECT_TRUE(r.status == IntegrateStatus::StepUnderflow ||
                r.status == IntegrateStatus::NonFinite)
        << m << ": " << to_string(r.status);
    EXPECT_TRUE(y.allFinite()) << m;
    EXPECT_LT(secs, 1.0) << m;
    if (s->adaptive()) {
      EXPECT_NEAR(r.t, 1.0, 1e-6) << m;
      EXPECT_GT(y[0], 1e6) << m;
      EXPECT_LT(worst_rel, 1e-6) << m;
    } else {
      EXPECT_NEAR(r.t, 1.0, 0.05) << m;
    }
    std::printf("  %s: %s at t = %.12f, y = %.3e, %ld steps, %ld rejected\n", m,
                to_string(r.status).c_str(), r.t, y[0], r.steps, r.rejected);
  }
}

TEST(IntegrateFailure, MaxStepsAndHmin) {
  const Kepler kp;
  auto s = make_stepper("dopri5");
  Vec y = kp.exact(0.0);
  IntegrateOptions o = tight(1e-10);
  o.max_steps = 10;
  auto r = run(kp, *s, 0.0, y, Kepler::period, o);
  EXPECT_EQ(r.status, IntegrateStatus::MaxSteps);
  EXPECT_EQ(r.steps + r.rejected, 10);
  EXPECT_LT(max_abs_diff(y, kp.exact(r.t)), 1e-9);  // a valid intermediate state

  Vec y2 = kp.exact(0.0);
  o = tight(1e-12);
  o.h_min = 0.5;  // the accuracy needs far smaller steps
  r = run(kp, *s, 0.0, y2, Kepler::period, o);
  EXPECT_EQ(r.status, IntegrateStatus::StepUnderflow);
  EXPECT_EQ(r.steps, 0);
  EXPECT_EQ(y2, kp.exact(0.0));

  // Fixed step: MaxSteps too.
  auto e = make_stepper("euler");
  Vec y3 = kp.exact(0.0);
  IntegrateOptions of;
  of.max_steps = 7;
  r = run(kp, *e, 0.0, y3, 1.0, of);
  EXPECT_EQ(r.status, IntegrateStatus::MaxSteps);
  EXPECT_EQ(r.steps, 7);
  EXPECT_NEAR(r.t, 7 * of.h_fixed, 1e-15);
}

// The step loop allocates nothing: stage vectors are fixed-capacity members, event values
// live on the stack (up to 16 events), StepView is a value. Measured over whole integrate()
// calls with events, an observer that interpolates, and a projection hook.
TEST(IntegratePerformance, NoHeapAllocationInIntegrate) {
  const Kepler kp;
  const System f = kp;
  const Event ev[] = {{[](double, const Vec& v) { return v[1] + 10.0; }, 0},
                      {[](double t, const Vec&) { return t - 5.5; }, +1}};
  Vec probe(4);
  const StepObserver obs = [&probe](const StepView& v) {
    v.at(0.5 * (v.t0() + v.t1()), probe);
    return true;
  };
  const PostStep post = [](double, Vec&) { return true; };
  // The counter works (a direct call, which the compiler may not elide).
  g_heap_allocs = 0;
  g_count_allocs = true;
  ::operator delete(::operator new(16));
  g_count_allocs = false;
  ASSERT_EQ(g_heap_allocs.load(), 1);
  for (const char* m : {"euler", "rk4", "dopri5", "dop853"}) {
    auto s = make_stepper(m);
    Vec y = kp.exact(0.0);
    IntegrateOptions o = tight(1e-10);
    o.event_samples = 3;  // interior guard samples use the same stack storage
    g_heap_allocs = 0;
    g_count_allocs = true;
    const auto r = integrate(f, *s, 0.0, y, 10.0, ev, obs, post, o);
    g_count_allocs = false;
    EXPECT_EQ(r.status, IntegrateStatus::Event) << m;
    EXPECT_NEAR(r.t, 5.5, 1e-12) << m;
    EXPECT_EQ(g_heap_allocs.load(), 0) << m;
  }
}

// Throughput of the driver (printed): Kepler over 10 periods at tol 1e-10.
TEST(IntegratePerformance, Timing) {
  const Kepler kp;
  for (const char* m : {"dopri5", "dop853"}) {
    auto s = make_stepper(m);
    Vec y = kp.exact(0.0);
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = run(kp, *s, 0.0, y, 10 * Kepler::period, tight(1e-10));
    const double us =
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(r.status, IntegrateStatus::Reached);
    std::printf("  %s: %ld steps, %ld rhs, %.1f us (%.1f ns/step)\n", m, r.steps, s->rhs_evals(),
                us, 1e3 * us / r.steps);
  }
}

TEST(IntegrateStatusNames, AllNamed) {
  for (auto st : {IntegrateStatus::Reached, IntegrateStatus::Event, IntegrateStatus::StepUnderflow,
                  IntegrateStatus::NonFinite, IntegrateStatus::MaxSteps, IntegrateStatus::Stopped})
    EXPECT_NE(to_string(st), "unknown");
}

}  // namespace
}  // namespace ajx::numerics
