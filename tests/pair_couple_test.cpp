// The pair couple (physics/pair_couple.hpp, the diagnostic layer pair_couple = "motor_clutch"):
// a pure couple about ẑ, τ sin²θ12 about the axis, zero for a lower segment turning with the
// motor; off by default and then without any effect; the ledger closes with it on.
#include <gtest/gtest.h>

#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "config/config.hpp"
#include "physics/astrojax_system.hpp"
#include "physics/pair_couple.hpp"
#include "sim/simulation.hpp"
#include "measured.hpp"

using namespace ajx;
using namespace ajx::physics;

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

Model couple_model(double tau_c, double slip_rate) {
  Model m;
  m.layers.pair_couple = PairCouple::MotorClutch;
  m.p.couple_torque = tau_c;
  m.p.couple_slip_rate = slip_rate;
  return m;
}

// A constructed state: the bead off the axis, the lower segment of length L2 tilted by θ at
// azimuth α, ḋ2 = Ω_b ẑ × d2 + λ d2 + μ ẑ (a spin Ω_b about z plus a stretch and a vertical
// rate, neither of which turns the segment about z: β̇ = Ω_b exactly).
struct Constructed {
  Vec3 r1, r2, v1, v2;
  double L2, theta;
};
Constructed constructed(double theta, double spin) {
  Constructed c;
  c.L2 = 0.035;
  c.theta = theta;
  const double alpha = 0.7;
  const Vec3 d2 = c.L2 * Vec3(std::sin(theta) * std::cos(alpha), std::sin(theta) * std::sin(alpha), -std::cos(theta));
  c.r1 = Vec3(0.012, -0.004, -0.79);
  c.r2 = c.r1 + d2;
  c.v1 = Vec3(0.3, -0.2, 0.05);
  c.v2 = c.v1 + spin * Vec3(-d2.y(), d2.x(), 0.0) + 0.4 * d2 - 0.1 * Vec3::UnitZ();
  return c;
}

}  // namespace

TEST(PairCouple, PureCoupleWithTorqueTauSin2Theta) {
  // Zero net force, and Σ (r_i × F_i)_z = ((r2 − r1) × F2)_z = τ ρ²/L2² = τ sin²θ12, with
  // τ = τ_c tanh(w/Ω_ε), w = (ω_m − β̇) ρ²/(ρ² + (ε L2)²). Tolerances: a few ulps of the
  // largest term (|F| ≤ τ_c/L2 ≈ 0.03 N here; torques ~ τ_c).
  const double tau_c = 1e-3, slip_rate = 2.0, omega_m = 39.0, spin = 30.0;
  const Model m = couple_model(tau_c, slip_rate);
  for (double theta : {0.3, 1.0, 1.5, 2.5}) {
    const Constructed c = constructed(theta, spin);
    const PairCoupleForces f = pair_couple_forces(m, omega_m, c.r1, c.r2, c.v1, c.v2);
    const double s2 = std::sin(theta) * std::sin(theta);
    const double w = (omega_m - spin) * s2 / (s2 + kCoupleTiltFloor * kCoupleTiltFloor);
    const double tau = tau_c * std::tanh(w / slip_rate);
    EXPECT_NEAR(f.couple, tau, 16 * eps * tau_c) << "θ " << theta;
    EXPECT_LE((f.f1 + f.f2).norm(), 4 * eps * tau_c / c.L2) << "θ " << theta;
    const double torque_z = c.r1.cross(f.f1).z() + c.r2.cross(f.f2).z();
    EXPECT_NEAR(torque_z, tau * s2, 64 * eps * tau_c) << "θ " << theta;
    EXPECT_LE(f.f2.norm(), tau_c / c.L2 * (1 + 4 * eps));
    // Its power on the balls, F2·(v2 − v1) = τ ẑ·(d2 × ḋ2)/L2² = τ β̇ sin²θ12; the motor turns
    // its side at ω_m against τ sin²θ12, and the slip takes the rest, τ (ω_m − β̇) sin²θ12 >= 0.
    EXPECT_NEAR(f.power, tau * spin * s2, 64 * eps * tau_c * spin);
    EXPECT_NEAR(f.loss, tau * (omega_m - spin) * s2, 64 * eps * tau_c * omega_m);
    EXPECT_NEAR(f.power + f.loss, torque_z * omega_m, 64 * eps * tau_c * omega_m);
    EXPECT_GT(f.loss, 0.0);
    EXPECT_GT(tau, 0.0);  // the pair lags: the couple turns it forwards
  }
  // A vertical lower segment: no lever, no force, and nothing divides by zero.
  const Constructed v = constructed(0.0, spin);
  const PairCoupleForces f0 = pair_couple_forces(m, omega_m, v.r1, v.r2, v.v1, v.v2);
  EXPECT_TRUE(std::isfinite(f0.slip));
  EXPECT_EQ(f0.f2.norm(), 0.0);
}

TEST(PairCouple, EquationsOfMotionSeeAPureCouple) {
  // Through evaluate(), in free flight (slack: the string passes no force): m1 r̈1 + m2 r̈2 is
  // unchanged by the couple and its z-moment about the axis grows by τ sin²θ12. Tolerance:
  // rounding of m r̈ ~ m g = 0.18 N, a few ulps.
  const Model off;
  const Model on = couple_model(5e-4, 1.0);
  const Constructed c = constructed(1.1, 10.0);
  numerics::Vec y = numerics::Vec::Zero(idx::dim);
  y.segment<3>(idx::r1) = c.r1;
  y.segment<3>(idx::r2) = c.r2;
  y.segment<3>(idx::v1) = c.v1;
  y.segment<3>(idx::v2) = c.v2;
  const TopKinematics top = point_on_circle(0.015, 0.2, 40.0, 0.1);
  const Contact slack(Mode::Slack);
  const Dynamics a = evaluate(off, top, slack, y), b = evaluate(on, top, slack, y);
  const double m1 = on.p.bead_mass, m2 = on.p.ball_mass;
  const Vec3 dp = m1 * (b.acc1 - a.acc1) + m2 * (b.acc2 - a.acc2);
  const double scale = (m1 + m2) * on.p.gravity;
  EXPECT_LE(dp.norm(), 8 * eps * scale);
  const double dL = m1 * c.r1.cross(b.acc1 - a.acc1).z() + m2 * c.r2.cross(b.acc2 - a.acc2).z();
  const PairCoupleForces f = pair_couple_forces(on, top.motor_omega, c.r1, c.r2, c.v1, c.v2);
  EXPECT_NEAR(dL, f.couple * std::sin(1.1) * std::sin(1.1), 8 * eps * scale);
  EXPECT_EQ(b.couple_power, f.power);
  EXPECT_EQ(a.couple_power, 0.0);
}

TEST(PairCouple, ZeroWhenTheLowerSegmentTurnsWithTheMotor) {
  // Both balls turning rigidly about the axis at ω_m (v_i = ω_m ẑ × r_i): β̇ = ω_m, so w = 0 up
  // to the rounding of v2 − v1 (a few ulps of ω_m L2), and τ ≤ τ_c w/Ω_ε.
  const double tau_c = 1e-3, slip_rate = 0.1, omega_m = 39.0;
  const Model m = couple_model(tau_c, slip_rate);
  for (double theta : {0.2, 1.0, 1.4}) {
    const Constructed c = constructed(theta, 0.0);
    const Vec3 z = Vec3::UnitZ();
    const PairCoupleForces f = pair_couple_forces(m, omega_m, c.r1, c.r2, omega_m * z.cross(c.r1),
                                                  omega_m * z.cross(c.r2));
    const double w_round = 16 * eps * omega_m * (c.r1.norm() / c.L2) / std::pow(std::sin(theta), 2);
    EXPECT_LE(std::abs(f.slip), w_round) << "θ " << theta;
    EXPECT_LE(std::abs(f.couple), tau_c * w_round / slip_rate) << "θ " << theta;
  }
  // And it opposes a lead as it drives a lag: odd in ω_m − β̇.
  const Constructed c = constructed(1.0, 35.0);
  const double lead = pair_couple_forces(m, 31.0, c.r1, c.r2, c.v1, c.v2).couple;
  const double lag = pair_couple_forces(m, 39.0, c.r1, c.r2, c.v1, c.v2).couple;
  EXPECT_NEAR(lead, -lag, 16 * eps * tau_c);
  EXPECT_LT(lead, 0.0);
}

namespace {

// The rise's ramp in short: hanging at rest, ω_m 0 → 45 rad/s over 40 s, R = 2 cm, full model.
sim::RunSummary spin_up(const Model& m, numerics::Vec* y_end = nullptr, double* couple_work = nullptr) {
  const MotorSchedule sched(m.p.drive_radius, {{0.0, 45.0, 40.0}});
  State s = sim::hanging_at_rest(m, sched);
  sim::RunOptions o;
  o.method = "dopri5";
  o.integ.tol.rtol = 1e-10;
  o.integ.tol.atol = 1e-12;
  sim::Simulation simulation(m, sched, o);
  double work = 0.0, t_prev = 0.0, p_prev = 0.0;
  const sim::RunSummary r = simulation.run(s, 40.0, 0.01, [&](const sim::Sample& smp) {
    work += 0.5 * (smp.dyn.couple_power + p_prev) * (smp.t - t_prev);  // trapezoid, for scale only
    t_prev = smp.t;
    p_prev = smp.dyn.couple_power;
  });
  if (y_end) *y_end = s.y;
  if (couple_work) *couple_work = work;
  return r;
}

}  // namespace

TEST(PairCouple, OffOrZeroLeavesEveryRunBitIdentical) {
  // Layer "none" ignores τ_c: the same bits. "motor_clutch" with τ_c = 0 adds exact zeros to the
  // forces, but its state carries the motor's ledger (W_m, W_c: two more quadratures, so the error
  // control takes other steps): the same trajectory to the integration's accuracy (rtol 1e-10 on
  // a run of ~1 m: 1e-6 m leaves decades), and W_m = W_s (the same rates summed by the same
  // stepper), W_c = 0, exactly.
  Model base;
  base.p.drive_radius = 0.02;
  Model ignored = base;
  ignored.p.couple_torque = 1e-3;
  Model zero = couple_model(0.0, 1.0);
  zero.p.drive_radius = 0.02;
  numerics::Vec y0, y1, y2;
  const sim::RunSummary r0 = spin_up(base, &y0), r1 = spin_up(ignored, &y1), r2 = spin_up(zero, &y2);
  ASSERT_TRUE(r0.ok()) << r0.failure;
  EXPECT_EQ(r0.steps, r1.steps);
  EXPECT_TRUE(y0 == y1);
  ASSERT_EQ(y2.size(), idx::dim_ledger);
  EXPECT_LT((y0.head<12>() - y2.head<12>()).norm(), 1e-6);
  EXPECT_EQ(y2(idx::clutch_loss), 0.0);
  EXPECT_EQ(y2(idx::rod_work), y2(idx::motor_work));  // the same rates, the same impulses
}

TEST(PairCouple, EnergyLedgerClosesWithTheCoupleOn) {
  // W_m (the motor's, the couple's side included) = W_c (the couple's slip) + ΔE + drag +
  // friction + impacts, and W_m = W_c + W_s (W_s: the string's work and the couple's on the balls). As the ledger
  // tests of simulation_test: the work integrals are quadratures of the integrator, each step's
  // local error is below rtol = 1e-10 of the terms, so after N steps the residual stays below
  // N × 1e-10 of W_m (the 1e-6 of simulation_test is this bound for N = 1e4). The couple must do
  // work well above that tolerance, so that leaving it out of the ledger would fail the test.
  Model m = couple_model(1e-3, 1.0);
  m.p.drive_radius = 0.02;
  double couple_work = 0.0;
  const sim::RunSummary r = spin_up(m, nullptr, &couple_work);
  ASSERT_TRUE(r.ok()) << r.failure;
  const double tol = double(r.steps) * 1e-10 * std::abs(r.energy.motor_work);
  EXPECT_LT(std::abs(r.energy.residual), tol)
      << "W_m " << r.energy.motor_work << " ΔE " << r.energy.delta_energy << " drag " << r.energy.drag_loss
      << " friction " << r.energy.friction_loss << " impact " << r.energy.impact_loss;
  EXPECT_LT(std::abs(r.energy.tie_residual), tol);
  EXPECT_GT(std::abs(couple_work), 1e3 * tol);
  EXPECT_GT(r.energy.clutch_loss, 1e3 * tol);  // the couple slips: leaving its loss out would fail
  report("pair_couple_balance", fmt::format("W_m {:.6e} J, W_s {:.6e} J (couple on the balls ≈ {:.3e} J), couple's slip "
                                            "{:.3e} J, residual {:.2e} J, steps {}",
                                            r.energy.motor_work, r.energy.string_work, couple_work,
                                            r.energy.clutch_loss, r.energy.residual, r.steps));
}

TEST(PairCouple, ConfigNamesFileKeyAndRange) {
  const std::string text = R"(
[model]
couple_torque = 6e-4
[layers]
pair_couple = "motor_clutch"
[[schedule]]
kind = "hold"
omega = 1.0
duration = 1.0
[output]
path = "out/x.h5"
)";
  const config::RunConfig c = config::parse_run_config(text, "f.toml");
  EXPECT_EQ(c.model.layers.pair_couple, PairCouple::MotorClutch);
  EXPECT_DOUBLE_EQ(c.model.p.couple_torque, 6e-4);
  EXPECT_DOUBLE_EQ(c.model.p.couple_slip_rate, 1.0);
  EXPECT_EQ(config::parse_run_config(text, "f.toml", {"layers.pair_couple=none"}).model.layers.pair_couple,
            PairCouple::None);
  auto error_of = [&](const std::string& t, const std::vector<std::string>& o) -> std::string {
    try {
      config::parse_run_config(t, "f.toml", o);
    } catch (const config::ConfigError& e) {
      return e.what();
    }
    return "";
  };
  const std::string neg = error_of(text, {"model.couple_torque=-1e-4"});
  EXPECT_NE(neg.find("f.toml"), std::string::npos) << neg;
  EXPECT_NE(neg.find("couple_torque"), std::string::npos) << neg;
  EXPECT_NE(neg.find("[0"), std::string::npos) << neg;
  const std::string rate = error_of(text, {"model.couple_slip_rate=0"});
  EXPECT_NE(rate.find("couple_slip_rate"), std::string::npos) << rate;
  EXPECT_NE(rate.find("(0"), std::string::npos) << rate;
  const std::string layer = error_of(text, {"layers.pair_couple=twist"});
  EXPECT_NE(layer.find("pair_couple"), std::string::npos) << layer;
  EXPECT_NE(layer.find("motor_clutch"), std::string::npos) << layer;
  std::string no_torque = text;
  no_torque.replace(no_torque.find("couple_torque = 6e-4"), 20, "");
  const std::string missing = error_of(no_torque, {});
  EXPECT_NE(missing.find("model.couple_torque"), std::string::npos) << missing;
}
