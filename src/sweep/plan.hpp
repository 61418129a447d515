// The plan of a sweep: its chains, each with its model, compiled protocol and split into tasks.
// A chain is one grid point running the protocol, or in the hold mode one (grid point, held
// ω_m, seed, perturbation). Built the same way by the sweep and by everything that later
// re-runs part of a chain from a sweep file (threshold refinement), so both agree.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "physics/state.hpp"
#include "sim/simulation.hpp"
#include "sweep/grid.hpp"
#include "sweep/protocol.hpp"
#include "sweep/task.hpp"

namespace ajx::sweep {

// Where a chain starts: a seed state (see seeds.hpp) at ω_m = omega.
struct ChainStart {
  ChainStart() = default;
  ChainStart(std::string seed_, double omega_, int perturbation_, double kick_)
      : seed(std::move(seed_)), omega(omega_), perturbation(perturbation_), kick(kick_) {}
  std::string seed = "hanging";
  double omega = 0.0;     // [rad/s]
  int perturbation = 0;   // 0: the seed itself; k >= 1: the seed with velocity kick k
  double kick = 0.0;      // rms of a perturbation's velocity kick [m/s]
  // A basin chain (sweep/basin.hpp): its level and sample, and the start drawn for it.
  int level = -1, sample = -1;
  std::optional<physics::State> state;
};

struct SweepPlan {
  // Every grid axis of the file (of any part), in order of first appearance; a chain's
  // points[c].values has one value per axis, NaN where its part has no such axis.
  std::vector<std::string> axes;
  std::vector<std::size_t> part;          // per chain: its part of SweepConfig::parts (0 for a plain file)
  std::vector<GridPoint> points;     // per chain: parameters and protocol segments
  std::vector<ChainStart> starts;         // per chain
  std::vector<ChainSetup> setups;         // per chain
  // Per chain: its bisection (a [bisect] part), whose tasks are probes with no /windows rows
  // (sweep/bisection.hpp); none for a protocol or hold chain.
  // Its setup has no windows and protocol.duration is an estimate (the holds and the ramps
  // between the levels).
  std::vector<std::optional<BisectSpec>> bisect;
  std::vector<std::vector<TaskSpan>> spans;  // per chain: its tasks in order
  std::vector<std::size_t> first_task;    // per chain: the global id of its task 0
  std::size_t n_tasks = 0;
  std::size_t max_windows = 0;            // the most windows of any chain
  std::size_t max_samples = 0;            // the most samples of any window
  double total_duration = 0.0;            // simulated seconds of all chains [s]

  std::size_t chains() const { return setups.size(); }
  bool has_bisection() const;
  // The state chain c starts from at t = 0.
  physics::State start_state(std::size_t c) const;
};

// One part of a sweep (a plain sweep has one): the model and integrator its chains start from,
// and what it asks for. A grouped sweep has a part per (group, model variant).
struct PlanPart {
  physics::Model model;
  sim::RunOptions run;
  SweepSpec spec;
  std::string source_name;  // for messages
};

// Throws GridError (grid points) or std::invalid_argument (protocols).
SweepPlan make_plan(const std::vector<PlanPart>& parts);

}  // namespace ajx::sweep
