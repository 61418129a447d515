// Refining a threshold: a bracket from a sweep says the class changed between two windows.
// The chain is re-run from its last stored state before the bracket, along its own schedule up
// to the start of the window before the change, and then across the bracket `factor` times
// slower: a ramp at rate/factor with windows of the same length (so each window spans factor
// times less ω_m), a staircase with factor times as many levels with the same settle and
// measure times. The new windows are classified and the threshold looked for again among them.
//
// If the change is not found in the refined windows, it moved with the ramp rate or dwell time
// beyond the old bracket: the threshold is rate-dependent there (a transient, not a
// bifurcation of the quasi-static orbit), which is worth knowing in itself.
#pragma once
#include <optional>
#include <vector>

#include "physics/state.hpp"
#include "sweep/orbit_classifier.hpp"
#include "sweep/protocol.hpp"
#include "sweep/task.hpp"
#include "sweep/thresholds.hpp"

namespace ajx::sweep {

// A chain's motor schedule up to t_cut: the piece containing t_cut is cut there and made to
// end at ω_cut exactly (the caller's ω_m at t_cut). Shared by refinement and hold tests.
std::vector<physics::DriveSegment> schedule_until(const std::vector<physics::DriveSegment>& schedule, double t_cut,
                                                  double omega_cut);

// The refined piece of a chain: a chain setup whose schedule is the old one up to the start of
// the window before the change, then the slower segment; its windows are the new ones only.
// `segments` are the chain's protocol segments (windows refer to them by index).
// Throws std::invalid_argument when the bracket's windows are not of one ramp or staircase
// direction or factor < 1.
ChainSetup refined_chain(const ChainSetup& chain, const std::vector<Segment>& segments, const Bracket& bracket,
                         int factor);

struct Refinement {
  std::optional<Bracket> bracket;  // the threshold among the new windows; none: it moved out
  int factor = 1;
  std::vector<ClassedWindow> windows;  // the new windows with their classes
  bool ok = true;                  // false: the integration failed (see failure)
  std::string failure;
  double simulated = 0.0;          // seconds integrated [s]
};

// Re-runs threshold t of a chain from `start` (a stored state of the chain at a time no later
// than the start of the bracket's first window).
Refinement refine_threshold(Threshold t, const ChainSetup& chain, const std::vector<Segment>& segments,
                            const Bracket& bracket, int factor, const physics::State& start,
                            const ClassifierSettings& settings = {});

}  // namespace ajx::sweep
