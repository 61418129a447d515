// Recurrence on a Poincaré section (sim/section_recurrence.hpp), on sequences of section points
// whose distance to their periodic orbit is known: an exact period of k crossings is found with
// its T, turn and integrals once the crossings span the history; an orbit converging onto a
// periodic one is recognised only where skipping the periods that fit moves it by less than
// ε l; a steady drift counts with the periods skipped; a deviation that grows (a lag just past
// its Hopf point) is never taken for a period however small; a second frequency beside the orbit
// (a quasi-periodic motion) is never taken for a period, nor are crossings in the other direction.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/section_recurrence.hpp"

using namespace ajx::sim;

namespace {

constexpr double kTol = 1e-3 * 0.826;  // ε l [m]
constexpr double kHistory = 5.0;        // [s], as the settle watch's

// The j-th crossing of an orbit with k crossings a period T, turning by Δψ = 2 a period, the
// first integral growing by 0.5 J a period; `offset` moves the point off the orbit along p_0.
SectionPoint point(int j, int k, double T, double offset, int direction = 1) {
  SectionPoint p;
  p.t = T * j / k;
  p.psi = 2.0 * j / k;
  p.direction = direction;
  p.p = Eigen::VectorXd::Zero(12);
  p.p(1) = 0.1 * std::sin(2 * M_PI * (j % k) / k) + 0.2;  // where the crossing lies on the orbit
  p.p(2) = 0.1 * std::cos(2 * M_PI * (j % k) / k);
  p.p(0) = offset;
  p.works[0] = 0.5 * j / k;
  return p;
}

}  // namespace

TEST(SectionRecurrence, AnExactPeriodOfFourCrossingsIsFoundWithItsPeriodTurnAndWork) {
  SectionRecurrence rec(kTol, kHistory);
  std::optional<Period> found;
  int j = 0;
  for (; j < 40 && !found; ++j) found = rec.add(point(j, 4, 1.0, 0.0), 100.0);
  ASSERT_TRUE(found);
  // Crossings every 0.25 s: the pairs a period apart span the 5 s history from crossing 20 on.
  EXPECT_EQ(j, 21);
  EXPECT_EQ(found->crossings, 4);
  EXPECT_NEAR(found->T, 1.0, 1e-12);
  EXPECT_NEAR(found->turn, 2.0, 1e-12);
  EXPECT_NEAR(found->works[0], 0.5, 1e-12);
  EXPECT_EQ(found->distance, 0.0);
}

TEST(SectionRecurrence, AConvergingOrbitIsRecognisedOnlyWhereTheSkipMovesItLessThanTolerance) {
  // Offsets a q^j, q = 0.9 a period of 0.25 s: skipping n periods from crossing j leaves the
  // point where the orbit would be a q^j (1 − q^n) further on.
  const double a = 0.05, q = 0.9, T = 0.25;
  for (double time_left : {5.0, 50.0}) {
    SectionRecurrence rec(kTol, kHistory);
    bool found = false;
    for (int j = 0; j < 400 && !found; ++j) {
      const std::optional<Period> per = rec.add(point(j, 1, T, a * std::pow(q, j)), time_left);
      if (!per) continue;
      found = true;
      const double n = std::floor(time_left / per->T);
      EXPECT_LE(a * std::pow(q, j) * (1.0 - std::pow(q, n)), kTol) << j;
      EXPECT_LE(a * std::pow(q, j) * (1.0 - std::pow(q, n)), per->distance) << j;
    }
    EXPECT_TRUE(found) << time_left;
  }
}

TEST(SectionRecurrence, ASteadyDriftCountsWithThePeriodsSkipped) {
  // A drift of 1e-6 m a period: the bound is n times it, n = time left / T.
  const double drift = 1e-6, T = 0.25;
  for (double time_left : {10.0, 100.0, 1000.0}) {
    SectionRecurrence rec(kTol, kHistory);
    std::optional<Period> found;
    for (int j = 0; j < 40; ++j) found = rec.add(point(j, 1, T, drift * j), time_left);
    const double n = std::floor(time_left / T);
    EXPECT_EQ(found.has_value(), n * drift <= kTol) << time_left;
  }
}

TEST(SectionRecurrence, AGrowingDeviationIsNeverTakenForAPeriodHoweverSmall) {
  // Offsets a e^{γ t}, γ = 0.1/s (the growth of the lag at 16π, 0.65π past its Hopf point), from
  // a = 1e-9 m: over 400 crossings the drift times the periods that fit stays below ε l, which
  // the linear bound alone would take for a periodic orbit; the growth over the history is not.
  const double a = 1e-9, gamma = 0.1, T = 0.25, time_left = 50.0;
  SectionRecurrence rec(kTol, kHistory);
  const double n = std::floor(time_left / T);
  for (int j = 0; j < 400; ++j) {
    const double drift = a * std::exp(gamma * T * j) * (std::exp(gamma * T) - 1.0);
    ASSERT_LT(n * drift, kTol) << j;  // the linear bound would hold
    EXPECT_FALSE(rec.add(point(j, 1, T, a * std::exp(gamma * T * j)), time_left)) << j;
  }
}

TEST(SectionRecurrence, ASecondFrequencyBesideTheOrbitIsNeverTakenForAPeriod) {
  // A swing of 1 mm at a frequency incommensurate with the crossings (the golden ratio): some
  // consecutive shifts are small, but not over the history.
  const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
  SectionRecurrence rec(kTol, kHistory);
  for (int j = 0; j < 400; ++j)
    EXPECT_FALSE(rec.add(point(j, 1, 0.25, 1e-3 * std::sin(2 * M_PI * golden * j)), 60.0)) << j;
}

TEST(SectionRecurrence, CrossingsInTheOtherDirectionNeverMatchAndAPeriodMustFit) {
  // The same point, its directions the Thue-Morse sequence (no three equal blocks in a row: no
  // period of the directions).
  SectionRecurrence rec(kTol, kHistory);
  for (int j = 0; j < 60; ++j)
    EXPECT_FALSE(rec.add(point(j, 1, 0.3, 0.0, __builtin_popcount(unsigned(j)) % 2 ? -1 : 1), 100.0)) << j;
  // Exact, but less than a period left.
  SectionRecurrence short_left(kTol, kHistory);
  for (int j = 0; j < 40; ++j) EXPECT_FALSE(short_left.add(point(j, 1, 0.3, 0.0), 0.2)) << j;
}
