// The orbit class sequence of a chain, and how it compares with the paper's.
//
// A chain's windows in protocol order are cut into legs (maximal stretches of one direction:
// ω_m rising, falling, or one held level), and each leg into runs of one class, repeats
// collapsed. On request, one not-settled window between two windows of the same class on the
// same leg is a blip and is absorbed into that class (counted in `blips`). That is off by
// default: a one-window excursion (the bead climbs and falls back within a window on a slow
// ramp) is exactly such a window, and absorbing it would hide the paper's "rise" step.
//
// The paper's sequence (the paper's section 3.2; docs/guide/thresholds.md), as steps in this order:
//   rise      up: fallen → not fallen (the bead starts to climb at ω_rise)
//   circular  a circular orbit (locked or lagging) after the climb
//   fall      down: circular → fallen (not-settled runs between allowed) at ω_fall
//   locked    up: a locked-circular orbit (ω_ball = ω_m)
//   omega_1   up: locked → lagging (not-settled runs between allowed) at ω1; the paper's
//             lagging orbit keeps ω_ball nearly constant (dω_ball/dω_m ≈ 0)
//   omega_2   up: circular → flower (not-settled runs between allowed) at ω2
// Each step is looked for after the last step found: present when found there, out of order
// when it occurs only before it, missing when it does not occur at all.
#pragma once
#include <array>
#include <limits>
#include <string_view>
#include <vector>

#include "sweep/orbit_classifier.hpp"
#include "sweep/thresholds.hpp"

namespace ajx::sweep {

struct ClassRun {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  int leg = 0;              // legs numbered from 0 in protocol order
  int direction = 0;        // +1 rising, -1 falling, 0 held
  OrbitClass cls = OrbitClass::NotSettled;
  double omega_from = nan;  // ω_m at the start of its first window [rad/s]
  double omega_to = nan;    // ω_m at the end of its last window [rad/s]
  int first = 0, last = 0;  // positions of its first and last window in the input
  int windows = 0;          // windows in it, blips included
  int blips = 0;            // single not-settled windows absorbed
  double omega_ball_mean = nan;   // mean ω_ball over its windows with one [rad/s]
  double omega_ball_slope = nan;  // least-squares dω_ball/dω_m over them (1 locked; paper's lagging ≈ 0)
};

// `omega_ball` holds each window's ω_ball (NaN when unreliable), as many as `windows`.
// Throws std::invalid_argument when the sizes differ.
std::vector<ClassRun> class_runs(const std::vector<ClassedWindow>& windows, const std::vector<double>& omega_ball,
                                 bool absorb_blips = false);

enum class PaperStep { Rise, Circular, Fall, Locked, Omega1, Omega2 };
inline constexpr std::array<PaperStep, 6> kPaperSteps{PaperStep::Rise,   PaperStep::Circular, PaperStep::Fall,
                                                      PaperStep::Locked, PaperStep::Omega1,   PaperStep::Omega2};
std::string_view to_string(PaperStep s);     // "rise", "circular", "fall", "locked", "omega_1", "omega_2"
std::string_view describe(PaperStep s);      // e.g. "up: fallen -> climb (omega_rise)"

enum class StepStatus { Present, OutOfOrder, Missing };
std::string_view to_string(StepStatus s);    // "present", "out of order", "missing"

struct StepMatch {
  PaperStep step;
  StepStatus status = StepStatus::Missing;
  int run = -1;       // the run where it happens (the run entered, for a transition)
  double omega = ClassRun::nan;  // ω_m where it happens: the start of that run [rad/s]
};

std::vector<StepMatch> compare_with_paper(const std::vector<ClassRun>& runs);

}  // namespace ajx::sweep
