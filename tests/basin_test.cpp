// Basin sampling (sweep/basin.hpp): the Wilson interval against published values and its
// coverage, every family's draws inside the model's bounds, the draws reproducible from the
// chain's identity alone, and the bounds checked before any work.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>

#include "config/config.hpp"
#include "physics/contact_modes.hpp"
#include "sim/simulation.hpp"
#include "sweep/basin.hpp"
#include "sweep/plan.hpp"
#include "sweep/protocol.hpp"

using namespace ajx;

namespace {

physics::Model paper_model() {
  physics::Model m;
  m.p.drive_radius = 0.015;
  m.p.contact_distance = 0.035;
  return m;
}

// The angle of a segment from the downward vertical.
double from_vertical(const physics::Vec3& d) { return std::acos(std::clamp(-d.z() / d.norm(), -1.0, 1.0)); }

}  // namespace

TEST(Wilson, PublishedValues) {
  // 5 of 10: [0.2366, 0.7634]; 0 of 10: [0, z²/(n + z²)] = [0, 0.2775] (Newcombe 1998, Table I: method 3).
  const sweep::Interval a = sweep::wilson_interval(5, 10), b = sweep::wilson_interval(0, 10);
  EXPECT_NEAR(a.lo, 0.2366, 5e-5);
  EXPECT_NEAR(a.hi, 0.7634, 5e-5);
  EXPECT_DOUBLE_EQ(b.lo, 0.0);
  const double z2 = 1.959963984540054 * 1.959963984540054;
  EXPECT_NEAR(b.hi, z2 / (10 + z2), 1e-15);
  EXPECT_TRUE(std::isnan(sweep::wilson_interval(0, 0).lo));
}

TEST(Wilson, CoverageNearNominal) {
  // The exact coverage Σ_k C(n,k) p^k (1−p)^(n−k) [p ∈ CI(k)] of a 95 % interval: Wilson's
  // oscillates about 0.95 and stays above 0.92 for n p (1 − p) ≥ 5 (Brown, Cai, DasGupta 2001, Fig. 4).
  for (int n : {40, 100, 200})
    for (double p : {0.2, 0.35, 0.5, 0.8}) {
      double coverage = 0.0;
      for (int k = 0; k <= n; ++k) {
        const double logp = std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0) + k * std::log(p) +
                            (n - k) * std::log1p(-p);
        const sweep::Interval ci = sweep::wilson_interval(k, n);
        if (ci.lo <= p && p <= ci.hi) coverage += std::exp(logp);
      }
      EXPECT_GT(coverage, 0.92) << "n = " << n << ", p = " << p;
      EXPECT_LT(coverage, 0.98) << "n = " << n << ", p = " << p;
    }
}

TEST(BasinDraws, HangingFamilyInsideItsRangesAndOnTheString) {
  const physics::Model m = paper_model();
  sweep::BasinSpec b;
  b.family = sweep::BasinFamily::Hanging;
  b.s_lo = 0.2;
  b.s_hi = m.p.string_length - m.p.contact_distance;
  b.swing = 0.6;
  const double w = 30.0;
  const sweep::CompiledProtocol p = sweep::basin_protocol(b, w, 3, 0);
  const physics::MotorSchedule schedule(m.p.drive_radius, p.schedule);
  const physics::Vec3 a = schedule.top(0.0).a;
  double s_min = 1.0, s_max = 0.0;
  for (int n = 0; n < 500; ++n) {
    const physics::State s = sweep::basin_start(m, schedule, b, w, 3, n);
    const double L1 = (s.r1() - a).norm(), L2 = (s.r2() - s.r1()).norm();
    EXPECT_NEAR(L1 + L2, m.p.string_length, 1e-9);
    EXPECT_GE(L1, b.s_lo - 1e-9);
    EXPECT_LE(L1, b.s_hi + 1e-9);
    EXPECT_LE(from_vertical(s.r1() - a), b.swing + 1e-6);
    EXPECT_LE(from_vertical(s.r2() - s.r1()), b.swing + 1e-6);
    s_min = std::min(s_min, L1), s_max = std::max(s_max, L1);
  }
  // 500 uniform draws fill the range: each end is missed by more than 2 % of it with probability 0.98^500 < 1e-4.
  EXPECT_LT(s_min, b.s_lo + 0.02 * (b.s_hi - b.s_lo));
  EXPECT_GT(s_max, b.s_hi - 0.02 * (b.s_hi - b.s_lo));
}

TEST(BasinDraws, CloudKeepsTheOrbitsSegmentsAndStaysWithinEpsilon) {
  const physics::Model m = paper_model();
  sweep::BasinSpec b;
  b.family = sweep::BasinFamily::Cloud;
  b.orbit = "circular_high";
  b.epsilon = 0.01;
  const double w = 4.0 * std::numbers::pi;
  const physics::MotorSchedule schedule(m.p.drive_radius, sweep::basin_protocol(b, w, 0, 0).schedule);
  const physics::State o = sweep::basin_orbit(m, schedule, b, w);
  const physics::Vec3 a = schedule.top(0.0).a;
  const double L1 = (o.r1() - a).norm();
  for (int n = 0; n < 200; ++n) {
    const physics::State s = sweep::basin_start(m, schedule, b, w, 0, n, &o);
    EXPECT_NEAR((s.r1() - a).norm(), L1, 1e-9);
    EXPECT_NEAR((s.r2() - s.r1()).norm(), m.p.string_length - L1, 1e-9);
    // Moved across the segment by at most ε (the chord of a turn by at most ε / L).
    EXPECT_LE((s.r1() - o.r1()).norm(), b.epsilon * (1 + 1e-9));
  }
}

TEST(BasinDraws, HandPathStaysWithinItsAmplitudeAndHandsOverAtABreakpoint) {
  sweep::BasinSpec b;
  b.family = sweep::BasinFamily::Hand;
  b.hand_amplitude = 0.12;
  b.hand_duration = 3.0;
  b.hand_modes = 4;
  b.settle = 30.0;
  b.measure = 5.0;
  const double w = 40.0;
  for (int n = 0; n < 100; ++n) {
    const sweep::CompiledProtocol p = sweep::basin_protocol(b, w, 2, n);
    ASSERT_TRUE(p.hand);
    ASSERT_EQ(p.hand->p.size(), 4u);
    EXPECT_EQ(p.hand->duration, b.hand_duration);
    // The motor ramps from rest at step_rate from t = 0, with a breakpoint at T (the hand lets go).
    EXPECT_EQ(p.schedule.front().omega_begin, 0.0);
    EXPECT_NEAR(p.schedule.front().duration, b.hand_duration, 1e-12);
    EXPECT_NEAR(p.schedule.front().omega_end, b.step_rate * b.hand_duration, 1e-12);
    const physics::MotorSchedule sched(0.015, p.schedule);
    physics::MotorSchedule held = sched;
    held.set_hand(*p.hand);
    // |x_top − a| <= A throughout, planar, and no offset left at T.
    double worst = 0.0;
    for (int k = 0; k <= 300; ++k) {
      const double t = b.hand_duration * k / 300.0;
      const physics::Vec3 d = held.top(t).a - sched.top(t).a;
      worst = std::max(worst, d.norm());
      EXPECT_EQ(d.z(), 0.0);
    }
    EXPECT_LE(worst, b.hand_amplitude);
    EXPECT_EQ((held.top(b.hand_duration).a - sched.top(b.hand_duration).a).norm(), 0.0);
    ASSERT_EQ(p.windows.size(), 1u);
    EXPECT_EQ(p.windows[0].omega_begin, w);
    EXPECT_NEAR(p.windows[0].t_begin, w / b.step_rate + b.settle, 1e-9);
    EXPECT_NEAR(p.windows[0].t_end, p.duration, 1e-12);
  }
}

TEST(BasinDraws, ReproducibleFromTheChainsIdentityAlone) {
  const physics::Model m = paper_model();
  sweep::BasinSpec b;
  b.family = sweep::BasinFamily::Hanging;
  b.s_lo = 0.3;
  b.s_hi = 0.7;
  const physics::MotorSchedule schedule(m.p.drive_radius, sweep::basin_protocol(b, 20.0, 1, 7).schedule);
  const physics::State x = sweep::basin_start(m, schedule, b, 20.0, 1, 7);
  // Drawn again after other draws: the same bits.
  for (int n = 0; n < 20; ++n) (void)sweep::basin_start(m, schedule, b, 20.0, 1, n);
  const physics::State y = sweep::basin_start(m, schedule, b, 20.0, 1, 7);
  EXPECT_EQ(0, std::memcmp(x.y.data(), y.y.data(), sizeof(double) * std::size_t(x.y.size())));
  // Another sample, level or seed: another start.
  EXPECT_NE(x.r1(), sweep::basin_start(m, schedule, b, 20.0, 1, 8).r1());
  EXPECT_NE(x.r1(), sweep::basin_start(m, schedule, b, 20.0, 2, 7).r1());
  b.seed = 2;
  EXPECT_NE(x.r1(), sweep::basin_start(m, schedule, b, 20.0, 1, 7).r1());
  // The generator's first outputs are pinned: a change of the draws changes every stored start.
  sweep::BasinSpec c;
  sweep::BasinDraws d(c, 0, 0);
  const double u0 = d.uniform();
  EXPECT_GE(u0, 0.0);
  EXPECT_LT(u0, 1.0);
  sweep::BasinDraws e(c, 0, 0);
  EXPECT_EQ(u0, e.uniform());
}

TEST(BasinDraws, UniformIsUniform) {
  // 10 bins of 100 000 draws: χ² with 9 degrees of freedom below 27.9 (p = 0.001).
  sweep::BasinSpec b;
  sweep::BasinDraws d(b, 4, 5);
  std::array<int, 10> bins{};
  const int N = 100000;
  for (int i = 0; i < N; ++i) ++bins[std::size_t(d.uniform() * 10)];
  double chi2 = 0.0;
  for (int k : bins) chi2 += (k - N / 10.0) * (k - N / 10.0) / (N / 10.0);
  EXPECT_LT(chi2, 27.9);
}

TEST(BasinCheck, RefusesARangeBeyondTheStops) {
  const physics::Model m = paper_model();
  sweep::BasinSpec b;
  b.family = sweep::BasinFamily::Hanging;
  b.s_lo = 0.3;
  b.s_hi = m.p.string_length - m.p.contact_distance + 0.01;  // below the bottom stop
  try {
    sweep::check_basin(m, b, "f.toml");
    FAIL() << "accepted";
  } catch (const sweep::BasinError& e) {
    EXPECT_NE(std::string(e.what()).find("f.toml: key 'basin.s'"), std::string::npos) << e.what();
  }
  b.s_hi = 0.5;
  b.s_lo = 0.01;  // above the top stop s_min = 5 cm
  EXPECT_THROW(sweep::check_basin(m, b, "f.toml"), sweep::BasinError);
  b.s_lo = m.p.top_stop;
  EXPECT_NO_THROW(sweep::check_basin(m, b, "f.toml"));
}

TEST(BasinCheck, RefusesAHandBeyondTheStringALateHandoverAndATieThatWouldSlip) {
  physics::Model m = paper_model();
  sweep::BasinSpec b;
  b.family = sweep::BasinFamily::Hand;
  b.settle = 40.0;
  const auto refused = [&](const char* key) {
    try {
      sweep::check_basin(m, b, "f.toml");
      return std::string("accepted");
    } catch (const sweep::BasinError& e) {
      return std::string(e.what()).find(std::string("f.toml: key 'basin.") + key + "'") != std::string::npos
                 ? std::string()
                 : std::string(e.what());
    }
  };
  EXPECT_NO_THROW(sweep::check_basin(m, b, "f.toml"));
  b.hand_amplitude = m.p.string_length * 1.01;
  EXPECT_EQ(refused("hand_amplitude"), "");
  b.hand_amplitude = 0.1;
  b.hand_duration = b.settle;  // the hand would still hold the top when the window starts
  EXPECT_EQ(refused("hand_duration"), "");
  b.hand_duration = 3.0;
  m.layers.tie_clutch = true;  // I_a ω̇_m > τ_s: the rod alone would make the held tie slip
  b.step_rate = 1.01 * m.p.tie_static_torque / m.p.tie_inertia;
  EXPECT_EQ(refused("step_rate"), "");
  b.step_rate = 5.0;
  EXPECT_NO_THROW(sweep::check_basin(m, b, "f.toml"));
}

TEST(BasinPlan, ChainsPerLevelAndSampleWithTheirStarts) {
  const config::SweepConfig cfg = config::load_sweep_config(std::string(ASTROJAX_SOURCE_DIR) + "/tests/data/tiny_basin.toml");
  ASSERT_TRUE(cfg.basin);
  const sweep::SweepPlan plan = config::make_plan(cfg);
  ASSERT_EQ(plan.chains(), 12u);
  for (std::size_t c = 0; c < plan.chains(); ++c) {
    EXPECT_EQ(plan.starts[c].level, int(c / 6));
    EXPECT_EQ(plan.starts[c].sample, int(c % 6));
    ASSERT_TRUE(plan.starts[c].state);
    EXPECT_EQ(plan.spans[c].size(), 1u);
    EXPECT_EQ(plan.setups[c].protocol.windows.size(), 1u);
  }
  // The plan made again (as on another rank) has the same starts.
  const sweep::SweepPlan again = config::make_plan(cfg);
  for (std::size_t c = 0; c < plan.chains(); ++c)
    EXPECT_EQ(plan.start_state(c).y, again.start_state(c).y);
}
