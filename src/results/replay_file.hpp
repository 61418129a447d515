// The file of `astrojax replay`: a run file (its /trajectory with the whole energy ledger,
// /summary, provenance, so that every reader of run files reads it) with dense samples of one
// sweep window re-run from its stored start, plus what only a replay knows: the stored window
// it reproduces against what the re-run found (/replay).
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "results/run_file.hpp"
#include "results/sweep_result.hpp"
#include "sim/simulation.hpp"

namespace ajx::results {

// The stored window and the re-run's verdict on it.
struct ReplayInfo {
  std::string source;                  // the sweep file
  std::string source_commit;           // its /provenance git_commit ("" when absent)
  std::int64_t chain = 0, window = 0, task = 0;  // task: its index in the chain
  std::string group, variant, variant_label;     // "" for a plain sweep
  double task_begin = 0, t_begin = 0, t_end = 0;  // [s]
  double omega_begin = 0, omega_end = 0;          // ω_m at the window's ends [rad/s]
  std::int64_t direction = 0;
  double sweep_sample_rate = 0, sample_rate = 0;  // [1/s] the sweep's and the replay's
  WindowRow stored, replayed;
  std::string reason;                  // the classifier's, for the replayed window
  bool reproduced = false;             // same class and ω_ball to the stored precision
  double omega_ball_difference = 0;    // replayed − stored [rad/s] (0 when both undefined)
};

// The replay's run file at `path` (its folder made if missing): written as "<path>.part" and
// renamed when complete, so a failure (io::Hdf5Error) leaves nothing behind.
void write_replay(const std::filesystem::path& path, const std::string& command_line, const config::CommonConfig& cfg,
                  const Trajectory& traj, const ReplayInfo& info, const sim::RunSummary& sum);

}  // namespace ajx::results
