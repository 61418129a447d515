// Whole trajectories of the hybrid system: energy conservation and balance, constraint
// drift, convergence order on the full equations, and the analytic steady state of the pair
// resting on the bottom stop.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <fmt/format.h>

#include "numerics/stepper.hpp"
#include "physics/astrojax_system.hpp"
#include "physics/energy.hpp"
#include "sim/simulation.hpp"
#include "steady_orbit.hpp"
#include "measured.hpp"

using namespace ajx;
using namespace ajx::physics;
using ajx::numerics::Vec;

namespace {

sim::RunOptions tight(const std::string& method, double rtol) {
  sim::RunOptions o;
  o.method = method;
  o.integ.tol.rtol = rtol;
  o.integ.tol.atol = rtol * 1e-2;
  return o;
}

// The circular orbit of the paper's Table 1 (cm): bead at radius 14.427, height -52.483;
// bottom ball opposite at radius 11.924, height -62.353, turning at ω ≈ 4.7π rad/s.
State table1_state(const Model& m, const MotorSchedule& sched, double omega) {
  const Vec3 r1(-0.14427, 0.0, -0.52483), r2(0.11924, 0.0, -0.62353);
  const Vec3 w(0, 0, omega);
  return sim::explicit_state(m, sched, r1, r2, w.cross(r1), w.cross(r2), Mode::Sliding, 0.0, 1e-2);
}

// Record a measured figure in the test's XML and print it (ctest -V shows it).
}  // namespace

TEST(Simulation, FreeFrictionlessMotionConservesEnergy) {
  // c_D = 0, μ = 0, R = 0: E is conserved; relative drift below 1e-9 over 100 s. The scene:
  // the bead 0.3 m down the string at 0.5 rad from the vertical, the lower segment at 0.9 rad,
  // both spinning at 6 rad/s about the axis through the fixed top: the bead slides to and fro
  // on a taut string and never reaches the bottom ball (a landing would fail the run).
  Model m;
  m.p.drag = 0.0;
  m.p.drive_radius = 0.0;
  m.layers.friction = Friction::None;
  m.layers.bottom_stop = false;
  const MotorSchedule sched(m.p.drive_radius, {{0.0, 0.0, 100.0}});
  const double l = m.p.string_length, s0 = 0.3;
  const Vec3 r1 = s0 * Vec3(std::sin(0.5), 0, -std::cos(0.5));
  const Vec3 r2 = r1 + (l - s0) * Vec3(std::sin(0.9), 0, -std::cos(0.9));
  const Vec3 w(0, 0, 6.0);
  State s = sim::explicit_state(m, sched, r1, r2, w.cross(r1), w.cross(r2), Mode::Sliding);
  const double E0 = mechanical_energy(m.p, s.y);
  // The energy scale: (m1 + m2) g l, the depth of the potential well.
  const double scale = (m.p.bead_mass + m.p.ball_mass) * m.p.gravity * l;
  double worst = 0.0, L1_min = l, L1_max = 0.0;
  sim::Simulation simulation(m, sched, tight("dop853", 1e-13));
  const sim::RunSummary r = simulation.run(s, 100.0, 0.01, [&](const sim::Sample& smp) {
    worst = std::max(worst, std::abs(mechanical_energy(m.p, smp.y) - E0) / scale);
    L1_min = std::min(L1_min, smp.dyn.g.L1);
    L1_max = std::max(L1_max, smp.dyn.g.L1);
  });
  ASSERT_TRUE(r.ok()) << r.failure;
  ASSERT_GT(r.min_tension, 0.0) << "the string went slack: not a taut-string scene";
  EXPECT_GT(L1_max - L1_min, 0.05) << "the bead should slide along the string";
  EXPECT_LT(worst, 1e-9);
  report("relative_energy_drift", fmt::format("{:.3e}", worst));
}

TEST(Simulation, MotorWorkBalancesEnergyDragFrictionAndImpacts) {
  // Drive, drag and kinetic friction on: W_m = ΔE + drag + friction + impact losses to 1e-6
  // of W_m, and the friction power is never negative.
  for (auto law : {FrictionLaw::Capstan, FrictionLaw::PointContact}) {
    Model m;
    m.p.drive_radius = 0.02;
    m.layers.friction = Friction::Kinetic;
    m.layers.friction_law = law;
    const MotorSchedule sched(m.p.drive_radius, {{0.0, 45.0, 40.0}});  // 0 → ~14π rad/s over 40 s
    State s = sim::hanging_at_rest(m, sched);
    sim::Simulation simulation(m, sched, tight("dopri5", 1e-10));
    const sim::RunSummary r = simulation.run(s, 40.0, 0.01);
    ASSERT_TRUE(r.ok()) << r.failure;
    ASSERT_GE(r.min_tension, 0.0) << "the scene left the taut-string model";
    EXPECT_LT(std::abs(r.energy.residual), 1e-6 * std::abs(r.energy.motor_work))
        << "W_m " << r.energy.motor_work << " ΔE " << r.energy.delta_energy << " drag "
        << r.energy.drag_loss << " friction " << r.energy.friction_loss << " impact " << r.energy.impact_loss;
    EXPECT_GE(r.min_friction_power, 0.0);
    EXPECT_GT(r.energy.motor_work, 0.0);
    report(std::string(law == FrictionLaw::Capstan ? "capstan" : "point_contact") + "_balance",
                   fmt::format("W_m {:.6e} J, residual {:.2e} J, friction {:.3e} J, impacts {:.3e} J, sticks {}",
                               r.energy.motor_work, r.energy.residual, r.energy.friction_loss,
                               r.energy.impact_loss, r.sticks));
  }
}

TEST(Simulation, EnergyClosesThroughStickSlipSlackPhasesAndImpacts) {
  // The full model on a violent spin-up (R = 6 cm, ω_m 2π → 14π rad/s): the bead sticks and
  // slips, the string goes slack and snaps taut again, the bead lands on the bottom ball.
  // W_m = ΔE + drag + friction + impact losses must still close to 1e-6 of W_m.
  Model m;
  m.p.drive_radius = 0.06;
  m.layers.friction = Friction::StickSlip;
  const double pi = 3.141592653589793;
  const MotorSchedule sched(m.p.drive_radius, {{2 * pi, 2 * pi, 10.0}, {2 * pi, 14 * pi, 75.4}, {14 * pi, 14 * pi, 20.0}});
  State s = sim::hanging_at_rest(m, sched);
  sim::Simulation simulation(m, sched, tight("dopri5", 1e-10));
  const sim::RunSummary r = simulation.run(s, sched.duration(), 0.01);
  ASSERT_TRUE(r.ok()) << r.failure;
  EXPECT_GT(r.sticks, 0);
  EXPECT_GT(r.slack_phases, 0);
  EXPECT_GT(r.impacts, 0);
  EXPECT_LT(std::abs(r.energy.residual), 1e-6 * r.energy.motor_work);
  EXPECT_GE(r.min_friction_power, 0.0);
  report("full_model_balance",
         fmt::format("W_m {:.6e} J, residual {:.2e} J, friction {:.3e} J, impacts {:.3e} J ({}), sticks {}, slack {}",
                     r.energy.motor_work, r.energy.residual, r.energy.friction_loss, r.energy.impact_loss, r.impacts,
                     r.sticks, r.slack_phases));
}

TEST(Simulation, ConstraintDriftStaysBelow1e10OverA600sRun) {
  Model m;
  m.p.drive_radius = 0.01;
  const MotorSchedule sched(m.p.drive_radius, {{0.0, 30.0, 300.0}, {30.0, 10.0, 300.0}});
  State s = sim::hanging_at_rest(m, sched);
  sim::Simulation simulation(m, sched, tight("dopri5", 1e-9));
  const sim::RunSummary r = simulation.run(s, 600.0, 0.05);
  ASSERT_TRUE(r.ok()) << r.failure;
  EXPECT_LT(r.max_sample_drift, 1e-10);
  EXPECT_LT(r.max_drift, 1e-10);
  report("max_drift", fmt::format("{:.3e}", r.max_drift));
}

namespace {

// Fixed-step integration of the sliding mode (no events, no projection) with a stepper's
// propagated solution, for the order measurement.
Vec fixed_step(const Model& m, const MotorSchedule& sched, const std::string& method, Vec y,
               double T, int n) {
  auto stepper = numerics::make_stepper(method);
  const Contact sliding{Mode::Sliding, 0, 0.0};  // frictionless: σ plays no role
  const numerics::System f = [&](double t, const Vec& x, Vec& dx) { rhs(m, sched, sliding, t, x, dx); };
  numerics::Tolerances tol;
  Vec ynew(y.size());
  const double h = T / n;
  for (int k = 0; k < n; ++k) {
    stepper->attempt(f, k * h, y, h, ynew, tol);
    stepper->accept(f);
    y = ynew;
  }
  return y;
}

}  // namespace

TEST(Simulation, MeasuredConvergenceOrderOfRk4AndDopri5) {
  // Frictionless sliding with the drive on a ramp (ω̇ ≠ 0) from the Table 1 orbit: a smooth
  // scene with no mode switch in 0.5 s. Error of the state against a dop853 reference at the
  // finest step; order p = log2(e(h)/e(2h)) over successive halvings. Dopri5's fifth-order
  // error constant is small, so a sixth-order term still shows at moderate h: its estimates
  // approach 5 from above (5.7, 5.5, 5.3, 5.1). The test asserts the approach is monotone and
  // the finest estimate within 0.3 of nominal, with errors (>= 1e-13) well above the
  // round-off of ~800 steps (~1e-15).
  Model m;
  m.layers.friction = Friction::None;
  const MotorSchedule sched(m.p.drive_radius, {{14.0, 16.0, 10.0}});
  const Vec y0 = table1_state(m, sched, 14.0).y;
  const double T = 0.5;
  for (const auto& [method, order, n0] : {std::tuple{std::string("rk4"), 4, 50}, std::tuple{std::string("dopri5"), 5, 50}}) {
    const Vec ref = fixed_step(m, sched, "dop853", y0, T, 16 * n0);
    std::vector<double> err, p;
    for (int n = n0; n <= 16 * n0; n *= 2) {
      err.push_back((fixed_step(m, sched, method, y0, T, n).head(12) - ref.head(12)).norm());
      if (err.size() > 1) p.push_back(std::log2(err[err.size() - 2] / err.back()));
    }
    ASSERT_GT(err.back(), 1e-13) << "errors reached round-off: the order would be meaningless";
    EXPECT_NEAR(p.back(), order, 0.3) << method;
    for (std::size_t i = 1; i < p.size(); ++i)
      EXPECT_LT(std::abs(p[i] - order), std::abs(p[i - 1] - order) + 0.02) << method << " estimate " << i;
    std::string all;
    for (double x : p) all += fmt::format("{:.3f} ", x);
    report(method + "_orders", all);
  }
}

TEST(Simulation, PairOnTheBottomStopSettlesToTheSteadyConicalOrbit) {
  // Drag mass-proportional on both balls (c_D/m equal) damps every mode as e^{-c_D t/(2m)};
  // with c_D = 0.02 kg/s that is e^{-0.556 t}: after 80 s an initial 0.1 m transient is 5e-21 m,
  // far below the integrator's 1e-11 relative tolerance. Tolerance: 1e-8 m on positions.
  for (double w : {2.0, 9.0}) {  // below and above the pendulum frequency √(g/l) ≈ 3.45 rad/s
    Model m;
    m.p.drag = 0.02;
    m.p.drive_radius = 0.02;
    const MotorSchedule sched(m.p.drive_radius, {{w, w, 80.0}});
    State s = sim::hanging_at_rest(m, sched);
    sim::Simulation simulation(m, sched, tight("dop853", 1e-11));
    const sim::RunSummary r = simulation.run(s, 80.0, 0.0);
    ASSERT_TRUE(r.ok()) << r.failure;
    ASSERT_EQ(s.contact.mode, Mode::BottomStop);
    // The co-rotating force balance (tests/steady_orbit.hpp), solved independently.
    const double L1 = m.p.string_length - m.p.contact_distance, L2 = m.p.contact_distance;
    const auto x = test::solve_steady(m.p, L1, L2, w, test::linear_guess(m.p, L1, L2, w));
    ASSERT_LT(test::steady_residual(m.p, L1, L2, w, x).norm(), 1e-12) << "Newton did not converge";
    // The simulated state in the co-rotating frame.
    double phi, om, od;
    sched.phase(s.t, phi, om, od);
    const Eigen::Matrix3d Q = Eigen::AngleAxisd(-phi, Vec3::UnitZ()).toRotationMatrix();
    const Vec3 p1 = Q * Vec3(s.y.segment<3>(idx::r1)), p2 = Q * Vec3(s.y.segment<3>(idx::r2));
    EXPECT_LT((p1 - x.segment<3>(0)).norm(), 1e-8) << "ω = " << w;
    EXPECT_LT((p2 - x.segment<3>(3)).norm(), 1e-8) << "ω = " << w;
    // ω_ball = ω on a locked orbit.
    EXPECT_NEAR(r.omega_ball, w, 1e-6);
    report("radius_bottom_ball_w" + std::to_string(int(w)), fmt::format("{:.6e}", x.segment<2>(3).norm()));
  }
}

TEST(Simulation, AJammedPointContactEndsTheRunWithAReasonNotACrash) {
  // μ tan(ψ/2) >= 1 has no sliding solution for the point-contact law: with μ_k = 2 the
  // law jams once ψ > 2 atan(1/2) ≈ 0.93 rad. A sharply bent string gets there at once.
  Model m;
  m.p.mu_static = m.p.mu_kinetic = 2.0;
  m.p.drive_radius = 0.0;
  m.layers.friction_law = FrictionLaw::PointContact;
  const MotorSchedule sched(m.p.drive_radius, {{0.0, 0.0, 1.0}});
  const Vec3 r1(0.3, 0.0, -0.3), r2 = r1 + (m.p.string_length - r1.norm()) * Vec3(-1, 0, 0);
  State s = sim::explicit_state(m, sched, r1, r2, Vec3(0, 0, 0.5), Vec3::Zero(), Mode::Sliding);
  sim::Simulation simulation(m, sched, tight("dopri5", 1e-9));
  const sim::RunSummary r = simulation.run(s, 1.0, 0.01);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.failure.find("jams"), std::string::npos) << r.failure;
  EXPECT_TRUE(s.y.allFinite());
}

TEST(Simulation, SampleSpansDeliverExactlyTheGridSamplesInsideThem) {
  // With sample spans the run hands out the grid samples inside [begin, end) only, and each is
  // bit-identical to the same sample of the unfiltered run (the steps do not depend on them).
  // Spans that begin and end between and on grid points, and one past the run's end.
  Model m;
  m.p.drive_radius = 0.015;
  const double pi = 3.141592653589793;
  const MotorSchedule sched(m.p.drive_radius, {{4 * pi, 6 * pi, 3.0}});
  const double dt = 0.02;
  const std::vector<std::pair<double, double>> spans{{0.0, 0.1}, {0.505, 1.0}, {1.37, 1.5}, {2.9, 4.0}};
  std::vector<std::pair<double, Vec>> all, kept;
  for (bool filtered : {false, true}) {
    sim::RunOptions o = tight("dop853", 1e-9);
    if (filtered) o.sample_spans = spans;
    State s = table1_state(m, sched, 4 * pi);
    sim::Simulation simulation(m, sched, o);
    auto& out = filtered ? kept : all;
    const sim::RunSummary r =
        simulation.run(s, 3.0, dt, [&](const sim::Sample& smp) { out.emplace_back(smp.t, smp.y); }, 0.0);
    ASSERT_TRUE(r.ok()) << r.failure;
  }
  std::vector<std::pair<double, Vec>> expected;
  for (const auto& [t, y] : all)
    for (const auto& [b, e] : spans)
      if (t >= b && t < e) expected.emplace_back(t, y);
  ASSERT_EQ(kept.size(), expected.size());
  EXPECT_GT(kept.size(), 20u);
  EXPECT_LT(kept.size(), all.size() / 2);
  for (std::size_t i = 0; i < kept.size(); ++i) {
    EXPECT_EQ(kept[i].first, expected[i].first);
    EXPECT_EQ(kept[i].second, expected[i].second) << "t = " << kept[i].first;
  }
}
