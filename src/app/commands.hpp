// Subcommands of the astrojax executable. Each returns the process exit code:
// 0 success, 2 bad input (nothing written), 3 the integration failed (file written, marked failed).
#pragma once
#include <string>
#include <vector>

namespace ajx::app {

inline constexpr int kExitBadInput = 2;
inline constexpr int kExitRunFailed = 3;

struct RunArgs {
  std::string config_path;
  std::vector<std::string> overrides;  // "key=value"
  std::string output;                  // overrides output.path when non-empty
  bool quiet = false;
  std::string command_line;            // stored in the file for provenance
};
int run_command(const RunArgs& args);

inline constexpr int kExitInterrupted = 4;

struct SweepArgs {
  std::string config_path;
  std::vector<std::string> overrides;
  std::string output;
  bool quiet = false;
  bool resume = false;  // continue an interrupted sweep from <output>.part
  long max_tasks = 0;   // stop (resumably) after this many task results; 0: no limit
  std::string command_line;
};
// Collective: every rank of MPI_COMM_WORLD calls it (rank 0 is the master).
int sweep_command(const SweepArgs& args);

struct ThresholdsArgs {
  std::string input;  // a sweep's HDF5 file
  std::string csv;    // also write the table as CSV here, when non-empty
  int refine = 0;     // re-run each bracket this many times slower (0: no refinement)
  int jobs = 1;       // threads for the refinements
};
int thresholds_command(const ThresholdsArgs& args);

struct ClassifyArgs {
  std::string input;                  // a sweep's HDF5 file, rewritten in place
  std::vector<std::string> settings;  // "name=value" of ClassifierSettings fields
};
int classify_command(const ClassifyArgs& args);

struct OrbitsArgs {
  std::string config_path;             // any run or sweep file, or one with an [orbits] table
  std::vector<std::string> overrides;
  std::vector<std::string> omega;      // ω_m values: rad/s, or "4.7pi"
  std::vector<double> s;               // stuck orbits to continue, bead positions [m]
  std::string parameter;               // continue in this parameter
  std::vector<double> range;           // [lo, hi] of the continuation
  int s_points = 0;                    // 0: the config's (default 81)
  bool all = false;                    // print every stuck orbit, not only their summary
  bool thresholds = false;             // predict ω_rise, ω_fall, ω1 from the branches
  int threshold_s_points = 21;
  std::string compare;                 // a sweep's HDF5: its brackets next to the predictions
  std::string csv, branches_csv, events_csv, output;
  std::string command_line;
};
int orbits_command(const OrbitsArgs& args);

}  // namespace ajx::app
