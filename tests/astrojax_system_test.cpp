// The equations of motion in each mode: the tensions solved at each evaluation must keep the
// constraints at acceleration level, which is checked here independently by differencing the
// constraint along the exact quadratic motion; plus statics and rotational symmetry.
#include <gtest/gtest.h>

#include <cctype>
#include <ostream>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "physics/astrojax_system.hpp"
#include "physics/contact_modes.hpp"
#include "physics/string_friction.hpp"
#include "sim/simulation.hpp"

using namespace ajx::physics;
using ajx::numerics::Vec;

namespace {

Model test_model(Friction fr, FrictionLaw law = FrictionLaw::Capstan) {
  Model m;
  m.p.drive_radius = 0.015;
  m.layers.friction = fr;
  m.layers.friction_law = law;
  return m;
}

// A random taut state on the mode's constraints with velocities satisfying J v = b.
Vec random_state(const Model& m, Mode mode, const TopKinematics& top, std::mt19937& rng) {
  Contact c{mode, 0, 0.0};
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const double l = m.p.string_length;
  const double s = mode == Mode::BottomStop ? l - m.p.contact_distance : l * (0.3 + 0.4 * (U(rng) + 1) / 2);
  c.s_star = s;
  const Vec3 dir1 = Vec3(0.5 * U(rng), 0.5 * U(rng), -1.0).normalized();
  const Vec3 dir2 = Vec3(0.6 * U(rng), 0.6 * U(rng), -1.0).normalized();
  Vec y = Vec::Zero(idx::dim);
  y.segment<3>(idx::r1) = top.a + s * dir1;
  y.segment<3>(idx::r2) = y.segment<3>(idx::r1) + (l - s) * dir2;
  for (int i = 0; i < 6; ++i) y(idx::v1 + i) = 0.5 * U(rng);  // v/L <~ 20/s even on the 3 cm link
  project_positions(m, c, top, y);
  project_velocities(m, c, top, y);
  return y;
}

// Constraint values at t ± h along r(t ± h) = r ± v h + ½ r̈ h², with the exact top motion.
struct Lengths {
  double L1, L2;
};
Lengths lengths(const TopKinematics& top, const Vec3& r1, const Vec3& r2) {
  return {(r1 - top.a).norm(), (r2 - r1).norm()};
}

}  // namespace

TEST(AstrojaxSystem, HangingAtRestIsStatic) {
  Model m = test_model(Friction::Kinetic);
  const MotorSchedule sched(m.p.drive_radius, {{0.0, 0.0, 1.0}});
  const State s = ajx::sim::hanging_at_rest(m, sched);
  const Dynamics d = evaluate(m, sched.top(0.0), s.contact, s.y);
  const double g = m.p.gravity, m1 = m.p.bead_mass, m2 = m.p.ball_mass;
  EXPECT_NEAR(d.T1, (m1 + m2) * g, 1e-14);
  // A straight string has no friction: T2 = T1, and the bottom ball carries the bead's weight.
  EXPECT_NEAR(d.T2, (m1 + m2) * g, 1e-14);
  EXPECT_NEAR(d.contact, m1 * g, 1e-14);
  EXPECT_LT(d.acc1.norm(), 1e-14);
  EXPECT_LT(d.acc2.norm(), 1e-14);
  EXPECT_GT(d.margins.up, 0.0);
}

class ConstraintAcceleration : public ::testing::TestWithParam<std::tuple<Mode, Friction, FrictionLaw>> {};

TEST_P(ConstraintAcceleration, TensionsKeepTheStringLengthsAtSecondOrder) {
  const auto [mode, fr, law] = GetParam();
  const Model m = test_model(fr, law);
  const MotorSchedule sched(m.p.drive_radius, {{3.0, 40.0, 2.0}});  // a ramp: ω̇ = 18.5 rad/s²
  std::mt19937 rng(7);
  const double t = 1.3, h = 5e-4;
  const TopKinematics top = sched.top(t);
  for (int trial = 0; trial < 20; ++trial) {
    const Vec y = random_state(m, mode, top, rng);
    // σ = sgn ṡ while sliding; s* = L1 while stuck.
    const Geometry g0 = geometry(top, y.segment<3>(idx::r1), y.segment<3>(idx::r2), y.segment<3>(idx::v1),
                                 y.segment<3>(idx::v2));
    const Contact c{mode, g0.L1_dot > 0 ? 1 : -1, g0.L1};
    const Dynamics d = evaluate(m, top, c, y);
    const Vec3 r1 = y.segment<3>(idx::r1), r2 = y.segment<3>(idx::r2);
    const Vec3 v1 = y.segment<3>(idx::v1), v2 = y.segment<3>(idx::v2);
    const auto at = [&](double dt) {
      return lengths(sched.top(t + dt), r1 + v1 * dt + 0.5 * d.acc1 * dt * dt,
                     r2 + v2 * dt + 0.5 * d.acc2 * dt * dt);
    };
    // Second differences at h and h/2, Richardson-combined: the O(h²) term cancels and what is
    // left is ~ h⁴ |L⁽⁶⁾|/360 with |L⁽⁶⁾| <~ R ω⁶ ≈ 0.015 · 40⁶ ≈ 6e7 m/s⁶ from the top's
    // motion, ≈ 1e-11 at h = 5e-4, plus rounding 4 ε L / (h/2)² ≈ 1e-8. The tensions being
    // wrong by one centripetal term q ~ v²/L ~ 1 m/s² would show as O(1).
    const auto second = [&](double hh) {
      const Lengths p = at(hh), z = at(0.0), n = at(-hh);
      return std::pair{(p.L1 - 2 * z.L1 + n.L1) / (hh * hh), (p.L2 - 2 * z.L2 + n.L2) / (hh * hh)};
    };
    const auto [a1, a2] = second(h);
    const auto [b1, b2] = second(h / 2);
    const double L1dd = (4 * b1 - a1) / 3, L2dd = (4 * b2 - a2) / 3;
    const double tol = 1e-7;
    if (mode == Mode::Sliding) {
      EXPECT_NEAR(L1dd + L2dd, 0.0, tol);
      const double kappa = tension_ratio(law, sliding_mu(m), d.g.psi, c.sigma);
      EXPECT_NEAR(d.T1, kappa * d.T2, 1e-12 * std::abs(d.T1));
      if (d.T2 >= 0) {
        EXPECT_GE(d.friction_power, 0.0);
      }
    } else {
      EXPECT_NEAR(L1dd, 0.0, tol);
      EXPECT_NEAR(L2dd, 0.0, tol);
      EXPECT_EQ(d.friction_power, 0.0);
    }
    // Motor power is the top's force on the string times its velocity.
    EXPECT_NEAR(d.motor_power, -d.T1 * d.g.u1.dot(top.a_dot), 1e-15);
  }
}

// Parameters print by name in test names and messages (found by gtest through ADL).
namespace ajx::physics {
void PrintTo(Mode m, std::ostream* os) { *os << to_string(m); }
void PrintTo(Friction f, std::ostream* os) { *os << to_string(f); }
void PrintTo(FrictionLaw f, std::ostream* os) { *os << to_string(f); }
}  // namespace ajx::physics

INSTANTIATE_TEST_SUITE_P(
    Modes, ConstraintAcceleration,
    ::testing::Values(std::make_tuple(Mode::Sliding, Friction::None, FrictionLaw::Capstan),
                      std::make_tuple(Mode::Sliding, Friction::Kinetic, FrictionLaw::Capstan),
                      std::make_tuple(Mode::Sliding, Friction::Kinetic, FrictionLaw::PointContact),
                      std::make_tuple(Mode::BottomStop, Friction::Kinetic, FrictionLaw::Capstan),
                      std::make_tuple(Mode::Stuck, Friction::Kinetic, FrictionLaw::Capstan),
                      std::make_tuple(Mode::BottomStop, Friction::None, FrictionLaw::Capstan)),
    [](const auto& info) {  // e.g. sliding_kinetic_capstan
      std::string name = std::string(to_string(std::get<0>(info.param))) + "_" +
                         std::string(to_string(std::get<1>(info.param))) + "_" +
                         std::string(to_string(std::get<2>(info.param)));
      for (char& ch : name)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return name;
    });

TEST(AstrojaxSystem, RotatingTheSceneAboutTheAxisRotatesTheMotion) {
  // The physics is symmetric under rotations about ẑ: rotating the state by α and advancing
  // the motor phase by α gives the rotated accelerations and the same tensions.
  const Model m = test_model(Friction::Kinetic);
  const double alpha = 0.7;
  const MotorSchedule s0(m.p.drive_radius, {{10.0, 20.0, 1.0}}, 0.0), s1(m.p.drive_radius, {{10.0, 20.0, 1.0}}, alpha);
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(alpha, Vec3::UnitZ()).toRotationMatrix();
  std::mt19937 rng(3);
  for (Mode mode : {Mode::Sliding, Mode::BottomStop, Mode::Stuck}) {
    const TopKinematics top0 = s0.top(0.4), top1 = s1.top(0.4);
    ASSERT_LT((top1.a - Q * top0.a).norm(), 1e-15);
    const Vec y0 = random_state(m, mode, top0, rng);
    Vec y1 = y0;
    for (int k = 0; k < 4; ++k) y1.segment<3>(3 * k) = Q * y0.segment<3>(3 * k);
    const Contact c{mode, +1, (y0.segment<3>(idx::r1) - top0.a).norm()};
    const Dynamics d0 = evaluate(m, top0, c, y0), d1 = evaluate(m, top1, c, y1);
    EXPECT_NEAR(d1.T1, d0.T1, 1e-12 * std::abs(d0.T1));
    EXPECT_NEAR(d1.T2, d0.T2, 1e-12 * std::abs(d0.T2));
    EXPECT_LT((d1.acc1 - Q * d0.acc1).norm(), 1e-12 * d0.acc1.norm());
    EXPECT_LT((d1.acc2 - Q * d0.acc2).norm(), 1e-12 * d0.acc2.norm());
  }
}

TEST(AstrojaxSystem, PlasticImpactRemovesTheApproachVelocityAndAccountsEnergy) {
  // Landing on the bottom stop: after the impulse L̇1 = L̇2 = 0, and
  // ΔKE = -dissipated + impulsive motor work exactly.
  const Model m = test_model(Friction::Kinetic);
  const MotorSchedule sched(m.p.drive_radius, {{20.0, 20.0, 1.0}});
  const TopKinematics top = sched.top(0.2);
  std::mt19937 rng(11);
  Vec y = random_state(m, Mode::BottomStop, top, rng);
  y.segment<3>(idx::v2) += Vec3(0.3, -0.2, 0.5);  // an approach velocity off the new constraints
  const double ke0 = 0.5 * m.p.bead_mass * y.segment<3>(idx::v1).squaredNorm() +
                     0.5 * m.p.ball_mass * y.segment<3>(idx::v2).squaredNorm();
  const Contact stop{Mode::BottomStop, 0, 0.0};
  const ProjectionEnergy e = project_velocities(m, stop, top, y);
  const double ke1 = 0.5 * m.p.bead_mass * y.segment<3>(idx::v1).squaredNorm() +
                     0.5 * m.p.ball_mass * y.segment<3>(idx::v2).squaredNorm();
  const Drift drift = constraint_drift(m, stop, top, y);
  EXPECT_LT(drift.velocity, 1e-14);
  EXPECT_GT(e.dissipated, 0.0);
  EXPECT_NEAR(ke1 - ke0, -e.dissipated + e.motor_work, 1e-15);
}
