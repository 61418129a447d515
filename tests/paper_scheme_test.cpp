// The paper's two-step scheme (sim/paper_scheme.hpp): its recurrence on a toy orbit with a known
// answer, its order against DOP853 on the Astrojax, and the sign of the energy the printed drag
// injects.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>

#include "config/config.hpp"
#include "physics/energy.hpp"
#include "sim/paper_scheme.hpp"
#include "sim/simulation.hpp"
#include "sim/table1_starts.hpp"

namespace {

using namespace ajx;
using physics::Vec3;
namespace idx = physics::idx;
constexpr double pi = std::numbers::pi;
constexpr double kH = 1.0 / 2000.0;  // the paper's step [s]

// Energy decay rate -d ln E/dt of a circular orbit in the isotropic potential ½ k |x|² with drag
// -c v, integrated by the scheme's recurrence (central_step) for T seconds; E from the central
// velocity (x_{k+1} - x_{k-1})/(2h). Exact: x = ρ e^{-γt/2} (cos ω't, sin ω't), E ∝ e^{-γt}, γ = c/m.
double toy_decay_rate(sim::PaperDrag drag, double m, double c, double w0, double h, double T) {
  const double gamma = c / m, wd = std::sqrt(w0 * w0 - 0.25 * gamma * gamma);
  const auto exact = [&](double t) { return Vec3(std::exp(-0.5 * gamma * t) * Vec3(std::cos(wd * t), std::sin(wd * t), 0)); };
  Vec3 prev = exact(0.0), now = exact(h);
  const auto energy = [&](const Vec3& before, const Vec3& x, const Vec3& after) {
    const Vec3 v = (after - before) / (2 * h);
    return 0.5 * m * v.squaredNorm() + 0.5 * m * w0 * w0 * x.squaredNorm();
  };
  const long n = long(std::lround(T / h));
  double E1 = 0.0, En = 0.0;
  for (long k = 1; k <= n; ++k) {
    const Vec3 next = sim::central_step(now, prev, -m * w0 * w0 * now, m, c, h, drag);
    const double E = energy(prev, now, next);
    if (k == 1) E1 = E;
    En = E;
    prev = now;
    now = next;
  }
  return -std::log(En / E1) / (double(n - 1) * h);
}

// The recurrence's characteristic roots z (conjugate pair) have |z|² = 1 ∓ γh (their product):
// the energy of the corrected scheme decays exactly at -ln(1 - γh)/h = γ (1 + γh/2 + ...), the
// printed one grows at ln(1 + γh)/h. Forward Euler's amplification matrix [[1, h], [-h ω0², 1 - γh]]
// has determinant 1 - γh + h² ω0²: its energy changes at ln(1 - γh + h² ω0²)/h ≈ -γ + h ω0².
TEST(PaperScheme, ToyCircularOrbitDecaysAtTheExactRate) {
  const double m = 0.018, c = 1.7245e-3, w0 = 4.8 * pi, gamma = c / m, T = 20.0;
  const double corrected = toy_decay_rate(sim::PaperDrag::Corrected, m, c, w0, kH, T);
  const double printed = toy_decay_rate(sim::PaperDrag::Printed, m, c, w0, kH, T);
  // The start pair is the exact orbit, not the recurrence's own mode: a second mode of relative
  // size O(h) rides on it and moves the fitted rates by ~1e-9 γ (a bound of 1e-7 γ).
  EXPECT_NEAR(corrected, -std::log(1 - gamma * kH) / kH, 1e-7 * gamma);
  EXPECT_NEAR(printed, -std::log(1 + gamma * kH) / kH, 1e-7 * gamma);
  // Against the exact rate γ: the scheme's relative error is γh/2 = 2.4e-5.
  EXPECT_NEAR(corrected / gamma, 1.0, 0.51 * gamma * kH + 1e-9);
  EXPECT_GT(printed, -1.01 * gamma);  // grows: -d ln E/dt ≈ -γ
  EXPECT_LT(printed, -0.99 * gamma);
  // Forward Euler at the same step (the linear map above, exactly).
  const double euler_rate = -std::log(1 - gamma * kH + kH * kH * w0 * w0) / kH;
  EXPECT_LT(euler_rate, 0.0);  // Euler's orbit gains energy where the exact one decays
  std::printf("toy orbit, h = 1/2000 s: exact decay rate γ = %.6f /s, paper_corrected %.6f /s, paper (printed) "
              "%.6f /s, forward Euler %.6f /s\n", gamma, corrected, printed, euler_rate);
}

// A smooth taut-sliding case: Table 1's circular orbit 1 moving with the motor at 4.8π, no friction,
// taut string without stops (the scheme's physics), R = 15 mm, for 1 s.
physics::Model smooth_model(double drag) {
  physics::Model m;
  m.p.drive_radius = 0.015;
  m.p.drag = drag;
  m.layers.friction = physics::Friction::None;
  m.layers.slack = m.layers.bottom_stop = m.layers.top_stop = false;
  return m;
}
const physics::MotorSchedule& hold_48pi() {
  static const physics::MotorSchedule s(smooth_model(0.0).p.drive_radius, {{4.8 * pi, 4.8 * pi, 2.0}});
  return s;
}
physics::State smooth_start(const physics::Model& m) {
  sim::PairStart p = sim::table1_pair("circular1", 4.8 * pi, kH);
  sim::project_pair(m, hold_48pi(), kH, p);
  const Vec3 w(0, 0, 4.8 * pi);
  return sim::explicit_state(m, hold_48pi(), p.r1_0, p.r2_0, w.cross(p.r1_0), w.cross(p.r2_0), physics::Mode::Sliding);
}

// DOP853 at rtol 1e-12 from the start: positions at t = h_pair and at t = T.
struct Reference {
  Vec3 r1_h, r2_h, r1_T, r2_T;
};
Reference reference(const physics::Model& m, const physics::State& start, double h_pair, double T) {
  sim::RunOptions opt;
  opt.method = "dop853";
  opt.axes = sim::Axes::Lab;
  opt.integ.tol = {1e-12, 1e-14};
  Reference r;
  physics::State s = start;
  sim::Simulation(m, hold_48pi(), opt).run(s, h_pair, 0.0);
  r.r1_h = s.y.segment<3>(idx::r1);
  r.r2_h = s.y.segment<3>(idx::r2);
  s = start;
  const sim::RunSummary sum = sim::Simulation(m, hold_48pi(), opt).run(s, T, 0.0);
  EXPECT_TRUE(sum.ok()) << sum.failure;
  r.r1_T = s.y.segment<3>(idx::r1);
  r.r2_T = s.y.segment<3>(idx::r2);
  return r;
}

// The scheme's position error at T against the reference `ref_model` (the same start).
double scheme_error(const physics::Model& m, const physics::Model& ref_model, double h, double T) {
  const physics::State start = smooth_start(m);
  const Reference ref = reference(ref_model, start, h, T);
  const sim::PairStart pair{0.0, start.y.segment<3>(idx::r1), start.y.segment<3>(idx::r2), ref.r1_h, ref.r2_h};
  physics::State end;
  const sim::RunSummary sum = sim::run_paper_scheme(m, hold_48pi(), sim::PaperDrag::Corrected, h, pair, T, 0.0, {}, end);
  EXPECT_TRUE(sum.ok()) << sum.failure;
  const Vec3 r1 = end.y.segment<3>(idx::r1), r2 = end.y.segment<3>(idx::r2);
  EXPECT_NEAR(end.t, T, 1e-9);
  return std::max((r1 - ref.r1_T).norm(), (r2 - ref.r2_T).norm());
}

// Observed orders log2(e(h)/e(h/2)) for h = 1/1000, 1/2000, 1/4000 s.
std::pair<double, double> orders(const std::function<double(double)>& error, const char* label) {
  const double e1 = error(1e-3), e2 = error(5e-4), e3 = error(2.5e-4);
  std::printf("%s: |error| at T = 1 s for h = 1/1000, 1/2000, 1/4000 s: %.3e %.3e %.3e m, orders %.3f %.3f\n", label,
              e1, e2, e3, std::log2(e1 / e2), std::log2(e2 / e3));
  return {std::log2(e1 / e2), std::log2(e2 / e3)};
}

// Without drag the scheme is the central difference with a position constraint (SHAKE): order 2.
// The next term of the error is (ω h)² ~ 1e-4 relative, so the observed order is 2 to ±0.05.
TEST(PaperScheme, SecondOrderWithoutDrag) {
  const physics::Model m = smooth_model(0.0);
  const auto [o1, o2] = orders([&](double h) { return scheme_error(m, m, h, 1.0); }, "no drag vs dop853");
  EXPECT_NEAR(o1, 2.0, 0.05);
  EXPECT_NEAR(o2, 2.0, 0.05);
}

// With drag: (q^(k) - q^(k-1))/h = q̇ - (h/2) q̈ + O(h²), so the corrected scheme solves
// (m - c_D h/2) q̈ = F - c_D q̇ to O(h²): against DOP853 on that modified inertia (masses m - c_D h/2,
// equal for both balls, gravity scaled by m/(m - c_D h/2) so that the weight stays m g) it is
// second order; against the true equations it has the extra O(h) term c_D h/(2m) ≈ 2.4e-5 relative.
TEST(PaperScheme, SecondOrderAgainstTheModifiedInertia) {
  const physics::Model m = smooth_model(1.7245e-3);
  const auto modified = [&](double h) {
    physics::Model r = m;
    const double mass = m.p.bead_mass - 0.5 * m.p.drag * h;
    r.p.gravity = m.p.gravity * m.p.bead_mass / mass;
    r.p.bead_mass = r.p.ball_mass = mass;
    return r;
  };
  const auto [o1, o2] = orders([&](double h) { return scheme_error(m, modified(h), h, 1.0); },
                               "paper_corrected vs dop853 with the modified inertia");
  EXPECT_NEAR(o1, 2.0, 0.05);
  EXPECT_NEAR(o2, 2.0, 0.05);
  orders([&](double h) { return scheme_error(m, m, h, 1.0); }, "paper_corrected vs dop853 (true equations)");
}

// The paper's scheme from Table 1's circular orbit 1 at 4.8π, with its physics (kinetic
// point-contact friction, taut string), for T seconds: the energy ledger's injection,
// dE/dt - (P_motor - P_drag - P_fric), and the drag power.
struct Injection {
  double injection, p_drag;
};
Injection injection(sim::PaperDrag drag, double T) {
  physics::Model m;
  m.p.drive_radius = 0.015;
  m.layers.friction = physics::Friction::Kinetic;
  m.layers.friction_law = physics::FrictionLaw::PointContact;
  m.layers.slack = m.layers.bottom_stop = m.layers.top_stop = false;
  sim::PairStart p = sim::table1_pair("circular1", 4.8 * pi, kH);
  sim::project_pair(m, hold_48pi(), kH, p);
  physics::State end;
  const sim::RunSummary sum = sim::run_paper_scheme(m, hold_48pi(), drag, kH, p, T, 0.0, {}, end);
  EXPECT_TRUE(sum.ok()) << sum.failure;
  const double dt = sum.t_end - kH;  // the ledger starts at the first step with a velocity
  return {-sum.energy.residual / dt, sum.energy.drag_loss / dt};
}

// The printed drag +c_D v where the physics has -c_D v: the scheme adds 2 c_D |v|² = 2 P_drag
// per second beyond the exact ledger. The corrected scheme closes the ledger to O(h²) (its
// residual bounds the error of the printed one's measured injection): to the scheme's truncation,
// (ω h)² ≈ 6e-5 relative, asserted as 1e-4 of the drag power.
TEST(PaperScheme, PrintedDragInjectsTwiceTheDragPower) {
  const Injection printed = injection(sim::PaperDrag::Printed, 2.0);
  const Injection corrected = injection(sim::PaperDrag::Corrected, 2.0);
  std::printf("Table 1 circular orbit 1 at 4.8π, 2 s, h = 1/2000 s: injection paper %+.4e W (P_drag %.4e W), "
              "paper_corrected %+.4e W (P_drag %.4e W)\n", printed.injection, printed.p_drag, corrected.injection,
              corrected.p_drag);
  EXPECT_GT(printed.injection, 0.0);
  EXPECT_NEAR(printed.injection / (2 * printed.p_drag), 1.0, 0.01);
  EXPECT_LT(std::abs(corrected.injection), 1e-4 * corrected.p_drag);
}

TEST(PaperScheme, TableOneCircularPairTurnsWithTheMotor) {
  const double w = 4.8 * pi;
  const sim::PairStart p = sim::table1_pair("circular1", w, kH);
  EXPECT_NEAR((p.r1_1 - p.r1_0).norm(), 2 * 0.14427 * std::sin(0.5 * w * kH), 1e-15);  // the chord of θ = ω h
  // Counter-clockwise about +z, like the motor: (r0 × r1)·ẑ > 0 for both balls.
  EXPECT_GT(p.r1_0.cross(p.r1_1).z(), 0.0);
  EXPECT_GT(p.r2_0.cross(p.r2_1).z(), 0.0);
  EXPECT_THROW(sim::table1_pair("flower5", w, kH), std::invalid_argument);
}

TEST(PaperScheme, ConfigRefusesLayersTheSchemeLacks) {
  const std::string run = "[integrator]\nmethod = \"paper\"\n[[schedule]]\nkind = \"hold\"\nomega = 15.0\nduration = 1.0\n";
  try {
    config::parse_run_config(run, "x.toml");
    FAIL() << "the stuck bead of the default layers was accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("layers.friction"), std::string::npos) << e.what();
  }
  const std::string ok = "[layers]\nfriction = \"kinetic\"\nslack = false\nbottom_stop = false\ntop_stop = false\n"
                         "[initial]\npreset = \"table1\"\norbit = \"flower3\"\n" + run;
  const config::RunConfig c = config::parse_run_config(ok, "x.toml");
  EXPECT_EQ(c.initial.orbit, "flower3");
  EXPECT_THROW(config::parse_run_config(ok, "x.toml", {"initial.orbit=flower9"}), config::ConfigError);
}

}  // namespace
