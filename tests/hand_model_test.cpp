// The hand-written peer's model (src/bench/peers/hand_model.*) against the project's physics:
// the matched comparison is only fair if the peer integrates the same equations. Its
// right-hand side and its guards must agree with the project's to rounding in every mode, at
// the work-precision scenes' states, and its projection must land on the constraints.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "bench/peers/hand_bridge.hpp"
#include "bench/peers/hand_model.hpp"
#include "bench/scene_file.hpp"
#include "physics/mode_transitions.hpp"
#include "physics/rotating_axes.hpp"

using namespace ajx;

namespace {

bench::Scene scene(const char* name) {
  return bench::load_scene(std::string(ASTROJAX_SOURCE_DIR) + "/sweeps/scenes/" + name + ".toml", {}, 10.0);
}

// The scene's initial state in the rotating axes, and the project's top there.
numerics::Vec rotating_state(const bench::Scene& s) {
  numerics::Vec y = s.initial.y;
  physics::rotate_about_z(y, -bench::phase(s, s.initial.t));
  return y;
}

// Rounding of a sum of a few terms of size `scale`: a few ulps of it.
constexpr double kRounding = 64 * std::numeric_limits<double>::epsilon();

// Each mode the peer models, at a state: the RHS of both, and each guard of the mode.
void expect_same(const bench::Scene& s, const physics::Contact& c) {
  const hand::Params h = bench::hand_params(s);
  const numerics::Vec y = rotating_state(s);
  const double t = s.initial.t;
  numerics::Vec f(physics::idx::dim);
  physics::rhs_in_rotating_axes(s.model, s.schedule, c, t, y, f);
  double g[12], scale = 0.0;
  hand::rhs(h, bench::hand_contact(c), t, y.data(), g);
  for (int i = 0; i < 12; ++i) scale = std::max(scale, std::abs(f(i)));
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(g[i], f(i), kRounding * scale) << physics::to_string(c.mode) << " " << i;

  // The guards, in the peer's order (hand_model.cpp) against physics::guard_value.
  using G = physics::Guard;
  std::vector<G> order;
  switch (c.mode) {
    case physics::Mode::Sliding: order = {G::LandBottom, G::LandTop, G::Rest, G::Slacken}; break;
    case physics::Mode::Stuck: order = {G::SlipUp, G::SlipDown, G::Slacken}; break;
    case physics::Mode::BottomStop: order = {G::SlipUp, G::Slacken}; break;
    case physics::Mode::TopStop: order = {G::SlipDown, G::Slacken}; break;
    case physics::Mode::Slack: break;
  }
  const physics::TopKinematics top = physics::top_in_rotating_axes(s.schedule, t);
  double hg[8];
  ASSERT_EQ(hand::guards(h, bench::hand_contact(c), t, y.data(), hg), int(order.size()));
  for (std::size_t i = 0; i < order.size(); ++i) {
    const double v = physics::guard_value(order[i], s.model, top, c, y);
    EXPECT_NEAR(hg[i], v, kRounding * (std::abs(v) + 1.0)) << physics::to_string(c.mode) << " guard " << i;
  }
}

}  // namespace

TEST(HandModel, AgreesWithTheProjectInEveryMode) {
  const bench::Scene stuck = scene("stick_slip_passage"), bottom = scene("bottom_stop_fast");
  ASSERT_EQ(stuck.initial.contact.mode, physics::Mode::Stuck);
  ASSERT_EQ(bottom.initial.contact.mode, physics::Mode::BottomStop);
  expect_same(stuck, stuck.initial.contact);
  expect_same(bottom, bottom.initial.contact);
  // The same states in the other modes: the laws differ, both sides must compute the same one.
  expect_same(stuck, {physics::Mode::Sliding, +1, 0.0});
  expect_same(stuck, {physics::Mode::Sliding, -1, 0.0});
  expect_same(bottom, {physics::Mode::Sliding, +1, 0.0});
  expect_same(stuck, {physics::Mode::TopStop, 0, 0.0});
}

TEST(HandModel, DriveOnARampAgreesWithTheSchedule) {
  const bench::Scene s = scene("stick_slip_passage");  // a ramp 6π → 2π at 2 rad/s², then hold
  const hand::Params h = bench::hand_params(s);
  for (double t : {0.0, 1.0, 3.14, 6.28, 6.3, 50.0}) {
    double phi, w, wd, hw, hwd;
    s.schedule.phase(t, phi, w, wd);
    h.omega(t, hw, hwd);
    EXPECT_NEAR(hw, w, 1e-13 * w) << t;
    EXPECT_EQ(hwd, wd) << t;
  }
}

TEST(HandModel, ProjectionLandsOnTheConstraints) {
  const bench::Scene s = scene("stick_slip_passage");
  const hand::Params h = bench::hand_params(s);
  numerics::Vec y = rotating_state(s);
  y(physics::idx::r1) += 1e-6;  // off the held lengths by 1 µm and off the rates
  y(physics::idx::v2 + 2) += 1e-4;
  const physics::Contact c = s.initial.contact;
  hand::project(h, bench::hand_contact(c), s.initial.t, y.data(), 1e-12);
  const physics::TopKinematics top = physics::top_in_rotating_axes(s.schedule, s.initial.t);
  const physics::Drift d = physics::constraint_drift(s.model, c, top, y);
  EXPECT_LT(d.position, 1e-14);
  EXPECT_LT(d.velocity, 1e-13);
}
