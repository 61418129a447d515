// The step bound from the guards' time scales (sim/step_bound.hpp, [integrator] max_step =
// "auto"). Events are sign changes of a guard between step ends: a guard that crosses zero and
// comes back inside one step is not seen. In a slack flight the balls fly on parabolas, which
// an adaptive method integrates exactly, so nothing but a bound keeps its steps short, while the
// string's Taut guard L1 + L2 − l oscillates with the top turning at ω_m.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <fmt/format.h>
#include <optional>

#include "config/config.hpp"
#include "physics/mode_transitions.hpp"
#include "sim/simulation.hpp"
#include "sim/step_bound.hpp"

namespace {

using namespace ajx;
using physics::Vec3;

constexpr double kOmega = 10.0 * std::numbers::pi;  // ω_m [rad/s]: the top turns once per 0.2 s
constexpr double kR = 0.01;                          // R [m]
constexpr double kL1 = 0.40;                         // |r1 − a| at t = 0 [m]
constexpr double kVz = 0.981;                        // upward speed [m/s]: back at z = 0 after 2 v_z/g = 0.2 s

// Both balls in free flight in the plane of the top, on the far side of the axis from it at
// t = 0 (a = (R, 0, 0)), the string slack by R: L1 + L2 = l − R. As the top turns, L1 grows by up
// to 2R (at φ = π, t = 0.1 s), so the Taut guard rises through 0 near t = 0.05 s, stays positive
// for about half a turn, and falls back below 0 near t = 0.15 s; at t = 0.2 s the top and the
// balls (v_z chosen so) are back where they started. Equal masses and velocities keep r2 − r1,
// hence L2, constant.
std::string scene(const std::string& max_step, int event_samples = -1) {
  const double l = 0.826;
  const double x1 = kR + kL1, x2 = x1 + (l - kR - kL1);
  return fmt::format(R"(
[model]
string_length = {l}
drive_radius = {R}
contact_distance = 0.03
[integrator]
method = "dop853"
rtol = 1e-9
atol = 1e-12
axes = "lab"
max_step = {max_step}
{samples}
[initial]
preset = "explicit"
r1 = [{x1:.17g}, 0.0, 0.0]
r2 = [{x2:.17g}, 0.0, 0.0]
v1 = [0.0, 0.0, {vz}]
v2 = [0.0, 0.0, {vz}]
mode = "slack"
[[schedule]]
kind = "hold"
omega = {w:.17g}
duration = 1.0
)",
                     fmt::arg("l", l), fmt::arg("R", kR), fmt::arg("max_step", max_step),
                     fmt::arg("samples", event_samples < 0 ? std::string() : fmt::format("event_samples = {}", event_samples)), fmt::arg("x1", x1),
                     fmt::arg("x2", x2), fmt::arg("vz", kVz), fmt::arg("w", kOmega));
}

// The first time the Taut guard rises through 0, from the exact free flight with linear drag:
// r(t) = r0 + v∞ t + (v0 − v∞)(1 − e^{−kt})/k, v∞ = −(g/k) ẑ, k = c_D/m (the same for both balls),
// by a scan at 1e-4 s and bisection to 1e-12 s.
double first_taut_exact(const config::RunConfig& c) {
  const physics::Parameters& p = c.model.p;
  const double k = p.drag / p.bead_mass;
  const Vec3 v_inf(0.0, 0.0, -p.gravity / k);
  const double L2 = (c.initial.r2 - c.initial.r1).norm();
  const auto guard = [&](double t) {
    const Vec3 r1 = c.initial.r1 + v_inf * t + (c.initial.v1 - v_inf) * (1.0 - std::exp(-k * t)) / k;
    const Vec3 a(kR * std::cos(kOmega * t), kR * std::sin(kOmega * t), 0.0);
    return (r1 - a).norm() + L2 - p.string_length - physics::taut_margin(p);
  };
  double lo = 0.0;
  while (guard(lo + 1e-4) < 0.0) lo += 1e-4;
  double hi = lo + 1e-4;
  while (hi - lo > 1e-12) (guard(0.5 * (lo + hi)) < 0.0 ? lo : hi) = 0.5 * (lo + hi);
  return hi;
}

// The first sample (every 1e-4 s over 0.2 s, a whole turn) with the string taut, if any.
std::optional<double> first_taut_sample(const config::RunConfig& c, long* steps = nullptr) {
  const physics::MotorSchedule schedule(c.model.p.drive_radius, c.schedule);
  physics::State s = sim::explicit_state(c.model, schedule, c.initial.r1, c.initial.r2, c.initial.v1, c.initial.v2,
                                         c.initial.mode);
  sim::Simulation simulation(c.model, schedule, c.run);
  std::optional<double> first;
  const sim::RunSummary sum = simulation.run(s, 0.2, 1e-4, [&](const sim::Sample& x) {
    if (!first && x.contact.mode != physics::Mode::Slack) first = x.t;
  });
  EXPECT_TRUE(sum.ok()) << sum.failure;
  if (steps) *steps = sum.steps;
  return first;
}

TEST(StepBound, TheDefaultIsAutoAndANumberOverridesIt) {
  EXPECT_TRUE(config::parse_run_config(scene("\"auto\""), "auto").run.guard_step_bound);
  const config::RunConfig fixed = config::parse_run_config(scene("0.2"), "fixed");
  EXPECT_FALSE(fixed.run.guard_step_bound);
  EXPECT_EQ(fixed.run.integ.h_max, 0.2);
  // Guard samples inside the step: three with "auto" (h <= 4/Ω), none with a fixed bound unless
  // asked for (each step would take them all).
  EXPECT_EQ(config::parse_run_config(scene("\"auto\""), "auto").run.integ.event_samples, 3);
  EXPECT_EQ(fixed.run.integ.event_samples, 0);
  EXPECT_EQ(config::parse_run_config(scene("0.2", 2), "fixed2").run.integ.event_samples, 2);
  EXPECT_THROW(config::parse_run_config(scene("\"fast\""), "bad"), config::ConfigError);
}

// In this flight the balls do not turn (θ̇ = 0) and hang at 0.4 m from the top: Ω_rel = ω_m =
// 31.4 rad/s beats the swing √(g / 0.41 m) = 4.9 rad/s, so h ≤ 1/ω_m = 0.032 s.
TEST(StepBound, TheFlightIsBoundByTheTopTurningAboutTheBalls) {
  const config::RunConfig c = config::parse_run_config(scene("\"auto\""), "auto");
  const physics::MotorSchedule schedule(c.model.p.drive_radius, c.schedule);
  const physics::State s = sim::explicit_state(c.model, schedule, c.initial.r1, c.initial.r2, c.initial.v1,
                                               c.initial.v2, c.initial.mode);
  const physics::TopKinematics top = schedule.top(0.0);
  EXPECT_DOUBLE_EQ(sim::guard_rate(c.model.p, top, s.y), kOmega);
  EXPECT_DOUBLE_EQ(sim::guard_step_bound(c.model.p, top, s.y), 1.0 / kOmega);
}

// The Taut guard is −R cos(ω_m t) plus the flight's second-order z²/(2 L1): positive for about
// π/ω_m = 0.1 s, far longer than the bound 1/ω_m, so a step end must fall inside (the excursion
// is the guard's whole amplitude, beyond the hidden depth (1 − cos ½) A). With max_step = 0.2 s
// (a whole turn, and the flight is a parabola the error control passes in one step) the
// excursion is hidden inside one step and the string is never seen to pull taut in that turn.
// The located event lies within ~1e-8 s of the exact root (dense-output error ~1e-9 m at
// rtol 1e-9 over a guard rate R ω_m ≈ 0.3 m/s); the first taut sample then lies within one
// sample spacing (1e-4 s) after it.
TEST(StepBound, AutoSeesTheStringPullTautWhereALargeFixedBoundMissesIt) {
  const config::RunConfig with_auto = config::parse_run_config(scene("\"auto\""), "auto");
  const double t_exact = first_taut_exact(with_auto);
  ASSERT_GT(t_exact, 0.03);
  ASSERT_LT(t_exact, 0.07);
  const std::optional<double> seen = first_taut_sample(with_auto);
  ASSERT_TRUE(seen.has_value()) << "the string never pulled taut with max_step = \"auto\"";
  EXPECT_GE(*seen, t_exact - 1e-7);
  EXPECT_LE(*seen, t_exact + 1e-4 + 1e-7);

  const config::RunConfig with_fixed = config::parse_run_config(scene("0.2"), "fixed");
  const std::optional<double> missed = first_taut_sample(with_fixed);
  EXPECT_FALSE(missed.has_value() && *missed <= t_exact + 1e-4 + 1e-7)
      << "max_step = 0.2 s saw the pull at " << *missed << " s: the scene no longer tests a hidden crossing";
}

// Guard samples inside the step ([integrator] event_samples = k): the guarantee holds for the
// samples 1/ω_m apart, so the bound is (k + 1)/ω_m. With k = 3 (h ≤ 0.127 s, longer than 1/ω_m =
// 0.032 s) the pull is found within the same tolerances as with k = 0, in fewer steps; and with
// the large fixed bound 0.2 s, which alone hides the pull, three samples per step (0.05 s apart)
// see it too.
TEST(StepBound, InteriorSamplesSeeThePullWithStepsLongerThanTheRate) {
  const config::RunConfig c0 = config::parse_run_config(scene("\"auto\"", 0), "k0");
  const config::RunConfig c3 = config::parse_run_config(scene("\"auto\"", 3), "k3");
  EXPECT_EQ(c3.run.integ.event_samples, 3);
  const physics::MotorSchedule schedule(c3.model.p.drive_radius, c3.schedule);
  const physics::State s = sim::explicit_state(c3.model, schedule, c3.initial.r1, c3.initial.r2, c3.initial.v1,
                                               c3.initial.v2, c3.initial.mode);
  EXPECT_DOUBLE_EQ(sim::guard_step_bound(c3.model.p, schedule.top(0.0), s.y, 3), 4.0 / kOmega);
  const double t_exact = first_taut_exact(c3);
  long steps0 = 0, steps3 = 0;
  const std::optional<double> seen0 = first_taut_sample(c0, &steps0);
  const std::optional<double> seen3 = first_taut_sample(c3, &steps3);
  ASSERT_TRUE(seen0.has_value());
  ASSERT_TRUE(seen3.has_value()) << "the string never pulled taut with event_samples = 3";
  EXPECT_GE(*seen3, t_exact - 1e-7);
  EXPECT_LE(*seen3, t_exact + 1e-4 + 1e-7);
  EXPECT_LT(steps3, steps0) << "the longer bound saved no step";

  const config::RunConfig fixed3 = config::parse_run_config(scene("0.2", 3), "fixed3");
  const std::optional<double> seen_fixed = first_taut_sample(fixed3);
  ASSERT_TRUE(seen_fixed.has_value()) << "max_step = 0.2 s with 3 interior samples missed the pull";
  EXPECT_GE(*seen_fixed, t_exact - 1e-7);
  EXPECT_LE(*seen_fixed, t_exact + 1e-4 + 1e-7);
}

// Conservative advancement: the change of each length guard between two states y0, y1 with
// |y1_i − y0_i| <= e_i and the top moved by |Δa| is within guard_change_bound (the triangle
// inequality; sim/step_bound.hpp), over a spread of displacements and top angles; and the bound
// is reached when both balls move straight apart along the links (it is not slack by a factor).
TEST(StepBound, TheLengthGuardsChangeNoMoreThanTheirBound) {
  using physics::Guard;
  const config::RunConfig c = config::parse_run_config(scene("\"auto\""), "auto");
  const physics::MotorSchedule schedule(c.model.p.drive_radius, c.schedule);
  const physics::State s = sim::explicit_state(c.model, schedule, c.initial.r1, c.initial.r2, c.initial.v1,
                                               c.initial.v2, physics::Mode::Slack);
  const physics::Contact slack{physics::Mode::Slack, 0, 0.0};
  const physics::TopKinematics top0 = schedule.top(0.0);
  for (int k = 0; k < 200; ++k) {
    numerics::Vec y1 = s.y;
    for (int i = 0; i < 6; ++i) y1(i) += 0.03 * std::sin(1.7 * k + 2.3 * i + 0.4 * k * i);
    const physics::TopKinematics top1 = schedule.top(0.0013 * k);
    const double travel = (top1.a - top0.a).norm();
    const numerics::Vec e = (y1 - s.y).cwiseAbs();
    for (Guard g : {Guard::LandBottom, Guard::LandTop, Guard::Taut, Guard::ReachBall, Guard::ReachTop}) {
      ASSERT_TRUE(sim::has_change_bound(g));
      const double dg = physics::guard_value(g, c.model, top1, slack, y1) - physics::guard_value(g, c.model, top0, slack, s.y);
      EXPECT_LE(std::abs(dg), sim::guard_change_bound(g, travel, e) * (1 + 1e-12)) << physics::to_string(g) << " " << k;
    }
  }
  // Ball 2 pulled straight away from ball 1 along the link: ΔL2 = |Δr2| exactly.
  numerics::Vec y1 = s.y;
  const Vec3 u2 = (s.y.segment<3>(physics::idx::r2) - s.y.segment<3>(physics::idx::r1)).normalized();
  y1.segment<3>(physics::idx::r2) += 0.01 * u2;
  const double dL2 = physics::guard_value(Guard::LandBottom, c.model, top0, slack, y1) -
                     physics::guard_value(Guard::LandBottom, c.model, top0, slack, s.y);
  EXPECT_NEAR(dL2, sim::guard_change_bound(Guard::LandBottom, 0.0, (y1 - s.y).cwiseAbs()), 1e-15);
  EXPECT_FALSE(sim::has_change_bound(Guard::Slacken));
  EXPECT_FALSE(sim::has_change_bound(Guard::Rest));
}

TEST(StepBound, EventSamplesIsAWholeNumberInRange) {
  EXPECT_THROW(config::parse_run_config(scene("\"auto\"", 17), "bad"), config::ConfigError);
  std::string half = scene("\"auto\"", 1);
  half.replace(half.find("event_samples = 1"), 17, "event_samples = 1.5");
  EXPECT_THROW(config::parse_run_config(half, "bad"), config::ConfigError);
  EXPECT_EQ(config::parse_run_config(scene("\"auto\"", 16), "ok").run.integ.event_samples, 16);
}

}  // namespace
