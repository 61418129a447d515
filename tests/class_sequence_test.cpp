// The orbit class sequence (sweep/class_sequence.hpp): runs per leg with repeats collapsed,
// single not-settled blips absorbed on request, ω_ball's slope against ω_m, and the paper's steps found
// present, missing or out of order.
#include <gtest/gtest.h>

#include <cmath>

#include "sweep/class_sequence.hpp"

using namespace ajx::sweep;

namespace {
const double pi = 3.141592653589793;
using C = OrbitClass;

// Windows of 0.5π rad/s from `from` in direction dir, one per class given; ω_ball = ω_m for
// locked windows, 4.8π for lagging ones, NaN otherwise.
void leg(std::vector<ClassedWindow>& w, std::vector<double>& ob, double from, int dir, std::vector<C> classes) {
  double om = from;
  for (C c : classes) {
    const double next = om + dir * 0.5 * pi;
    w.push_back({om, next, dir, c, int(w.size())});
    const double mean = 0.5 * (om + next);
    ob.push_back(c == C::LockedCircular ? mean : c == C::LaggingCircular ? 4.8 * pi : std::nan(""));
    om = next;
  }
}
}  // namespace

TEST(ClassSequence, RunsCollapseRepeatsAndAbsorbSingleBlips) {
  std::vector<ClassedWindow> w;
  std::vector<double> ob;
  leg(w, ob, 0.0, +1, {C::Fallen, C::Fallen, C::NotSettled, C::Fallen, C::NotSettled, C::NotSettled, C::Flower});
  leg(w, ob, 3.5 * pi, -1, {C::Flower, C::Fallen});
  ASSERT_EQ(class_runs(w, ob).size(), 7u);  // by default a blip is a run of its own
  const auto runs = class_runs(w, ob, true);
  ASSERT_EQ(runs.size(), 5u);
  EXPECT_EQ(runs[0].cls, C::Fallen);
  EXPECT_EQ(runs[0].windows, 4);  // the blip at window 2 absorbed
  EXPECT_EQ(runs[0].blips, 1);
  EXPECT_NEAR(runs[0].omega_from, 0.0, 1e-12);
  EXPECT_NEAR(runs[0].omega_to, 2 * pi, 1e-12);
  EXPECT_EQ(runs[1].cls, C::NotSettled);  // two in a row are a run
  EXPECT_EQ(runs[1].windows, 2);
  EXPECT_EQ(runs[2].cls, C::Flower);
  EXPECT_EQ(runs[3].cls, C::Flower);  // the same class on the next leg is a new run
  EXPECT_EQ(runs[3].leg, 1);
  EXPECT_EQ(runs[3].direction, -1);
  EXPECT_THROW(class_runs(w, {}), std::invalid_argument);
}

TEST(ClassSequence, TheOmegaBallSlopeTellsLockedFromThePapersLagging) {
  std::vector<ClassedWindow> w;
  std::vector<double> ob;
  leg(w, ob, 3 * pi, +1, {C::LockedCircular, C::LockedCircular, C::LockedCircular, C::LaggingCircular,
                          C::LaggingCircular, C::LaggingCircular});
  const auto runs = class_runs(w, ob);
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_NEAR(runs[0].omega_ball_slope, 1.0, 1e-12);
  EXPECT_NEAR(runs[1].omega_ball_slope, 0.0, 1e-12);
  EXPECT_NEAR(runs[1].omega_ball_mean, 4.8 * pi, 1e-12);
}

TEST(ClassSequence, ThePapersSequenceIsFoundInOrder) {
  // Up from rest: fallen, climb (not settled), circular; down: lagging, fallen; up again from a
  // circular orbit: locked, lagging, flower.
  std::vector<ClassedWindow> w;
  std::vector<double> ob;
  leg(w, ob, 11 * pi, +1, {C::Fallen, C::Fallen, C::NotSettled, C::NotSettled, C::LaggingCircular});
  leg(w, ob, 13.5 * pi, -1, {C::LaggingCircular, C::LockedCircular, C::NotSettled, C::Fallen});
  leg(w, ob, 4 * pi, +1, {C::LockedCircular, C::LockedCircular, C::NotSettled, C::LaggingCircular, C::Flower});
  const auto m = compare_with_paper(class_runs(w, ob));
  ASSERT_EQ(m.size(), kPaperSteps.size());
  for (const StepMatch& s : m) EXPECT_EQ(s.status, StepStatus::Present) << to_string(s.step);
  EXPECT_NEAR(m[0].omega, 12 * pi, 1e-12);   // rise: the climb starts after two fallen windows
  EXPECT_NEAR(m[2].omega, 12 * pi, 1e-12);   // fall: the fallen window of the down leg
  EXPECT_NEAR(m[4].omega, 5.5 * pi, 1e-12);  // ω1: lagging entered on the second up leg
}

TEST(ClassSequence, MissingAndOutOfOrderStepsAreNamed) {
  // Locked then lagging on the way up, then the bead falls on the way down: ω1 happens before
  // the fall, and no climb from fallen, no flower.
  std::vector<ClassedWindow> w;
  std::vector<double> ob;
  leg(w, ob, 4 * pi, +1, {C::LockedCircular, C::LaggingCircular});
  leg(w, ob, 5 * pi, -1, {C::LaggingCircular, C::Fallen});
  const auto m = compare_with_paper(class_runs(w, ob));
  EXPECT_EQ(m[0].status, StepStatus::Missing);     // rise
  EXPECT_EQ(m[1].status, StepStatus::Present);     // circular
  EXPECT_EQ(m[2].status, StepStatus::Present);     // fall
  EXPECT_EQ(m[3].status, StepStatus::OutOfOrder);  // locked: only before the fall
  EXPECT_EQ(m[4].status, StepStatus::OutOfOrder);  // ω1 likewise
  EXPECT_EQ(m[5].status, StepStatus::Missing);     // ω2
}
