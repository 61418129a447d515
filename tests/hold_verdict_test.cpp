// Bifurcation or time limit (sweep/hold_verdict.hpp): a hold restarts a chain along its own
// schedule and holds ω_m; an orbit the motor sustains has dE/dt ≈ 0 and is judged sustained,
// a free whirl the motor feeds nothing decays with dE/dt = −P_drag and is judged a transient.
// Both orbits are built exactly from an independent force balance (tests/steady_orbit.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <fmt/format.h>

#include "measured.hpp"
#include "physics/drive.hpp"
#include "sim/simulation.hpp"
#include "steady_orbit.hpp"
#include "sweep/hold_verdict.hpp"
#include "sweep/protocol.hpp"

using namespace ajx;
using sweep::OrbitClass;

namespace {

const double pi = 3.141592653589793;

sweep::ChainSetup chain_at(const physics::Model& m, double omega) {
  sweep::ChainSetup c;
  c.model = m;
  c.protocol.schedule = {{omega, omega, 1.0}};
  c.protocol.duration = 1.0;
  c.run.integ.tol.rtol = 1e-10;
  c.run.integ.tol.atol = 1e-12;
  c.sample_rate = 50.0;
  return c;
}

// The pair on the bottom stop turning rigidly at w about the vertical through the origin,
// from the co-rotating force balance; velocities w ẑ × p.
physics::State conical_state(const physics::Model& m, double w, const test::Vec8& x) {
  const physics::Vec3 z = physics::Vec3::UnitZ();
  const physics::Vec3 p1 = x.segment<3>(0), p2 = x.segment<3>(3);
  const physics::MotorSchedule sched(m.p.drive_radius, {{w, w, 1.0}});
  return sim::explicit_state(m, sched, p1, p2, w * z.cross(p1), w * z.cross(p2), physics::Mode::BottomStop);
}

constexpr double kHold = 20.0, kWindow = 5.0;  // 4 windows; the last 2 measured

}  // namespace

TEST(HoldVerdict, HeldChainFollowsTheScheduleThenHolds) {
  const std::vector<sweep::Segment> segs{sweep::Segment{sweep::Segment::Kind::Ramp, {0.0, 10.0, 0.5, 4.0}, {}}};
  sweep::ChainSetup chain;
  chain.protocol = sweep::compile(segs);
  const double t_cut = 7.0;  // ω_m = 3.5 rad/s there
  const sweep::ChainSetup held = sweep::held_chain(chain, t_cut, 3, 4.0);
  const physics::MotorSchedule s0 = chain.motor(), s1 = held.motor();
  for (double t = 0.0; t <= t_cut; t += 0.5) {
    double p0, w0, d0, p1, w1, d1;
    s0.phase(t, p0, w0, d0);
    s1.phase(t, p1, w1, d1);
    EXPECT_NEAR(p1, p0, 1e-12);
    EXPECT_NEAR(w1, w0, 1e-12);
  }
  for (double t = t_cut + 0.1; t < t_cut + 12.0; t += 1.3) {
    double p, w, d;
    s1.phase(t, p, w, d);
    EXPECT_NEAR(w, 3.5, 1e-12);
    EXPECT_EQ(d, 0.0);
  }
  ASSERT_EQ(held.protocol.windows.size(), 3u);
  EXPECT_DOUBLE_EQ(held.protocol.windows.front().t_begin, t_cut);
  EXPECT_NEAR(held.protocol.windows.back().t_end, t_cut + 12.0, 1e-12);
  EXPECT_EQ(held.protocol.windows[1].direction, 0);
  EXPECT_THROW(sweep::held_chain(chain, chain.protocol.duration + 1.0, 3, 4.0), std::invalid_argument);
  EXPECT_THROW(sweep::held_chain(chain, t_cut, 0, 4.0), std::invalid_argument);
}

TEST(HoldVerdict, DragTimeAndTolerance) {
  physics::Parameters p;  // the paper's balls: m/c_D = 0.018/1.7245e-3 = 10.44 s
  EXPECT_NEAR(sweep::drag_time(p), 10.4378, 1e-4);
  // T = 5 m/c_D: r_tol = m/(2 c_D T) = 1/10.
  EXPECT_NEAR(sweep::sustain_tolerance(p, 5 * sweep::drag_time(p)), 0.1, 1e-12);
  p.drag = 0.0;
  EXPECT_TRUE(std::isinf(sweep::drag_time(p)));
}

TEST(HoldVerdict, DrivenConicalOrbitIsSustained) {
  // The fallen pendulum driven at w = 3 rad/s (below √(g/(l−d)) ≈ 3.5 rad/s, where the driven
  // radius is large), started exactly on its steady orbit: the motor feeds exactly what drag
  // takes, dE/dt = 0. Measured |r| is bounded by the integration error of E over the measured
  // 10 s, far below r_tol = m/(2 c_D T) = 0.26 for T = 20 s: we require |r| < 1e-3.
  physics::Model m;
  const double w = 3.0, L1 = m.p.string_length - m.p.contact_distance, L2 = m.p.contact_distance;
  const test::Vec8 x = test::solve_steady(m.p, L1, L2, w, test::linear_guess(m.p, L1, L2, w));
  ASSERT_LT(test::steady_residual(m.p, L1, L2, w, x).norm(), 1e-12);
  const sweep::HoldSide s =
      sweep::hold_side(chain_at(m, w), 0.0, kHold, kWindow, conical_state(m, w, x), OrbitClass::Fallen);
  ASSERT_TRUE(s.ok) << s.failure;
  ASSERT_EQ(s.classes.size(), 4u);
  EXPECT_EQ(s.measured, 2);
  EXPECT_NEAR(s.hold, kHold, 1e-12);
  EXPECT_NEAR(s.omega, w, 1e-12);
  EXPECT_EQ(s.final_class, OrbitClass::Fallen);
  EXPECT_GT(s.mean.drag, 0.0);
  EXPECT_NEAR(s.mean.motor, s.mean.drag, 1e-3 * s.mean.drag);
  EXPECT_LT(std::abs(s.ratio), 1e-3);
  EXPECT_NEAR(s.tolerance, sweep::sustain_tolerance(m.p, kHold), 1e-12);
  EXPECT_TRUE(s.sustained);
  EXPECT_TRUE(s.determined);
  report("hold_sustained_ratio", fmt::format("{:.2e} (P_drag {:.3e} W)", s.ratio, s.mean.drag));

  // Held after the "change" it ends in another class: a bifurcation; it ends in the old class
  // again: an excursion, back within the hold or already when the hold starts.
  sweep::HoldSide other = s;
  other.final_class = other.classes.back() = OrbitClass::NotSettled;
  EXPECT_EQ(sweep::judge(s, other).verdict, sweep::Verdict::Bifurcation) << sweep::judge(s, other).reason;
  sweep::HoldSide back = s;
  back.reference = OrbitClass::Flower;
  back.classes[0] = OrbitClass::NotSettled;
  sweep::Judgement j = sweep::judge(s, back);
  EXPECT_EQ(j.verdict, sweep::Verdict::Excursion) << j.reason;
  EXPECT_NE(j.reason.find("is not-settled and back to fallen after 5 s"), std::string::npos) << j.reason;
  back.classes[0] = OrbitClass::Fallen;
  j = sweep::judge(s, back);
  EXPECT_EQ(j.verdict, sweep::Verdict::Excursion) << j.reason;
  EXPECT_NE(j.reason.find("back to fallen when the hold starts (the sweep saw flower there)"), std::string::npos)
      << j.reason;
  other.ok = false;
  EXPECT_EQ(sweep::judge(s, other).verdict, sweep::Verdict::Undecided);
  // Per-window ratios scattering by ±1/4 (standard error) cannot tell r = 0 from r = −1.
  sweep::HoldSide noisy = s;
  noisy.determined = false;
  EXPECT_EQ(sweep::judge(noisy, back).verdict, sweep::Verdict::Undecided);
}

TEST(HoldVerdict, FreeWhirlIsATransient) {
  // The pair on the bottom stop whirling at 5 rad/s under a top that does not move (R = 0,
  // ω_m = 0): the motor feeds nothing (P_motor = 0 exactly), the bead stays on the ball (no
  // friction), so the energy balance gives dE/dt = −P_drag: r = −1 to the balance's closure
  // (1e-7 relative). The class stays fallen (the classifier decides by where the bead is), so
  // only the energy account can tell: not sustained, a time-limited transient.
  physics::Model m;
  m.p.drive_radius = 0.0;
  const double w = 5.0, L1 = m.p.string_length - m.p.contact_distance, L2 = m.p.contact_distance;
  physics::Parameters free = m.p;
  free.drag = 0.0;  // the geometry of the free whirl (no drag, no drive)
  const double c = m.p.gravity / (m.p.string_length * w * w), s_ = std::sqrt(1 - c * c);
  test::Vec8 guess;
  guess << L1 * s_, 0, -L1 * c, m.p.string_length * s_, 0, -m.p.string_length * c,
      (m.p.bead_mass + m.p.ball_mass) * m.p.gravity / c, m.p.ball_mass * m.p.gravity / c;
  const test::Vec8 x = test::solve_steady(free, L1, L2, w, guess);
  ASSERT_LT(test::steady_residual(free, L1, L2, w, x).norm(), 1e-12);
  sweep::ChainSetup chain = chain_at(m, 0.0);
  chain.protocol.schedule.clear();  // no schedule before the hold: ω_m = 0
  chain.protocol.duration = 0.0;
  const sweep::HoldSide s = sweep::hold_side(chain, 0.0, kHold, kWindow, conical_state(m, w, x), OrbitClass::Fallen);
  ASSERT_TRUE(s.ok) << s.failure;
  EXPECT_EQ(s.final_class, OrbitClass::Fallen);
  EXPECT_EQ(s.mean.motor, 0.0);
  EXPECT_NEAR(s.ratio, -1.0, 1e-6);
  EXPECT_FALSE(s.sustained);
  EXPECT_TRUE(s.determined);  // a uniform decay: every window has r_k = −1
  report("hold_free_whirl_ratio", fmt::format("{:+.7f}", s.ratio));

  sweep::HoldSide other = s;
  other.final_class = OrbitClass::NotSettled;
  const sweep::Judgement j = sweep::judge(s, other);
  EXPECT_EQ(j.verdict, sweep::Verdict::TimeLimited) << j.reason;
  EXPECT_NE(j.reason.find("not sustained"), std::string::npos) << j.reason;
}

TEST(HoldVerdict, AnOrbitThatChangesClassIsATransient) {
  // The sweep saw locked-circular before the change; held there, it ends fallen.
  sweep::HoldSide pre, post;
  pre.reference = OrbitClass::LockedCircular;
  pre.final_class = OrbitClass::Fallen;
  pre.first_change = 15.0;
  pre.sustained = true;  // sustained as a fallen pendulum, but not the orbit the sweep saw
  post.final_class = OrbitClass::Fallen;
  const sweep::Judgement j = sweep::judge(pre, post);
  EXPECT_EQ(j.verdict, sweep::Verdict::TimeLimited);
  EXPECT_NE(j.reason.find("becomes fallen"), std::string::npos) << j.reason;
}
