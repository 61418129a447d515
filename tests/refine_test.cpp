// Threshold refinement: the refined chain drives the motor exactly as the sweep did up to the
// bracket (same φ, ω: the balls see the same history), then crosses the bracket factor times
// slower without a jump in ω_m or φ; staircases get factor times as many levels.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "physics/drive.hpp"
#include "sweep/protocol.hpp"
#include "sweep/refine.hpp"

using namespace ajx::sweep;

namespace {
const double pi = 3.141592653589793;

ChainSetup chain_of(const std::vector<Segment>& segments) {
  ChainSetup c;
  c.protocol = compile(segments);
  return c;
}

void phase(const ajx::physics::MotorSchedule& s, double t, double& phi, double& om) {
  double od;
  s.phase(t, phi, om, od);
}
}  // namespace

TEST(Refine, RampIsTheSweepsUpToTheBracketThenSlower) {
  const std::vector<Segment> segs{Segment{Segment::Kind::Ramp, {0.0, 14 * pi, 0.5, 5.0}, {}},
                                  Segment{Segment::Kind::Ramp, {14 * pi, 2 * pi, 0.5, 5.0}, {}}};
  const ChainSetup chain = chain_of(segs);
  const Bracket b{0, 0, 5, 6};  // two windows on the way up
  const int factor = 4;
  const ChainSetup fine = refined_chain(chain, segs, b, factor);
  const Window &a = chain.protocol.windows[5], &z = chain.protocol.windows[6];
  const ajx::physics::MotorSchedule s0 = chain.motor(), s1 = fine.motor();

  // Identical drive before the bracket: φ and ω agree to the round-off of summing segments.
  for (double t = 0.0; t <= a.t_begin; t += a.t_begin / 97) {
    double p0, w0, p1, w1;
    phase(s0, t, p0, w0);
    phase(s1, t, p1, w1);
    EXPECT_NEAR(p1, p0, 1e-12 * std::abs(p0) + 1e-12) << "t = " << t;
    EXPECT_NEAR(w1, w0, 1e-12 * w0 + 1e-12);
  }
  // No jump at the junction, then rate/factor until the end of the bracket's second window.
  double pm, wm, pp, wp;
  phase(s1, a.t_begin - 1e-9, pm, wm);
  phase(s1, a.t_begin + 1e-9, pp, wp);
  EXPECT_NEAR(wp, wm, 1e-8);
  EXPECT_NEAR(pp, pm, 1e-7);  // |Δφ| ≈ 2 ω · 1e-9 s
  double p2, w2, od;
  s1.phase(a.t_begin + 1.0, p2, w2, od);
  EXPECT_NEAR(od, 0.5 / factor, 1e-12);
  ASSERT_FALSE(fine.protocol.windows.empty());
  EXPECT_DOUBLE_EQ(fine.protocol.windows.front().t_begin, a.t_begin);
  EXPECT_NEAR(fine.protocol.windows.front().omega_begin, a.omega_begin, 1e-12);
  EXPECT_NEAR(fine.protocol.windows.back().omega_end, z.omega_end, 1e-12);
  // The same window length: each new window spans factor times less ω_m.
  const double old_span = a.omega_end - a.omega_begin;
  for (const Window& w : fine.protocol.windows) {
    EXPECT_EQ(w.direction, +1);
    EXPECT_NEAR(w.omega_end - w.omega_begin, old_span / factor, 0.5 * old_span / factor);
  }
  EXPECT_NEAR(fine.protocol.duration, a.t_begin + factor * (z.t_end - a.t_begin), 1e-9);
}

TEST(Refine, StaircaseGetsFactorTimesTheLevels) {
  const std::vector<Segment> segs{Segment{Segment::Kind::Steps, {}, {30.0, 10.0, 5, 20.0, 5.0, 1.0}}};
  const ChainSetup chain = chain_of(segs);
  ASSERT_EQ(chain.protocol.windows.size(), 5u);  // 30, 25, 20, 15, 10 rad/s, falling
  const ChainSetup fine = refined_chain(chain, segs, Bracket{0, 0, 1, 3}, 3);
  // From 25 to 15 rad/s: 3·2 + 1 levels, 5/3 rad/s apart, each settled and measured as before.
  ASSERT_EQ(fine.protocol.windows.size(), 7u);
  for (std::size_t i = 0; i < 7; ++i) {
    EXPECT_NEAR(fine.protocol.windows[i].omega_begin, 25.0 - 10.0 * double(i) / 6.0, 1e-12);
    EXPECT_EQ(fine.protocol.windows[i].direction, -1);
    EXPECT_NEAR(fine.protocol.windows[i].t_end - fine.protocol.windows[i].t_begin, 5.0, 1e-12);
  }
  EXPECT_GE(fine.protocol.windows.front().t_begin, chain.protocol.windows[1].t_begin);
}

TEST(Refine, RejectsBracketsThatAreNotOneDirection) {
  const std::vector<Segment> segs{Segment{Segment::Kind::Ramp, {0.0, 4 * pi, 0.5, 5.0}, {}},
                                  Segment{Segment::Kind::Ramp, {4 * pi, 2 * pi, 0.5, 5.0}, {}}};
  const ChainSetup chain = chain_of(segs);
  const int last_up = int(std::lround(4 * pi / 0.5 / 5.0)) - 1;
  EXPECT_THROW(refined_chain(chain, segs, Bracket{0, 0, last_up, last_up + 1}, 2), std::invalid_argument);
  EXPECT_THROW(refined_chain(chain, segs, Bracket{0, 0, 1, 2}, 0), std::invalid_argument);
  EXPECT_THROW(refined_chain(chain, segs, Bracket{0, 0, 2, 1}, 2), std::invalid_argument);
  EXPECT_THROW(refined_chain(chain, segs, Bracket{0, 0, 1, 999}, 2), std::invalid_argument);
}
