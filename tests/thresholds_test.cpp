// Threshold brackets from constructed class sequences along the paper's protocol.
#include <gtest/gtest.h>

#include "sweep/thresholds.hpp"

using namespace ajx::sweep;

namespace {
using C = OrbitClass;
// Windows of 1 rad/s each: up from 0 to 6 with the given classes, down, then up again.
std::vector<ClassedWindow> seq(double from, int dir, std::initializer_list<C> classes) {
  std::vector<ClassedWindow> out;
  double w = from;
  for (C c : classes) {
    out.push_back({w, w + dir, dir, c});
    w += dir;
  }
  return out;
}
std::vector<ClassedWindow> join(std::initializer_list<std::vector<ClassedWindow>> parts) {
  std::vector<ClassedWindow> out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}
}  // namespace

TEST(Thresholds, ThePaperProtocolShape) {
  const auto w = join({
      seq(0, +1, {C::Fallen, C::Fallen, C::Fallen, C::NotSettled, C::LockedCircular, C::LaggingCircular}),  // rise at 3→4
      seq(6, -1, {C::LaggingCircular, C::LockedCircular, C::LockedCircular, C::NotSettled, C::Fallen, C::Fallen}),
      seq(0, +1, {C::Fallen, C::LockedCircular, C::LockedCircular, C::LaggingCircular, C::LaggingCircular, C::Flower}),
  });
  const auto rise = find_threshold(Threshold::Rise, w);
  ASSERT_TRUE(rise);
  EXPECT_DOUBLE_EQ(rise->before, 2.5);
  EXPECT_DOUBLE_EQ(rise->after, 3.5);
  const auto fall = find_threshold(Threshold::Fall, w);  // locked at 3.5 (window 4→3), fallen at 1.5
  ASSERT_TRUE(fall);
  EXPECT_DOUBLE_EQ(fall->before, 3.5);
  EXPECT_DOUBLE_EQ(fall->after, 1.5);
  const auto w1 = find_threshold(Threshold::Omega1, w);  // the last locked on the way up: 2.5 → 3.5
  ASSERT_TRUE(w1);
  EXPECT_DOUBLE_EQ(w1->before, 2.5);
  EXPECT_DOUBLE_EQ(w1->after, 3.5);
  const auto w2 = find_threshold(Threshold::Omega2, w);  // lagging at 4.5, flower at 5.5
  ASSERT_TRUE(w2);
  EXPECT_DOUBLE_EQ(w2->mid(), 5.0);
}

TEST(Thresholds, NotReachedAndFailedWindows) {
  const auto all_fallen = seq(0, +1, {C::Fallen, C::Fallen, C::Fallen});
  for (Threshold t : kThresholds) EXPECT_FALSE(find_threshold(t, all_fallen)) << to_string(t);
  // A failed window never makes a bracket.
  const auto failed = seq(0, +1, {C::Fallen, C::Failed, C::LockedCircular});
  EXPECT_FALSE(find_threshold(Threshold::Rise, failed));
  // A fall needs a circular orbit before it.
  const auto down = seq(5, -1, {C::Flower, C::Fallen});
  EXPECT_FALSE(find_threshold(Threshold::Fall, down));
}

// ω2 is a circular orbit giving way to a flower, through unsettled windows if need be; a lock
// lost to a lag through an unsettled window is not ω2.
TEST(Thresholds, Omega2IsCircularToFlower) {
  const auto lag_only = seq(4, +1, {C::LockedCircular, C::NotSettled, C::LaggingCircular, C::LaggingCircular});
  EXPECT_FALSE(find_threshold(Threshold::Omega2, lag_only));
  const auto w = seq(4, +1, {C::LockedCircular, C::NotSettled, C::LaggingCircular, C::NotSettled, C::NotSettled,
                             C::Flower, C::Fallen});
  const auto w2 = find_threshold(Threshold::Omega2, w);  // lagging at 6.5, flower at 9.5
  ASSERT_TRUE(w2);
  EXPECT_DOUBLE_EQ(w2->before, 6.5);
  EXPECT_DOUBLE_EQ(w2->after, 9.5);
  // A flower only after the bead has fallen is not a loss of a circular orbit.
  EXPECT_FALSE(find_threshold(Threshold::Omega2, seq(4, +1, {C::LaggingCircular, C::Fallen, C::Flower})));
}

TEST(Thresholds, PaperValues) {
  EXPECT_NEAR(paper_value(Threshold::Rise) / 3.141592653589793, 12.63, 1e-12);
  EXPECT_NEAR(paper_value(Threshold::Omega2) / 3.141592653589793, 15.0, 1e-12);
}
