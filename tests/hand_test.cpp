// The hand's start (physics/hand.hpp): while a hand moves the top along a random planar path the
// ledger closes with the prescribed top's work, for the rigid tie and the tie clutch; the top is
// handed over at T with continuous position and velocity; after T the motion is that of a run
// started from the handover state on the motor alone.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "one_set.hpp"
#include "physics/energy.hpp"
#include "physics/hand.hpp"
#include "sim/simulation.hpp"

using namespace ajx;
using namespace ajx::physics;

namespace {

constexpr double pi = std::numbers::pi;

sim::RunOptions tight(double rtol) {
  sim::RunOptions o;
  o.method = "dopri5";
  o.integ.tol.rtol = rtol;
  o.integ.tol.atol = rtol * 1e-2;
  return o;
}

// A hand of 3 modes over T = 3 s with |x_top − a| <= 0.12 m; the motor ramps from rest at 5 rad/s².
HandPath a_hand() {
  HandPath h{3.0, {}, {}};
  h.p = {Vec3(0.02, -0.01, 0), Vec3(-0.015, 0.005, 0), Vec3(0.004, 0.012, 0)};
  h.q = {Vec3(-0.01, 0.018, 0), Vec3(0.01, 0.01, 0), Vec3(-0.008, 0.003, 0)};
  return h;
}


}  // namespace

TEST(Hand, OffsetVanishesWithItsRateAtBothEndsAndItsRatesAreTheDerivatives) {
  const HandPath h = a_hand();
  EXPECT_EQ(h.offset(0.0).d.norm(), 0.0);
  EXPECT_EQ(h.offset(0.0).d_dot.norm(), 0.0);
  EXPECT_LT(h.offset(std::nextafter(3.0, 0.0)).d.norm(), 1e-12);
  EXPECT_LT(h.offset(std::nextafter(3.0, 0.0)).d_dot.norm(), 1e-12);
  EXPECT_EQ(h.offset(3.0).d.norm(), 0.0);
  // Central differences of d and ḋ (error O(δ²) with δ = 1e-5 s: below 1e-7 of the scales).
  double worst_v = 0.0, worst_a = 0.0, peak_v = 0.0;
  const double dt = 1e-5;
  for (int k = 1; k < 300; ++k) {
    const double t = 3.0 * k / 300.0;
    const HandOffset o = h.offset(t), plus = h.offset(t + dt), minus = h.offset(t - dt);
    worst_v = std::max(worst_v, ((plus.d - minus.d) / (2 * dt) - o.d_dot).norm());
    worst_a = std::max(worst_a, ((plus.d_dot - minus.d_dot) / (2 * dt) - o.d_ddot).norm());
    peak_v = std::max(peak_v, o.d_dot.norm());
  }
  EXPECT_LT(worst_v, 1e-7);
  EXPECT_LT(worst_a, 1e-6);
  EXPECT_LE(peak_v, h.speed_bound());
}

TEST(Hand, TheLedgerClosesWhileTheHandMovesTheTopAndTheMotionAfterHandoverIsTheMotorsAlone) {
  for (bool clutch : {false, true}) {
    const Model m = documented_set(clutch);  // basins.toml's set
    const std::vector<DriveSegment> segs{{0.0, 15.0, 3.0}, {15.0, 25.0, 2.0}};  // 5 rad/s² from rest
    const MotorSchedule motor(m.p.drive_radius, segs);
    MotorSchedule held = motor;
    held.set_hand(a_hand());
    // Through the hand: W_m = ΔE_tie + W_c + ΔE + drag + friction + impacts. The integrator's
    // local error (rtol 1e-10) summed over the run's ~1e4 steps bounds the balance's relative error by ~1e-6.
    State s = sim::hanging_at_rest(m, held);
    sim::Simulation hand_run(m, held, tight(1e-10));
    const sim::RunSummary r = hand_run.run(s, 3.0, 0.01);
    ASSERT_TRUE(r.ok()) << r.failure;
    EXPECT_GT(r.energy.motor_work, 1e-3) << "the hand does work on the pair";
    EXPECT_LT(std::abs(r.energy.residual), 1e-6 * r.energy.scale)
        << "clutch " << clutch << ": W_m " << r.energy.motor_work << " ΔE " << r.energy.delta_energy;
    EXPECT_LT(std::abs(r.energy.tie_residual), 1e-6 * r.energy.scale);
    // After T: the hand's run continued against a run on the motor alone from the handover state.
    State a = s, b = s;
    sim::Simulation on(m, held, tight(1e-11)), alone(m, motor, tight(1e-11));
    ASSERT_TRUE(on.run(a, 5.0, 0.01).ok());
    ASSERT_TRUE(alone.run(b, 5.0, 0.01).ok());
    const double gap = std::max((a.r1() - b.r1()).norm(), (a.r2() - b.r2()).norm());
    EXPECT_EQ(gap, 0.0) << "clutch " << clutch << ": the hand acts only before T";
  }
}
