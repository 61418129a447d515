// The full contact model: a derived case for each switch, stick-slip against its regularised
// twin, impacts and slack phases with their energy, watches of omitted layers, determinism.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "physics/energy.hpp"
#include "physics/string_friction.hpp"
#include "sim/simulation.hpp"
#include "steady_orbit.hpp"

using namespace ajx;
using namespace ajx::physics;
using numerics::Vec;

namespace {

const double pi = 3.141592653589793;

sim::RunOptions opts(double rtol = 1e-11) {
  sim::RunOptions o;
  o.method = "dop853";
  o.integ.tol.rtol = rtol;
  o.integ.tol.atol = rtol * 1e-2;
  return o;
}

// A stuck circular orbit at ω with the bead held at s* (tests/steady_orbit.hpp), its
// deflection ψ and tension ratio T1/T2, and the coefficient μ* = |ln(T1/T2)|/ψ at which the
// capstan cone is exactly at its edge.
struct StuckOrbit {
  test::Vec8 x;
  double s, psi, ratio, mu_edge;
};

StuckOrbit stuck_orbit(const Parameters& p, double w, double s) {
  // Seeded from the paper's Table 1 shape: bead out on one side, bottom ball on the other.
  test::Vec8 x0;
  x0 << -0.14427, 0, -0.52483, 0.11924, 0, -0.62353, 0.5, 0.3;
  StuckOrbit o;
  o.s = s;
  o.x = test::solve_steady(p, s, p.string_length - s, w, x0);
  const Vec3 a(p.drive_radius, 0, 0);
  const Vec3 u1 = (Vec3(o.x.segment<3>(0)) - a).normalized();
  const Vec3 u2 = (Vec3(o.x.segment<3>(3)) - Vec3(o.x.segment<3>(0))).normalized();
  o.psi = deflection(u1, u2);
  o.ratio = o.x(6) / o.x(7);
  o.mu_edge = std::abs(std::log(o.ratio)) / o.psi;
  return o;
}

State start_on(const Model& m, const MotorSchedule& sched, const StuckOrbit& o, double w) {
  const Vec3 p1 = o.x.segment<3>(0), p2 = o.x.segment<3>(3), W(0, 0, w);
  State s = sim::explicit_state(m, sched, p1, p2, W.cross(p1), W.cross(p2), Mode::Stuck);
  EXPECT_NEAR(s.contact.s_star, o.s, 1e-12);
  return s;
}

Model paper_model() {
  Model m;
  m.p.drive_radius = 0.01;
  m.layers.friction = Friction::StickSlip;
  return m;
}

// The scenes whose answers are derived by hand: a fixed top (R = 0) and no drag.
Model fixed_top() {
  Model m = paper_model();
  m.p.drive_radius = 0.0;
  m.p.drag = 0.0;
  return m;
}

sim::RunSummary run_to(const Model& m, const MotorSchedule& sched, State& st, double t_end, double rtol = 1e-12) {
  sim::Simulation simulation(m, sched, opts(rtol));
  return simulation.run(st, t_end, 0.0);
}

}  // namespace

TEST(ContactModel, StuckOrbitInsideTheConeStaysStuck) {
  // The paper's parameters at ω = 4.7π with the bead at s* = 0.547 m: a Table-1-like orbit
  // whose cone needs μ* ≈ 0.20 < μ_s = 0.257 (but > μ_k: a sliding bead could not hold it).
  // Started on it, the bead never slips and L1 stays s* to round-off. The orbit is an
  // equilibrium of the simulator to its accuracy; it is unstable (a departure from round-off
  // grows ~e^{0.6 t}), so the test bounds the departure at 10 s and prints its growth rate.
  Model m = paper_model();
  const double w = 4.7 * pi, s = 0.547, T = 10.0;
  const StuckOrbit o = stuck_orbit(m.p, w, s);
  ASSERT_LT(test::steady_residual(m.p, s, m.p.string_length - s, w, o.x).norm(), 1e-12);
  ASSERT_LT(o.mu_edge, m.p.mu_static);
  ASSERT_GT(o.mu_edge, m.p.mu_kinetic);
  const MotorSchedule sched(m.p.drive_radius, {{w, w, T}});
  State st = start_on(m, sched, o, w);
  sim::Simulation simulation(m, sched, opts(1e-12));
  double worst_s = 0.0, dev5 = 0.0, dev10 = 0.0;
  const sim::RunSummary r = simulation.run(st, T, 0.01, [&](const sim::Sample& smp) {
    worst_s = std::max(worst_s, std::abs(smp.dyn.g.L1 - s));
    const Eigen::Matrix3d Q = Eigen::AngleAxisd(-smp.top.phi, Vec3::UnitZ()).toRotationMatrix();
    const double dev = (Q * Vec3(smp.y.segment<3>(idx::r2)) - Vec3(o.x.segment<3>(3))).norm();
    if (std::abs(smp.t - 5.0) < 1e-9) dev5 = dev;
    if (std::abs(smp.t - 10.0) < 1e-9) dev10 = dev;
  });
  ASSERT_TRUE(r.ok()) << r.failure;
  EXPECT_EQ(r.mode_switches, 0);
  EXPECT_EQ(st.contact.mode, Mode::Stuck);
  EXPECT_LT(worst_s, 1e-11);
  EXPECT_LT(dev10, 1e-8);
  std::printf("measured stuck orbit at 4.7π: ψ = %.4f rad, T1/T2 = %.4f, cone edge μ* = %.4f, departure "
              "%.2e m at 5 s, %.2e m at 10 s (growth %.2f /s)\n",
              o.psi, o.ratio, o.mu_edge, dev5, dev10, std::log(dev10 / dev5) / 5.0);
}

TEST(ContactModel, JustOutsideTheConeTheBeadSlipsTheWayTheViolatedBoundSays) {
  // μ_s 5% below the edge μ*: the cone is left at once. At 4.7π the lower segment pulls harder
  // (T1/T2 < 1): the bead slips up the string (ṡ < 0). At 4π T1/T2 > 1: it slips down.
  for (const double w : {4.7 * pi, 4.0 * pi}) {
    Model m = paper_model();
    const double s = 0.547;
    const StuckOrbit o = stuck_orbit(m.p, w, s);
    ASSERT_LT(test::steady_residual(m.p, s, m.p.string_length - s, w, o.x).norm(), 1e-12);
    m.p.mu_static = 0.95 * o.mu_edge;
    m.p.mu_kinetic = 0.5 * m.p.mu_static;
    const MotorSchedule sched(m.p.drive_radius, {{w, w, 0.2}});
    State st = start_on(m, sched, o, w);
    sim::Simulation simulation(m, sched, opts());
    int first_sigma = 0;
    const sim::RunSummary r = simulation.run(st, 0.2, 0.001, [&](const sim::Sample& smp) {
      if (first_sigma == 0 && smp.contact.mode == Mode::Sliding) first_sigma = smp.contact.sigma;
    });
    ASSERT_TRUE(r.ok()) << r.failure;
    const int expected = o.ratio < 1.0 ? -1 : +1;  // T1 < κ_lo T2: up; T1 > κ_hi T2: down
    EXPECT_EQ(first_sigma, expected) << "ω = " << w / pi << "π, T1/T2 = " << o.ratio;
    const double L1 = (Vec3(st.y.segment<3>(idx::r1)) - sched.top(st.t).a).norm();
    EXPECT_EQ(L1 > s, expected > 0) << "L1 = " << L1;
    EXPECT_GT(std::abs(L1 - s), 1e-6);
  }
}

TEST(ContactModel, PlasticLandingOnTheBottomStop) {
  // A fixed top (R = 0), no drag, the string hanging straight: the bottom ball hangs still
  // (T2 = m2 g) and the bead falls freely along the string from L2 = 0.3 m. It lands after
  // t* = √(2 (0.3 - d)/g) at v = g t* and stops dead: the impact dissipates m1 g (0.3 - d).
  Model m = fixed_top();
  const double l = m.p.string_length, d = m.p.contact_distance, g = m.p.gravity, L20 = 0.3;
  const double t_land = std::sqrt(2 * (L20 - d) / g);
  const MotorSchedule sched(m.p.drive_radius, {{0.0, 0.0, 1.0}});
  for (const double dt : {-1e-6, 1e-6}) {
    State st = sim::explicit_state(m, sched, Vec3(0, 0, -(l - L20)), Vec3(0, 0, -l), Vec3::Zero(), Vec3::Zero(),
                                   Mode::Sliding);
    const sim::RunSummary r = run_to(m, sched, st, t_land + dt);
    ASSERT_TRUE(r.ok()) << r.failure;
    if (dt < 0) {
      EXPECT_EQ(st.contact.mode, Mode::Sliding);
      EXPECT_NEAR(-st.y(idx::v1 + 2), g * (t_land + dt), 1e-9);
      EXPECT_EQ(r.impacts, 0);
    } else {
      EXPECT_EQ(st.contact.mode, Mode::BottomStop);
      EXPECT_EQ(r.impacts, 1);
      EXPECT_NEAR(st.impact_loss, m.p.bead_mass * g * (L20 - d), 1e-9 * m.p.bead_mass * g * L20);
      EXPECT_LT(st.y.segment<6>(idx::v1).norm(), 1e-9);
      EXPECT_NEAR(st.y(idx::r1 + 2), -(l - d), 1e-12);
    }
  }
}

TEST(ContactModel, SlackPhaseEndsInAReTautImpact) {
  // The pair at rest on a string slack by δ = 5 mm (bead on the bottom ball), no drag, fixed
  // top: both fall freely together for t* = √(2δ/g) until the string pulls taut; the
  // plastic re-taut impact (and the bead meeting the ball at that instant) stop both, and
  // (m1 + m2) g δ is dissipated. They then hang at rest on the bottom stop.
  Model m = fixed_top();
  const double l = m.p.string_length, d = m.p.contact_distance, g = m.p.gravity, delta = 0.005;
  const double t_taut = std::sqrt(2 * delta / g);
  const MotorSchedule sched(m.p.drive_radius, {{0.0, 0.0, 1.0}});
  const Vec3 r1(0, 0, -(l - d - delta)), r2(0, 0, -(l - delta));
  for (const double dt : {-1e-6, 1e-3}) {
    State st = sim::explicit_state(m, sched, r1, r2, Vec3::Zero(), Vec3::Zero(), Mode::Slack);
    const sim::RunSummary r = run_to(m, sched, st, t_taut + dt);
    ASSERT_TRUE(r.ok()) << r.failure;
    if (dt < 0) {
      EXPECT_EQ(st.contact.mode, Mode::Slack);
      EXPECT_NEAR(-st.y(idx::v2 + 2), g * (t_taut + dt), 1e-9);
    } else {
      EXPECT_EQ(st.contact.mode, Mode::BottomStop);
      EXPECT_GE(r.impacts, 1);
      EXPECT_NEAR(st.impact_loss, (m.p.bead_mass + m.p.ball_mass) * g * delta, 1e-9);
      EXPECT_LT(st.y.segment<6>(idx::v1).norm(), 1e-9);
      EXPECT_LT(std::abs(r.energy.residual), 1e-12);
    }
  }
}

TEST(ContactModel, BouncingWithRestitutionEndsWithoutAnEventStorm) {
  // The same drop with restitution e = 0.5: the string bounces the ball up and the bounces
  // shrink geometrically (a Zeno sequence). The run must end, with every impact accounted:
  // ΔE + impact losses = 0 to 1e-6 of the energy dissipated.
  Model m = fixed_top();
  m.layers.restitution = 0.5;
  const double l = m.p.string_length, d = m.p.contact_distance;
  const MotorSchedule sched(m.p.drive_radius, {{0.0, 0.0, 2.0}});
  State st = sim::explicit_state(m, sched, Vec3(0, 0, -(l - d - 0.01)), Vec3(0, 0, -(l - 0.01)), Vec3::Zero(),
                                 Vec3::Zero(), Mode::Slack);
  const sim::RunSummary r = run_to(m, sched, st, 2.0);
  ASSERT_TRUE(r.ok()) << r.failure;
  EXPECT_GT(r.impacts, 2);
  EXPECT_LT(std::abs(r.energy.residual), 1e-6 * r.energy.impact_loss);
  EXPECT_LT(st.y.segment<6>(idx::v1).norm(), 1e-6);  // settled
  std::printf("measured bounce: %ld impacts, %ld slack phases, %ld chatter episodes, loss %.6e J\n", r.impacts,
              r.slack_phases, r.chatter, r.energy.impact_loss);
}

TEST(ContactModel, StickSlipHoldsWhereTheRegularisedTwinCreeps) {
  // The stuck orbit at 4.7π with μ_k = 1.2 μ* (so the regularised law can hold it only at
  // tanh(ṡ/ε) = μ*/μ_k, a creep speed ṡ ≈ ε atanh(1/1.2) ≈ 1.2 ε): stick-slip keeps L1 at s*
  // exactly; the regularised bead creeps, less for smaller ε, at a cost that grows as ε shrinks
  // while the event model's cost does not depend on ε at all.
  Model m = paper_model();
  const double w = 4.7 * pi, s = 0.547, T = 5.0;
  const StuckOrbit o = stuck_orbit(m.p, w, s);
  m.p.mu_kinetic = 1.2 * o.mu_edge;
  m.p.mu_static = std::max(m.p.mu_static, 1.3 * o.mu_edge);
  const MotorSchedule sched(m.p.drive_radius, {{w, w, T}});
  const auto creep = [&](Friction f, double eps, long& steps) {
    Model mm = m;
    mm.layers.friction = f;
    mm.layers.regularisation = eps;
    State st = start_on(mm, sched, o, w);
    if (f == Friction::Regularised) st.contact = {Mode::Sliding, 0, 0.0};
    sim::Simulation simulation(mm, sched, opts(1e-10));
    const sim::RunSummary r = simulation.run(st, T, 0.0);
    EXPECT_TRUE(r.ok()) << r.failure;
    steps = r.steps;
    return std::abs((Vec3(st.y.segment<3>(idx::r1)) - sched.top(st.t).a).norm() - s);
  };
  long steps_event = 0;
  const double c_event = creep(Friction::StickSlip, 0.0, steps_event);
  EXPECT_LT(c_event, 1e-11);
  double prev_creep = 1.0;
  long prev_steps = 0, steps_reg = 0;
  for (const double eps : {1e-2, 1e-3, 1e-4}) {
    const double c = creep(Friction::Regularised, eps, steps_reg);
    std::printf("measured regularised ε = %.0e m/s: creep %.3e m in %.0f s, %ld steps (event model: %ld)\n", eps, c,
                T, steps_reg, steps_event);
    EXPECT_GT(c, 1e3 * c_event + 1e-9);
    EXPECT_LT(c, prev_creep);
    EXPECT_GT(steps_reg, prev_steps);
    prev_creep = c;
    prev_steps = steps_reg;
  }
  EXPECT_GT(steps_reg, steps_event);
}

TEST(ContactModel, StribeckHoldsATableOneOrbitByCreepingThatShrinksWithEps) {
  // The Table-1-like stuck orbit at 4.7π needs μ* between μ_k and μ_s. The tanh law saturates at
  // μ_k, so its bead slides off. The Stribeck law f(v) = [μ_k + Δ e^{-(v/v_s)²}] tanh(v/ε) holds
  // it where |f(ṡ)| = μ* on the rising branch: ṡ* = ε x with tanh x = μ*/(μ_s − Δ(1 − e^{-(εx/v_s)²}))
  // → ṡ*/ε = atanh(μ*/μ_s) as ε/v_s → 0. The creep speed is linear in ε: the orbit is held to a
  // drift ṡ* t that vanishes with ε. Direction: T1/T2 < 1 here, so the bead creeps up (ṡ < 0).
  Model m = paper_model();
  const double w = 4.7 * pi, s = 0.547, T = 1.0, t0 = 0.2;
  const StuckOrbit o = stuck_orbit(m.p, w, s);
  ASSERT_GT(o.mu_edge, m.p.mu_kinetic);
  ASSERT_LT(o.mu_edge, m.p.mu_static);
  ASSERT_LT(o.ratio, 1.0);
  const MotorSchedule sched(m.p.drive_radius, {{w, w, T}});
  // The mean ṡ over [t0, T] (after the settling into creep, which takes ~ m ε / (T2 ψ μ'(0)) ≪ t0)
  // and the largest departure of L1 from s* over the run.
  const auto run = [&](Friction f, double eps, double& drift) {
    Model mm = m;
    mm.layers.friction = f;
    mm.layers.regularisation = eps;
    mm.layers.stribeck_speed = 1e-2;
    State st = start_on(mm, sched, o, w);
    st.contact = {Mode::Sliding, 0, 0.0};
    sim::Simulation simulation(mm, sched, opts(1e-10));
    double L1_t0 = 0.0, L1_T = 0.0;
    drift = 0.0;
    const sim::RunSummary r = simulation.run(st, T, 0.01, [&](const sim::Sample& smp) {
      drift = std::max(drift, std::abs(smp.dyn.g.L1 - s));
      if (std::abs(smp.t - t0) < 1e-9) L1_t0 = smp.dyn.g.L1;
      if (std::abs(smp.t - T) < 1e-9) L1_T = smp.dyn.g.L1;
    });
    EXPECT_TRUE(r.ok()) << r.failure;
    return (L1_T - L1_t0) / (T - t0);
  };
  // The tanh law at the smaller ε: it has no creep equilibrium (μ_k tanh < μ*), so the bead
  // slides off however small ε is.
  double drift_tanh = 0.0;
  run(Friction::Regularised, 1e-4, drift_tanh);
  double prev_speed = 1.0;
  for (const double eps : {1e-3, 1e-4}) {
    const Model law = [&] {
      Model mm = m;
      mm.layers.friction = Friction::Stribeck;
      mm.layers.regularisation = eps;
      mm.layers.stribeck_speed = 1e-2;
      return mm;
    }();
    // ṡ* by bisection on the rising branch (f increases on (0, ε atanh-ish] for ε ≪ v_s).
    double lo = 0.0, hi = 5.0 * eps;
    for (int i = 0; i < 100; ++i) {
      const double mid = 0.5 * (lo + hi);
      (regularised_coefficient(law, mid) < o.mu_edge ? lo : hi) = mid;
    }
    const double expected = -lo;
    double drift = 0.0;
    const double speed = run(Friction::Stribeck, eps, drift);
    std::printf("measured Stribeck ε = %.0e m/s (v_s = 1e-2): creep ṡ = %.4e m/s, expected %.4e (ṡ/ε = %.4f, "
                "atanh(μ*/μ_s) = %.4f), largest |L1 − s*| %.2e m in %.0f s; tanh law: %.2e m\n",
                eps, speed, expected, speed / eps, std::atanh(o.mu_edge / m.p.mu_static), drift, T, drift_tanh);
    // The orbit's own μ* moves as the bead creeps by |ṡ*| T (1 mm at ε = 1e-3) and as the
    // unstable orbit departs (~e^{0.6 t}): 5 % on the creep speed covers both at these ε.
    EXPECT_NEAR(speed, expected, 0.05 * std::abs(expected));
    EXPECT_LT(drift, 2.0 * std::abs(expected) * T + 1e-6);
    if (eps == 1e-4) EXPECT_GT(drift_tanh, 20.0 * drift);  // at equal ε
    EXPECT_LT(std::abs(speed), 0.2 * prev_speed);
    prev_speed = std::abs(speed);
  }
}

TEST(ContactModel, OmittedLayersReportTheirViolatedAssumptions) {
  // The kinetic layer on the spin-up where the full model sticks: it reports ṡ = 0 inside the
  // static cone. The slack layer off on a drop: a negative tension is reported, not hidden.
  {
    Model m = paper_model();
    m.layers.friction = Friction::Kinetic;
    const MotorSchedule sched(m.p.drive_radius, {{2 * pi, 2 * pi, 10.0}, {2 * pi, 14 * pi, 75.4}, {14 * pi, 14 * pi, 5.0}});
    State st = sim::hanging_at_rest(m, sched);
    sim::Simulation simulation(m, sched, opts(1e-10));
    const sim::RunSummary r = simulation.run(st, sched.duration(), 0.0);
    ASSERT_TRUE(r.ok()) << r.failure;
    ASSERT_EQ(r.violations.size(), 1u);
    EXPECT_NE(r.violations[0].what.find("static cone"), std::string::npos);
    EXPECT_GT(r.violations[0].count, 0);
    EXPECT_GT(r.violations[0].first_time, 0.0);
    EXPECT_GT(r.violations[0].worst, 0.0);
  }
  {
    // The pair balanced above a fixed top: the "bottom" ball sits on the bead, the links are
    // in compression. The bead does not stay on the ball (its one-sided cone is left: F1 < F2
    // with ψ ≈ 0), it slides along the straight string towards the top, which then carries
    // only the ball's weight: T1 = T2 = -m2 g. A string cannot push; without the slack layer
    // the run goes on but must say so, from t = 0, with the worst tension about -m2 g.
    Model m = paper_model();
    m.p.drive_radius = 0.0;
    m.p.drag = 0.0;
    m.layers.slack = false;
    const double l = m.p.string_length, d = m.p.contact_distance;
    const MotorSchedule sched(m.p.drive_radius, {{0.0, 0.0, 0.5}});
    const Vec3 up = Vec3(0.05, 0, 1).normalized();
    State st = sim::explicit_state(m, sched, (l - d) * up, l * up, Vec3::Zero(), Vec3::Zero(), Mode::BottomStop);
    const sim::RunSummary r = run_to(m, sched, st, 0.5, 1e-10);
    ASSERT_TRUE(r.ok()) << r.failure;
    bool found = false;
    for (const auto& v : r.violations)
      if (v.what.find("negative tension") != std::string::npos && v.count > 0 && v.first_time == 0.0 &&
          v.worst > 0.99 * m.p.ball_mass * m.p.gravity)
        found = true;
    EXPECT_TRUE(found);
  }
}

TEST(ContactModel, TheSameRunTwiceIsBitIdentical) {
  Model m = paper_model();
  const MotorSchedule sched(m.p.drive_radius, {{0.0, 14 * pi, 60.0}, {14 * pi, 3 * pi, 30.0}});
  std::vector<double> a, b;
  for (auto* out : {&a, &b}) {
    State st = sim::hanging_at_rest(m, sched);
    sim::Simulation simulation(m, sched, opts(1e-10));
    const sim::RunSummary r = simulation.run(st, sched.duration(), 0.01, [&](const sim::Sample& smp) {
      out->push_back(smp.t);
      out->insert(out->end(), smp.y.data(), smp.y.data() + smp.y.size());
      out->push_back(double(smp.contact.mode));
    });
    ASSERT_TRUE(r.ok()) << r.failure;
  }
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0);
}

TEST(ContactModel, EventBoundAndChatterResolutionNeverHang) {
  // A violent spin-up with many switches. (1) With a bound of 20 events the run stops and says
  // so. (2) With a hair-trigger chatter detector (3 switches within 10 s) the resolution engages
  // (band widened, impacts plastic), the run completes, reports it, and stays deterministic
  // and energy-consistent.
  Model m = paper_model();
  m.p.drive_radius = 0.06;
  const MotorSchedule sched(m.p.drive_radius, {{2 * pi, 2 * pi, 10.0}, {2 * pi, 14 * pi, 75.4}});
  {
    State st = sim::hanging_at_rest(m, sched);
    sim::RunOptions o = opts(1e-10);
    o.max_events = 20;
    sim::Simulation simulation(m, sched, o);
    const sim::RunSummary r = simulation.run(st, sched.duration(), 0.0);
    EXPECT_FALSE(r.ok());
    EXPECT_NE(r.failure.find("event bound 20 hit"), std::string::npos) << r.failure;
    EXPECT_TRUE(st.y.allFinite());
  }
  std::vector<double> finals[2];
  for (auto& fin : finals) {
    State st = sim::hanging_at_rest(m, sched);
    sim::RunOptions o = opts(1e-10);
    o.chatter_switches = 3;
    o.chatter_window = 10.0;
    sim::Simulation simulation(m, sched, o);
    const sim::RunSummary r = simulation.run(st, sched.duration(), 0.0);
    ASSERT_TRUE(r.ok()) << r.failure;
    EXPECT_GT(r.chatter, 0);
    EXPECT_GT(r.first_chatter, 0.0);
    EXPECT_LT(std::abs(r.energy.residual), 1e-6 * r.energy.motor_work);
    fin.assign(st.y.data(), st.y.data() + st.y.size());
  }
  EXPECT_EQ(finals[0], finals[1]);
}

TEST(ContactModel, PlasticLandingOnTheTopStop) {
  // Fixed top, no drag, straight string: the bead thrown up the string at v0 from
  // L1 = s_min + h decelerates at g (the hanging ball stays still) and reaches the top stop at
  // t* = (v0 - v)/g with v = √(v0² - 2 g h); the plastic landing dissipates ½ m1 v². The stop
  // only blocks upward motion and a straight string has no friction (ψ = 0): the bead leaves
  // at once and falls back at g.
  Model m = fixed_top();
  const double l = m.p.string_length, g = m.p.gravity, smin = m.p.top_stop, h = 0.2, v0 = 2.5;
  const double v = std::sqrt(v0 * v0 - 2 * g * h), t_land = (v0 - v) / g;
  const MotorSchedule sched(m.p.drive_radius, {{0.0, 0.0, 1.0}});
  for (const double dt : {-1e-6, 1e-6}) {
    State st = sim::explicit_state(m, sched, Vec3(0, 0, -(smin + h)), Vec3(0, 0, -l), Vec3(0, 0, v0), Vec3::Zero(),
                                   Mode::Sliding);
    const sim::RunSummary r = run_to(m, sched, st, t_land + dt);
    ASSERT_TRUE(r.ok()) << r.failure;
    if (dt < 0) {
      EXPECT_EQ(st.contact.mode, Mode::Sliding);
    } else {
      EXPECT_EQ(r.impacts, 1);
      EXPECT_NEAR(st.impact_loss, 0.5 * m.p.bead_mass * v * v, 1e-9 * m.p.bead_mass * v0 * v0);
      EXPECT_EQ(st.contact.mode, Mode::Sliding);
      EXPECT_EQ(st.contact.sigma, +1);
      EXPECT_NEAR(st.y(idx::v1 + 2), -g * dt, 1e-9);
      EXPECT_NEAR(st.y(idx::r1 + 2), -smin, 1e-9);
    }
  }
}

TEST(ContactModel, WithoutTheBottomStopTheCrossingIsReportedAndTheSingularityRefused) {
  // The free fall of the bead along a straight string with the bottom-stop layer off: it
  // passes L2 = d at t* = √(2 (0.3 - d)/g), reported as a violation from that instant, with
  // the penetration as its worst value; it falls on until 1e-4 l from the ball, where the
  // equations are singular, and the run ends there with that reason.
  Model m = fixed_top();
  m.layers.bottom_stop = false;
  const double l = m.p.string_length, d = m.p.contact_distance, g = m.p.gravity, L20 = 0.3;
  const double t_cross = std::sqrt(2 * (L20 - d) / g);
  const MotorSchedule sched(m.p.drive_radius, {{0.0, 0.0, 1.0}});
  State st = sim::explicit_state(m, sched, Vec3(0, 0, -(l - L20)), Vec3(0, 0, -l), Vec3::Zero(), Vec3::Zero(),
                                 Mode::Sliding);
  const sim::RunSummary r = run_to(m, sched, st, 1.0);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.failure.find("bottom-stop layer is off"), std::string::npos) << "failure: " << r.failure;
  ASSERT_EQ(r.violations.size(), 1u);
  EXPECT_NE(r.violations[0].what.find("below the bottom stop"), std::string::npos);
  EXPECT_EQ(r.violations[0].count, 1);
  EXPECT_NEAR(r.violations[0].first_time, t_cross, 1e-9);
  EXPECT_GT(r.violations[0].worst, 0.5 * d);
}
