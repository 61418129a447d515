// astrojax thresholds on the farm (thresholds_farm.cpp): the holds and refinements of every
// bracket are independent checks (sweep/bracket_check.hpp), run as farm tasks on the ranks of
// MPI_COMM_WORLD and on threads of rank 0. Rank 0 reads the sweep file and plans the checks;
// the other ranks get what they need to rebuild the sweep's plan (the stored sweep file and
// the classifier's settings) in one broadcast, and each task brings its check and start state.
// In one process the same farm runs the checks on threads (-j), as the sweep does.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "parallel/farm.hpp"
#include "physics/state.hpp"
#include "sweep/bracket_check.hpp"
#include "sweep/orbit_classifier.hpp"
#include "sweep/plan.hpp"

namespace ajx::app {

// What a worker rank rebuilds the sweep's plan from: /config of the file (text, name,
// overrides) and the classifier's settings ("name=value") the checks classify with.
struct ChecksContext {
  std::string config_text, config_source;
  std::vector<std::string> overrides, classifier_settings;
};

struct PlannedCheck {
  sweep::BracketCheck check;
  physics::State start;  // the chain's stored state before the check, read from the file
};

// Rank 0, collective with checks_worker on the other ranks: hands `context` to the workers and
// runs every check on the farm (with `threads` threads of rank 0, as FarmOptions::threads), the
// master's own threads with `plan` and `settings`. Results in the order of `checks`; none when
// Ctrl-C, SIGTERM or SIGUSR1 stopped the farm (the checks under way are finished first).
std::optional<std::vector<sweep::CheckResult>> run_checks(const ChecksContext& context, const sweep::SweepPlan& plan,
                                                         const sweep::ClassifierSettings& settings,
                                                         const std::vector<PlannedCheck>& checks, int threads);

// Rank 0 refused the input before any check: the workers are told (run_checks is not called).
void refuse_checks();

// The other ranks: wait for rank 0's context (none: it refused its input), rebuild the plan
// and serve the farm until rank 0 ends it.
void checks_worker();

}  // namespace ajx::app
