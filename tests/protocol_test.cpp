// Sweep protocols: the compiled motor schedule and its windows agree, windows tile the ramps,
// staircases hold where they measure, and tasks tile the chain.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "physics/drive.hpp"
#include "sweep/protocol.hpp"

using namespace ajx::sweep;

namespace {
const double pi = 3.141592653589793;

// The paper's protocol: up from rest past ω_rise, down towards ω_fall, up again through ω1, ω2.
std::vector<Segment> paper_like() {
  Segment up{Segment::Kind::Ramp, {0.0, 14 * pi, 0.2, 5.0}, {}};
  Segment down{Segment::Kind::Ramp, {14 * pi, 2 * pi, 0.2, 5.0}, {}};
  Segment again{Segment::Kind::Ramp, {2 * pi, 17 * pi, 0.2, 5.0}, {}};
  return {up, down, again};
}
}  // namespace

TEST(Protocol, WindowsAgreeWithTheSchedule) {
  const CompiledProtocol p = compile(paper_like());
  const ajx::physics::MotorSchedule sched(0.01, p.schedule);  // R: only the phase is read
  EXPECT_NEAR(sched.duration(), p.duration, 1e-9);
  // Ramp durations: (14π + 12π + 15π)/0.2.
  EXPECT_NEAR(p.duration, 41 * pi / 0.2, 1e-9);
  for (const Window& w : p.windows) {
    double phi, om, od;
    sched.phase(w.t_begin + 1e-12, phi, om, od);
    EXPECT_NEAR(om, w.omega_begin, 1e-9);
    sched.phase(w.t_end - 1e-12, phi, om, od);
    EXPECT_NEAR(om, w.omega_end, 1e-9);
    EXPECT_NEAR(w.t_end - w.t_begin, 5.0, 2.5);  // windows of ~5 s, the last of a ramp at most 1.5×
  }
  // Windows tile each ramp without gaps, and directions follow the ramps.
  for (std::size_t i = 1; i < p.windows.size(); ++i) EXPECT_DOUBLE_EQ(p.windows[i].t_begin, p.windows[i - 1].t_end);
  EXPECT_EQ(p.windows.front().direction, +1);
  int downs = 0;
  for (const Window& w : p.windows) downs += w.direction < 0;
  EXPECT_GT(downs, 0);
}

TEST(Protocol, StepsHoldWhereTheyMeasure) {
  Segment s{Segment::Kind::Steps, {}, {10.0, 20.0, 6, 30.0, 10.0, 1.0}};
  const CompiledProtocol p = compile({s}, 10.0);
  ASSERT_EQ(p.windows.size(), 6u);
  const ajx::physics::MotorSchedule sched(0.01, p.schedule);  // R: only the phase is read
  for (int i = 0; i < 6; ++i) {
    const Window& w = p.windows[std::size_t(i)];
    EXPECT_DOUBLE_EQ(w.omega_begin, 10.0 + 2.0 * i);
    EXPECT_DOUBLE_EQ(w.t_end - w.t_begin, 10.0);
    EXPECT_EQ(w.direction, +1);  // the staircase rises
    double phi, om, od;
    sched.phase(0.5 * (w.t_begin + w.t_end), phi, om, od);
    EXPECT_DOUBLE_EQ(om, w.omega_begin);
    EXPECT_EQ(od, 0.0);
    // Settled for 30 s at this level before measuring.
    sched.phase(w.t_begin - 29.999, phi, om, od);
    EXPECT_DOUBLE_EQ(om, w.omega_begin);
  }
  // Five 2 rad/s steps at 1 rad/s² between six 40 s holds.
  EXPECT_NEAR(p.duration, 6 * 40.0 + 5 * 2.0, 1e-9);
  // A falling staircase falls; a single held level has no direction.
  EXPECT_EQ(compile({Segment{Segment::Kind::Steps, {}, {20.0, 10.0, 3, 1.0, 1.0, 1.0}}}, 20.0).windows[1].direction, -1);
  EXPECT_EQ(compile({Segment{Segment::Kind::Steps, {}, {15.0, 15.0, 1, 1.0, 1.0, 1.0}}}, 15.0).windows[0].direction, 0);
}

TEST(Protocol, TasksTileTheChain) {
  const CompiledProtocol p = compile(paper_like());
  for (int per : {1, 3, 7, 1000}) {
    const auto tasks = split(p, per);
    EXPECT_DOUBLE_EQ(tasks.front().t_begin, 0.0);
    EXPECT_DOUBLE_EQ(tasks.back().t_begin + (tasks.back().t_end - tasks.back().t_begin), p.duration);
    int covered = 0;
    for (std::size_t i = 0; i < tasks.size(); ++i) {
      EXPECT_EQ(tasks[i].first_window, covered);
      EXPECT_LE(tasks[i].num_windows, per);
      covered += tasks[i].num_windows;
      if (i > 0) EXPECT_DOUBLE_EQ(tasks[i].t_begin, tasks[i - 1].t_end);
    }
    EXPECT_EQ(covered, int(p.windows.size()));
  }
}

TEST(Protocol, BadProtocolsAreRejected) {
  EXPECT_THROW(compile({}), std::invalid_argument);
  EXPECT_THROW(compile({Segment{Segment::Kind::Ramp, {0.0, 10.0, 0.0, 5.0}, {}}}), std::invalid_argument);
  EXPECT_THROW(compile({Segment{Segment::Kind::Ramp, {0.0, 10.0, 1.0, -5.0}, {}}}), std::invalid_argument);
  EXPECT_THROW(compile({Segment{Segment::Kind::Steps, {}, {1.0, 2.0, 0, 1.0, 1.0, 1.0}}}), std::invalid_argument);
  EXPECT_THROW(split(compile(paper_like()), 0), std::invalid_argument);
}
