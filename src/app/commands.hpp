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
  double task_timeout = 0;  // [s] a task not back within it is failed and its rank given up; 0: no bound
  std::string command_line;
};
// Collective: every rank of MPI_COMM_WORLD calls it (rank 0 is the master).
int sweep_command(const SweepArgs& args);

struct ThresholdsArgs {
  std::string input;  // a sweep's HDF5 file
  std::string csv;    // also write the table as CSV here, when non-empty
};
int thresholds_command(const ThresholdsArgs& args);

struct ClassifyArgs {
  std::string input;                  // a sweep's HDF5 file, rewritten in place
  std::vector<std::string> settings;  // "name=value" of ClassifierSettings fields
};
int classify_command(const ClassifyArgs& args);

}  // namespace ajx::app
