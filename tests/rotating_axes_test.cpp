// The equations in axes turning with the motor (physics/rotating_axes.hpp) against the lab
// ones: the same vector field (an identity, to round-off), the same hybrid trajectory through
// sim::Simulation (to the integrators' tolerance), and the reason the formulation exists:
// fewer steps on a locked orbit, which is a fixed point there.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bench/scene_file.hpp"
#include "bench/work_precision.hpp"
#include "physics/rotating_axes.hpp"
#include "sim/simulation.hpp"

namespace {

using namespace ajx;
using numerics::Vec;
using physics::Vec3;
namespace idx = physics::idx;

bench::Scene scene(const char* name, double horizon) {
  return bench::load_scene(std::string(ASTROJAX_SOURCE_DIR) + "/sweeps/scenes/" + name + ".toml", {}, horizon);
}

// d/dt [Rz(−φ) y] = Rz(−φ) ẏ − Ω×(Rz(−φ) y) for the positions and velocities, the work
// integrals unchanged: rhs_in_rotating_axes(Rz(−φ) y) must equal the right side built from the
// lab rhs, on a ramp (ω̇ ≠ 0) and in every taut mode and the slack one.
TEST(RotatingAxes, VectorFieldIsTheLabOneRotated) {
  const bench::Scene s = scene("stick_slip_passage", 1.0);
  const double t = 3.7;  // inside the ramp
  double phi, w, wd;
  s.schedule.phase(t, phi, w, wd);
  ASSERT_NE(wd, 0.0);
  for (physics::Mode mode : {physics::Mode::Sliding, physics::Mode::Stuck, physics::Mode::BottomStop,
                             physics::Mode::TopStop, physics::Mode::Slack}) {
    physics::Contact c{mode, 1, 0.7};
    Vec y = s.initial.y, lab(idx::dim), rot(idx::dim);
    physics::rotate_about_z(y, 0.4);  // some lab state at t (its phase is not the motor's)
    physics::rhs(s.model, s.schedule, c, t, y, lab);
    Vec y_rot = y;
    physics::rotate_about_z(y_rot, -phi);
    physics::rhs_in_rotating_axes(s.model, s.schedule, c, t, y_rot, rot);
    Vec expected = lab;
    physics::rotate_about_z(expected, -phi);
    for (int k : {idx::r1, idx::r2, idx::v1, idx::v2}) {
      const Vec3 x = y_rot.segment<3>(k);
      expected.segment<3>(k) -= Vec3(-w * x.y(), w * x.x(), 0.0);  // − Ω×x
    }
    // Round-off of a few operations on accelerations of ~10 m/s² (φ ~ 50 rad costs a few ulps).
    EXPECT_LT((rot - expected).cwiseAbs().maxCoeff(), 1e-12 * (1.0 + lab.cwiseAbs().maxCoeff()))
        << physics::to_string(mode);
  }
}

TEST(RotatingAxes, RotationRoundTripsAndLeavesTheWorkIntegrals) {
  Vec y = Vec::LinSpaced(idx::dim, -1.0, 2.0);
  const Vec y0 = y;
  physics::rotate_about_z(y, 1.234);
  EXPECT_EQ(y(idx::motor_work), y0(idx::motor_work));
  EXPECT_NEAR(y.segment<3>(idx::v2).norm(), y0.segment<3>(idx::v2).norm(), 1e-15);
  EXPECT_NE(y(idx::r1), y0(idx::r1));
  physics::rotate_about_z(y, -1.234);
  EXPECT_LT((y - y0).cwiseAbs().maxCoeff(), 1e-15);
}

// The hybrid trajectory (ramp down: stick, slip, stick) in both axes. Each run's position error
// at rtol 1e-11 is below 1e-10 m on this scene (astrojax bench work-precision: errors scale
// with rtol, 1e-11 m at rtol 1e-10), so two correct formulations agree to well under 1e-8 m
// (they do to 4e-12 m); dropping only the ramp's term R ω̇ ŷ of ä' (ω̇ = −1.3 rad/s²) moves
// the balls by 2e-5 m in 4 s.
TEST(RotatingAxes, SameHybridTrajectoryAsTheLab) {
  const bench::Scene s = scene("stick_slip_passage", 4.0);
  sim::RunSummary sums[2];
  physics::State ends[2];
  for (int k = 0; k < 2; ++k) {
    sim::RunOptions o = s.run;
    o.axes = k == 0 ? sim::Axes::Lab : sim::Axes::Rotating;
    o.integ.tol = {1e-11, 1e-14};
    sim::Simulation sim(s.model, s.schedule, o);
    ends[k] = s.initial;
    sums[k] = sim.run(ends[k], s.initial.t + s.horizon, 0.0);
    ASSERT_TRUE(sums[k].ok()) << sums[k].failure;
  }
  EXPECT_GT(sums[0].mode_switches, 0);  // a hybrid passage, not one smooth mode
  EXPECT_EQ(sums[0].mode_switches, sums[1].mode_switches);
  EXPECT_EQ(ends[0].contact.mode, ends[1].contact.mode);
  const bench::Errors e = bench::compare(ends[1], ends[0]);
  EXPECT_LT(e.position, 1e-8);
  EXPECT_LT(e.velocity, 1e-7);
  // The work integrals are the lab's: the same energy balance.
  EXPECT_NEAR(ends[1].y(idx::motor_work), ends[0].y(idx::motor_work), 1e-9);
  // ω_ball is measured in the lab either way: the axes' turn is added back.
  EXPECT_NEAR(sums[1].omega_ball, sums[0].omega_ball, 1e-6);
  EXPECT_GT(sums[1].omega_ball, 2.0 * std::numbers::pi);
}

// On the locked orbit the rotating state is constant up to the decaying transients, so an
// adaptive method needs fewer steps than in the lab, where it must follow the 6π rad/s turn.
TEST(RotatingAxes, LockedOrbitTakesFewerStepsThanInTheLab) {
  const bench::Scene s = scene("locked_circular", 10.0);
  long steps[2];
  for (int k = 0; k < 2; ++k) {
    sim::RunOptions o = s.run;
    o.axes = k == 0 ? sim::Axes::Lab : sim::Axes::Rotating;
    o.integ.tol = {1e-9, 1e-12};
    physics::State st = s.initial;
    steps[k] = sim::Simulation(s.model, s.schedule, o).run(st, 10.0, 0.0).steps;
  }
  EXPECT_LT(steps[1], steps[0]);
}

}  // namespace
