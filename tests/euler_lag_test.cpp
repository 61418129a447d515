// The lagging orbit after the lock is lost (sweeps/scenes/lag_after_lock.toml): the exact
// equations let it decay, explicit Euler at the paper's step h = 1/2000 s sustains it with
// energy of its own making. (The paper's own scheme is not Euler but the two-step central
// difference of its eq. (15): tests/paper_scheme_test.cpp.)
//
// Explicit Euler on the balls' velocities, v ← v + h a, raises the kinetic energy by
// ½ m h² |a|² per step beyond the exact work (the Hessian of E in v is the mass; gravity's
// potential is linear), i.e. by ½ m h |a|² per second and ball. On a circle at ω_b
// (|a| = ω_b² ρ, |v| = ω_b ρ) this balances the drag c_D ω_b² ρ² at ω_b = √(2 c_D/(m h)).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include <fmt/format.h>

#include "bench/scene_file.hpp"
#include "measured.hpp"
#include "physics/energy.hpp"
#include "sim/simulation.hpp"

namespace {

using namespace ajx;
namespace idx = physics::idx;
constexpr double pi = std::numbers::pi;

// Samples of one run: time, the balls' azimuths and accelerations, energy and work integrals.
struct Track {
  std::vector<double> t, theta2, omega_m, energy, motor, drag, friction, a2sum;
};

// Means over t in [t0, t1] of the ledger terms [W], ω_ball and ω_m [rad/s].
struct Ledger {
  double p_motor, p_drag, p_fric, de_dt, injection, omega_ball, omega_m, predicted_injection;
};

Track run(const bench::Scene& scene, const std::string& method, double step) {
  sim::RunOptions opt = scene.run;
  opt.method = method;
  opt.integ.h_fixed = step;
  opt.axes = sim::Axes::Lab;  // the paper integrated in the lab frame
  sim::Simulation simulation(scene.model, scene.schedule, opt);
  physics::State s = scene.initial;
  Track k;
  const physics::Parameters& p = scene.model.p;
  numerics::Vec prev_v;
  double prev_t = 0.0;
  const sim::RunSummary sum = simulation.run(s, scene.schedule.duration(), 0.01, [&](const sim::Sample& x) {
    const numerics::Vec v = x.y.segment<6>(idx::v1);
    // m1 |a1|² + m2 |a2|², a by a backward difference of the sampled velocities 0.01 s apart
    // (on a circle at ω_b it underestimates |a| by (ω_b Δt)²/24 < 0.2 % here).
    double a2 = NAN;
    if (prev_v.size() == 6) {
      const numerics::Vec a = (v - prev_v) / (x.t - prev_t);
      a2 = p.bead_mass * a.head<3>().squaredNorm() + p.ball_mass * a.tail<3>().squaredNorm();
    }
    prev_v = v;
    prev_t = x.t;
    k.t.push_back(x.t);
    k.theta2.push_back(std::atan2(x.y(idx::r2 + 1), x.y(idx::r2)));
    k.omega_m.push_back(x.top.omega);
    k.energy.push_back(physics::mechanical_energy(p, x.y));
    k.motor.push_back(x.y(idx::motor_work));
    k.drag.push_back(x.y(idx::drag_loss));
    k.friction.push_back(x.y(idx::friction_loss) + x.impact_loss);
    k.a2sum.push_back(a2);
  });
  EXPECT_TRUE(sum.ok()) << method << ": " << sum.failure;
  return k;
}

Ledger ledger(const Track& k, double t0, double t1, double step) {
  std::size_t i0 = 0, i1 = 0;
  while (i0 < k.t.size() && k.t[i0] < t0) ++i0;
  while (i1 + 1 < k.t.size() && k.t[i1 + 1] <= t1) ++i1;
  const double dt = k.t[i1] - k.t[i0];
  auto rate = [&](const std::vector<double>& w) { return (w[i1] - w[i0]) / dt; };
  // ω_ball: the bottom ball's unwrapped azimuth, end minus start over the stretch.
  double turned = 0.0;
  for (std::size_t i = i0 + 1; i <= i1; ++i) turned += std::remainder(k.theta2[i] - k.theta2[i - 1], 2.0 * pi);
  double a2 = 0.0, wm = 0.0;
  for (std::size_t i = i0 + 1; i <= i1; ++i) {
    a2 += k.a2sum[i];
    wm += k.omega_m[i];
  }
  Ledger l{};
  l.p_motor = rate(k.motor);
  l.p_drag = rate(k.drag);
  l.p_fric = rate(k.friction);
  l.de_dt = rate(k.energy);
  l.injection = l.de_dt - (l.p_motor - l.p_drag - l.p_fric);
  l.omega_ball = turned / dt;
  l.omega_m = wm / double(i1 - i0);
  l.predicted_injection = 0.5 * step * a2 / double(i1 - i0);
  return l;
}

std::string show(const Ledger& l) {
  return fmt::format("ω_m {:.2f}π ω_ball {:.2f}π P_motor {:.2e} P_drag {:.2e} dE/dt {:+.2e} injection {:+.2e} W",
                     l.omega_m / pi, l.omega_ball / pi, l.p_motor, l.p_drag, l.de_dt, l.injection);
}

class LagAfterLock : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new bench::Scene(bench::load_scene(std::string(ASTROJAX_SOURCE_DIR) + "/sweeps/scenes/lag_after_lock.toml",
                                                {}, 120.0));
  }
  static void TearDownTestSuite() { delete scene_; }
  static bench::Scene* scene_;
};
bench::Scene* LagAfterLock::scene_ = nullptr;

// Windows: the locked orbit (0-10 s, ω_m = 6π) and the last 40 s of the hold at 12π, which
// begins 60 s after the lock is lost (the ramp leaves 6π at t = 10 s).
constexpr double kLockedEnd = 10.0, kTailBegin = 80.0, kEnd = 120.0;

TEST_F(LagAfterLock, ExactEquationsLetTheLaggingOrbitDecay) {
  const Track k = run(*scene_, "dop853", 0.0);
  const Ledger locked = ledger(k, 0.0, kLockedEnd, 0.0), tail = ledger(k, kTailBegin, kEnd, 0.0);
  report("lag_after_lock dop853 locked", show(locked));
  report("lag_after_lock dop853 last 40 s", show(tail));
  // The ledger closes: the integrator adds nothing (rtol 1e-9 on a 10 s window of powers
  // ~1e-3 W leaves ~1e-9 relative; 1e-6 is the run's own energy-balance check).
  EXPECT_LT(std::abs(locked.injection), 1e-6 * locked.p_drag);
  // The locked orbit is fed by the motor: P_motor = P_drag while dE/dt ≈ 0.
  EXPECT_NEAR(locked.p_motor, locked.p_drag, 0.05 * locked.p_drag);
  // Not sustained: fed nothing, an orbit's energy decays as exp(−2 c_D t / m), a factor
  // e^{-11.5} ≈ 1e-5 over the 60 s from the lock's loss to the tail. A sustained orbit would
  // keep P_drag of the locked one's order; 1e-2 sits three decades from each.
  EXPECT_LT(tail.p_drag, 1e-2 * locked.p_drag);
}

TEST_F(LagAfterLock, PaperEulerSustainsItWithItsOwnEnergy) {
  const double h = 5e-4;  // the paper's 1/2000 s
  const Track k = run(*scene_, "euler", h);
  const Ledger locked = ledger(k, 0.0, kLockedEnd, h), tail = ledger(k, kTailBegin, kEnd, h);
  const physics::Parameters& p = scene_->model.p;
  const double omega_star = std::sqrt(2.0 * p.drag / (p.bead_mass * h));
  report("lag_after_lock euler locked", show(locked));
  report("lag_after_lock euler last 40 s", show(tail));
  report("lag_after_lock euler injection / (½ h Σ m|a|²)",
         fmt::format("{:.3f} locked, {:.3f} last 40 s", locked.injection / locked.predicted_injection,
                     tail.injection / tail.predicted_injection));
  report("lag_after_lock euler ω_ball / √(2c_D/(m h))", fmt::format("{:.3f} (√(2c_D/(m h)) = {:.2f}π rad/s)",
                                                                    tail.omega_ball / omega_star, omega_star / pi));
  // Sustained: P_drag stays of the locked orbit's order (decay would leave 1e-5 of it, above).
  EXPECT_GT(tail.p_drag, 0.5 * locked.p_drag);
  // Lagging: well below ω_m = 12π, on the side of the balance frequency √(2c_D/(m h)) = 6.2π.
  EXPECT_LT(tail.omega_ball, 0.6 * tail.omega_m);
  // The motor does not pay for it: |P_motor| is a small part of the drag loss, and the
  // ledger's residual (the integrator's injection) carries the rest: injection ≈ P_drag − P_motor.
  EXPECT_LT(std::abs(tail.p_motor), 0.1 * tail.p_drag);
  EXPECT_GT(tail.injection, 0.5 * tail.p_drag);
  // The injection is Euler's ½ h Σ m|a|² in sign and order (measured 1.10 of it). The excess
  // is not accounted for here: the projection onto the constraints after each step also
  // changes the velocity by O(h²), and the ledger's own work integrals are Euler sums. So the
  // test asserts the order only.
  EXPECT_GT(tail.injection / tail.predicted_injection, 0.5);
  EXPECT_LT(tail.injection / tail.predicted_injection, 2.0);
}

}  // namespace
