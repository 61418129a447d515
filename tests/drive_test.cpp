// The drive a(t) = R (cos φ, sin φ, 0): φ integrates ω_m, and ȧ, ä (with the ω̇ term) are the
// derivatives of a(t), checked by central differences with a derived error bound.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "physics/drive.hpp"

using namespace ajx::physics;

namespace {
constexpr double kR = 0.012;  // R [m]
MotorSchedule test_schedule() {
  return MotorSchedule(kR, {{5.0, 5.0, 2.0}, {5.0, 30.0, 3.0}, {30.0, 12.0, 1.5}});
}
}  // namespace

TEST(Drive, PhaseIsTheIntegralOfOmega) {
  const MotorSchedule s = test_schedule();
  EXPECT_DOUBLE_EQ(s.duration(), 6.5);
  // Simpson's rule on each piece is exact for the piecewise-linear ω.
  const double expected = 5.0 * 2.0 + 0.5 * (5.0 + 30.0) * 3.0 + 0.5 * (30.0 + 12.0) * 1.5;
  double phi, w, wd;
  s.phase(6.5, phi, w, wd);
  EXPECT_NEAR(phi, expected, 1e-12 * expected);
  EXPECT_DOUBLE_EQ(w, 12.0);
  // Past the end the last ω is held.
  double phi2;
  s.phase(7.5, phi2, w, wd);
  EXPECT_NEAR(phi2 - phi, 12.0, 1e-12 * phi2);
  EXPECT_EQ(wd, 0.0);
}

TEST(Drive, PhaseIsContinuousAtBreakpoints) {
  const MotorSchedule s = test_schedule();
  for (double tb : s.breakpoints()) {
    double pa, pb, wa, wb, d;
    s.phase(tb - 1e-12, pa, wa, d);
    s.phase(tb + 1e-12, pb, wb, d);
    // |Δφ| <= ω_max * 2e-12, |Δω| <= |ω̇| 2e-12 plus rounding.
    EXPECT_NEAR(pa, pb, 30.0 * 2e-12 + 1e-12);
    EXPECT_NEAR(wa, wb, 1e-9);
  }
}

TEST(Drive, VelocityAndAccelerationAreDerivativesOfPosition) {
  const MotorSchedule s = test_schedule();
  const double R = s.radius();
  EXPECT_EQ(R, kR);  // the schedule carries its R
  const double h = 1e-4;
  for (double t : {1.0, 3.3, 4.1, 5.9}) {  // inside segments, away from breakpoints
    const TopKinematics k = s.top(t);
    const Vec3 ap = s.top(t + h).a, am = s.top(t - h).a, a0 = k.a;
    const Vec3 v_fd = (ap - am) / (2 * h);
    const Vec3 acc_fd = (ap - 2 * a0 + am) / (h * h);
    // Truncation of the central differences: |a'''| h²/6 and |a''''| h²/12, with
    // |a'''| <= R(ω³ + 3ω|ω̇|) and |a''''| <= R(ω⁴ + 6ω²|ω̇| + 3ω̇²); rounding ε|a|/h and 4ε|a|/h².
    const double w = 30.0, wd = 25.0 / 3.0, eps = 2.2e-16;
    const double tol_v = R * (w * w * w + 3 * w * wd) * h * h / 6 + eps * R / h;
    const double tol_a = R * (w * w * w * w + 6 * w * w * wd + 3 * wd * wd) * h * h / 12 + 4 * eps * R / (h * h);
    EXPECT_LT((v_fd - k.a_dot).norm(), tol_v) << "t = " << t;
    EXPECT_LT((acc_fd - k.a_ddot).norm(), tol_a) << "t = " << t;
    // The ω̇ term matters: on the ramp ä has a tangential part R ω̇.
    if (k.omega_dot != 0.0) {
      const Vec3 tangential(-std::sin(k.phi), std::cos(k.phi), 0.0);
      EXPECT_NEAR(k.a_ddot.dot(tangential), R * k.omega_dot, 1e-12);
    }
  }
}

TEST(Drive, RejectsEmptyOrNonPositiveSegments) {
  EXPECT_THROW(MotorSchedule(kR, std::vector<DriveSegment>{}), std::invalid_argument);
  EXPECT_THROW(MotorSchedule(kR, {{1.0, 2.0, 0.0}}), std::invalid_argument);
  EXPECT_THROW(MotorSchedule(kR, {{1.0, 2.0, -1.0}}), std::invalid_argument);
  EXPECT_THROW(MotorSchedule(-kR, {{1.0, 2.0, 1.0}}), std::invalid_argument);  // R < 0
  EXPECT_THROW(MotorSchedule(std::nan(""), {{1.0, 2.0, 1.0}}), std::invalid_argument);
}
