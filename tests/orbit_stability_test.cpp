// Linear stability of locked orbits on the constraint manifold: the double pendulum at rest
// against its analytic frequencies, the Hamiltonian symmetry of the spectrum without drag,
// and orbits handed to the project's Simulation: an unstable one departs at the predicted
// rate, a stable one stays and its perturbation decays at the predicted rate.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fmt/format.h>
#include <numbers>

#include "orbits/corotating_frame.hpp"
#include "orbits/orbit_families.hpp"
#include "orbits/orbit_stability.hpp"
#include "sim/simulation.hpp"
#include "measured.hpp"

using namespace ajx;
using namespace ajx::orbits;

namespace {

constexpr double kPi = std::numbers::pi;

sim::RunOptions tight() {
  sim::RunOptions o;
  o.method = "dop853";
  o.integ.tol.rtol = 1e-11;
  o.integ.tol.atol = 1e-13;
  return o;
}

// Simulate from the orbit X displaced by δz0 (in the frame), holding ω; return |q(t) − q*| at
// the given times, measured in the co-rotating frame.
std::vector<double> departure(const physics::Model& m, const OrbitProblem& pb, const Vec9& X, const Vec12& dz0,
                              const std::vector<double>& times, physics::Mode* final_mode = nullptr) {
  const physics::MotorSchedule sched(m.p.drive_radius, {{pb.omega, pb.omega, times.back() + 1.0}});
  const Vec12 z0 = frame_coordinates(X) + dz0;
  const numerics::Vec y = lab_state(z0, pb.omega);
  const physics::Contact c = holding_contact(m, pb.closure, X(8));
  physics::State s = sim::explicit_state(m, sched, y.segment<3>(0), y.segment<3>(3), y.segment<3>(6),
                                         y.segment<3>(9), c.mode, 0.0, 1e-6);
  EXPECT_EQ(s.contact.mode, c.mode);
  sim::Simulation simulation(m, sched, tight());
  std::vector<double> out;
  double t = 0.0;
  for (double te : times) {
    if (te > t) {
      const sim::RunSummary r = simulation.run(s, te, 0.0);
      EXPECT_TRUE(r.ok()) << r.failure;
    }
    t = te;
    const Vec12 z = frame_state(s.y, pb.omega * s.t, pb.omega);
    out.push_back((z.head<6>() - X.head<6>()).norm());
  }
  if (final_mode) *final_mode = s.contact.mode;
  return out;
}

// A real displacement along the leading eigenvector, of size eps in positions.
Vec12 along_mode(const Stability& st, double eps) {
  Vec12 v = st.leading_mode.real();
  if (v.head<6>().norm() < 1e-3 * v.norm()) v = st.leading_mode.imag();
  return eps * v / v.head<6>().norm();
}

}  // namespace

TEST(OrbitStability, DoublePendulumAtRestHasItsAnalyticFrequencies) {
  // ω_m = 0, R = 0: the pair hanging on the bottom stop is a spherical double pendulum with
  // links a = l − d, b = d. Its frequencies solve m1 a b Ω⁴ − M (a + b) g Ω² + M g² = 0
  // (M = m1 + m2), each twice (two planes of swing); with equal masses the drag is
  // proportional to the mass matrix, so λ = −c/(2m) ± i √(Ω² − (c/2m)²). The finite
  // differences of the linearisation (steps ε^(1/3) of the shorter link) are good to
  // ε^(2/3) ≈ 4e-11 relative; allow 1e-9.
  const physics::Model m0;
  physics::Model m = m0;
  m.p.drive_radius = 0.0;
  const double a = m.p.string_length - m.p.contact_distance, b = m.p.contact_distance;
  const double m1 = m.p.bead_mass, M = m1 + m.p.ball_mass, g = m.p.gravity, gam = m.p.drag / (2 * m1);
  const double A = m1 * a * b, B = -M * (a + b) * g, C = M * g * g;
  const double disc = std::sqrt(B * B - 4 * A * C);
  std::vector<double> expected;
  for (double W2 : {(-B - disc) / (2 * A), (-B + disc) / (2 * A)})
    for (int k = 0; k < 2; ++k) expected.push_back(std::sqrt(W2 - gam * gam));
  const OrbitProblem pb{m, 0.0, Closure::BottomStop, 0.0};
  Vec9 X;
  X << 0, 0, -a, 0, 0, -a - b, M * g, m.p.ball_mass * g, a;
  const Stability st = stability(pb, solve(pb, X).X);
  ASSERT_EQ(st.eigenvalues.size(), 8);
  std::vector<double> imag;
  for (int i = 0; i < 8; ++i) {
    EXPECT_NEAR(st.eigenvalues(i).real(), -gam, 1e-9 * expected.back());
    if (st.eigenvalues(i).imag() > 0) imag.push_back(st.eigenvalues(i).imag());
  }
  std::sort(imag.begin(), imag.end());
  ASSERT_EQ(imag.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(imag[i], expected[i], 1e-9 * expected.back());
}

TEST(OrbitStability, WithoutDragTheSpectrumIsSymmetric) {
  // c_D = 0: the co-rotating dynamics is Hamiltonian (gyroscopic), so with λ also −λ is an
  // eigenvalue. Checked on every stuck orbit at 4.7π with R = 1 cm.
  physics::Model m;
  m.p.drag = 0.0;
  const double w = 4.7 * kPi;
  for (const auto& o : orbits_at({m, w, Closure::Stuck, 0.55})) {
    const Stability st = stability({m, w, Closure::Stuck, 0.55}, unknowns(o));
    const double scale = st.eigenvalues.cwiseAbs().maxCoeff();
    for (int i = 0; i < st.eigenvalues.size(); ++i) {
      double nearest = 1e300;
      for (int j = 0; j < st.eigenvalues.size(); ++j)
        nearest = std::min(nearest, std::abs(st.eigenvalues(j) + st.eigenvalues(i)));
      EXPECT_LT(nearest, 1e-6 * scale) << o.branch << " λ " << st.eigenvalues(i);
    }
  }
}

TEST(OrbitStability, UnstableTable1OrbitDepartsAtThePredictedRate) {
  // The Table-1-type orbit (bead opposite the ball, stuck at the table's s = 0.5443 m) at
  // 4.7π rad/s with the configured model: a real eigenvalue λ > 0. Displaced by 1e-7 m along
  // its eigenvector it must leave as e^{λ t}: the other modes are excited only through the
  // projection onto the string (O(ε²/l)) and the nonlinearity (|δ|/l < 1e-4 over the run), so
  // the measured rate over 2..8 s matches λ to well within 1 %.
  const physics::Model m;
  const double w = 4.7 * kPi, s = 0.544298;
  const OrbitProblem pb{m, w, Closure::Stuck, s};
  const SteadyOrbit* o = nullptr;
  const auto found = orbits_at(pb);
  for (const auto& c : found)
    if (c.branch == "-/+" && c.rho1 > 0.05) o = &c;
  ASSERT_NE(o, nullptr);
  ASSERT_TRUE(o->admissible);
  const Stability st = stability(pb, unknowns(*o));
  ASSERT_GT(st.growth, 0.0);
  ASSERT_EQ(st.frequency, 0.0);
  physics::Mode mode;
  const std::vector<double> d = departure(m, pb, unknowns(*o), along_mode(st, 1e-7), {2.0, 8.0}, &mode);
  EXPECT_EQ(mode, physics::Mode::Stuck) << "the bead should stay stuck while the orbit departs";
  const double measured = std::log(d[1] / d[0]) / 6.0;
  EXPECT_NEAR(measured, st.growth, 0.01 * st.growth);
  report("table1_growth", fmt::format("predicted {:.6f} /s, measured {:.6f} /s (|δ| {:.2e} → {:.2e} m)", st.growth,
                                      measured, d[0], d[1]));
}

TEST(OrbitStability, StableOrbitStaysAndItsPerturbationDecaysAtThePredictedRate) {
  // A stable admissible stuck orbit at 4.7π (bead on the top's side, ball opposite, s = 0.6468
  // m): unperturbed, the Simulation stays on it to integration accuracy for 20 s; displaced
  // along the least-damped mode (a complex pair), the displacement after whole periods of the
  // pair is e^{Re λ t} times the initial one (same 1 % argument as for the unstable orbit).
  const physics::Model m;
  const double w = 4.7 * kPi, s = 0.6468;
  const OrbitProblem pb{m, w, Closure::Stuck, s};
  const SteadyOrbit* o = nullptr;
  const auto found = orbits_at(pb);
  for (const auto& c : found)
    if (c.branch == "+/-" && c.rho1 > 0.05) o = &c;
  ASSERT_NE(o, nullptr);
  ASSERT_TRUE(o->admissible);
  const Stability st = stability(pb, unknowns(*o));
  ASSERT_LT(st.growth, 0.0);
  ASSERT_GT(st.frequency, 0.0);
  const std::vector<double> still = departure(m, pb, unknowns(*o), Vec12::Zero(), {20.0});
  EXPECT_LT(still[0], 1e-8);
  const double period = 2 * kPi / st.frequency, t1 = 3 * period;
  const std::vector<double> d = departure(m, pb, unknowns(*o), along_mode(st, 1e-6), {0.0, t1});
  const double measured = std::log(d[1] / d[0]) / t1;
  EXPECT_NEAR(measured, st.growth, 0.01 * std::abs(st.growth));
  report("stable_orbit", fmt::format("drift unperturbed {:.2e} m over 20 s; Re λ predicted {:.6f} /s, measured {:.6f} /s "
                                     "over 3 periods of {:.4f} s",
                                     still[0], st.growth, measured, period));
}
