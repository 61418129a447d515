// A bracket's checks as independent tasks: the hold of one side (sweep/hold_verdict.hpp) or a
// refinement (sweep/refine.hpp), each an integration of one chain of a sweep's plan from a
// stored state. `astrojax thresholds` hands them to the farm (which moves bytes): the check and
// its result travel encoded here, and decode(encode(x)) == x exactly, so a result is the same
// bytes whichever rank or thread computed it.
#pragma once
#include <cstddef>
#include <string>
#include <variant>
#include <vector>

#include "physics/state.hpp"
#include "sweep/hold_verdict.hpp"
#include "sweep/orbit_classifier.hpp"
#include "sweep/plan.hpp"
#include "sweep/refine.hpp"
#include "sweep/thresholds.hpp"

namespace ajx::sweep {

// Hold ω_m at its value at t_cut for `hold` seconds in windows of `window` s (hold_side).
struct HoldCheck {
  std::size_t chain = 0;
  double t_cut = 0.0;   // [s]
  double hold = 0.0;    // [s]
  double window = 0.0;  // [s]
  OrbitClass reference = OrbitClass::Failed;  // the sweep's class at this side
};

// Re-run threshold t's bracket `factor` times slower (refine_threshold).
struct RefineCheck {
  std::size_t chain = 0;
  Threshold threshold = Threshold::Rise;
  Bracket bracket{0.0, 0.0};
  int factor = 1;
};

using BracketCheck = std::variant<HoldCheck, RefineCheck>;
using CheckResult = std::variant<HoldSide, Refinement>;

// Runs the check on its chain of `plan` from `start` (a state of the chain no later than the
// check's start). An exception of the hold or refinement (a start later than it, a time outside
// the schedule, a chain the plan lacks) becomes the result's failure, ok = false.
CheckResult run_check(const BracketCheck& check, const SweepPlan& plan, const physics::State& start,
                      const ClassifierSettings& settings);

// The simulated seconds the check integrates from `start` (the hold's replay up to t_cut and the
// hold; the refined chain up to its last window), 0 for a check that cannot run: the farm hands
// the longest out first.
double check_seconds(const BracketCheck& check, const SweepPlan& plan, const physics::State& start);

// The check's result when it could not run to its end: ok = false with `why` as its failure.
CheckResult failed_check(const BracketCheck& check, const std::string& why);

// As bytes; the decoders throw std::runtime_error on a truncated or overlong message.
std::vector<std::byte> encode(const BracketCheck& check);
BracketCheck decode_check(const std::vector<std::byte>& bytes);
std::vector<std::byte> encode(const CheckResult& result);
CheckResult decode_check_result(const std::vector<std::byte>& bytes);

}  // namespace ajx::sweep
