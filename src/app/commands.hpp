// Subcommands of the astrojax executable. Each returns the process exit code, one meaning each
// (also under mpirun, where the master's code is the job's): 0 success, 1 an internal error (a
// bug, an MPI failure), 2 bad input (refused before any work, nothing written), 3 the
// integration failed (file written, marked failed), 4 interrupted (resumable: --resume),
// 5 the output could not be written while running (disk full; resumable once fixed).
// (mpirun sent SIGTERM or SIGINT itself returns 1 whatever the ranks return:
// docs/reference/exit-codes.md.)
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
  bool force = false;                  // replace an existing output
  double max_memory = 0;               // [MB] memory budget; 0: half the machine's
  std::string command_line;            // stored in the file for provenance
};
int run_command(const RunArgs& args);

inline constexpr int kExitInterrupted = 4;
// The output could not be written while the work ran (disk full, file too large, I/O error):
// what was finished is kept, but running again without fixing the cause cannot finish.
inline constexpr int kExitOutputFailed = 5;

struct SweepArgs {
  std::string config_path;
  std::vector<std::string> overrides;
  std::string output;
  bool quiet = false;
  bool resume = false;  // continue an interrupted sweep from <output>.part
  bool force = false;   // start afresh even over an interrupted sweep's .part and journal
  bool dry_run = false; // print the plan (chains, tasks, simulated seconds, a CPU estimate) and exit
  long max_tasks = 0;   // stop (resumably) after this many task results; 0: no limit
  double task_timeout = 0;  // [s] a task not back within it runs elsewhere, its rank given up; 0: automatic
  double min_task_timeout = 60;  // [s] the least automatic bound (20 times the slowest finished task)
  double max_memory = 0;  // [MB] memory budget of one rank; 0: half the machine's
  int threads = 1;  // threads of rank 0 that integrate (parallel::FarmOptions::threads)
  std::string command_line;
};
// Collective: every rank of MPI_COMM_WORLD calls it (rank 0 is the master).
int sweep_command(const SweepArgs& args);

// astrojax verify: a sweep's file (finished or .part) checked against its own /config and its
// journal; 0 intact, 2 damaged (each damage reported).
struct VerifyArgs {
  std::string input;
};
int verify_command(const VerifyArgs& args);

struct ThresholdsArgs {
  std::string input;  // a sweep's HDF5 file
  std::string csv;    // also write the table as CSV here, when non-empty
  int refine = 0;     // re-run each bracket this many times slower (0: no refinement)
  int jobs = 0;       // threads of rank 0 for the holds and refinements (0: the cores in one process, 1 under mpirun)
  std::string hold = "5tau";  // hold both sides of each bracket this long: seconds, or "Ntau" drag times
  bool no_hold = false;       // no holds: brackets without verdicts
  std::string markdown;       // also write the report as Markdown here, when non-empty
  double onset_span = 3.0;    // the Hopf fit takes levels up to this far above the first flower [π rad/s]
  bool sequence = false;      // print each chain's orbit class sequence against the paper's
  std::string sequence_csv;   // also write the sequence as CSV here, when non-empty
  bool absorb_blips = false;  // the sequence absorbs single not-settled windows between two of one class
  std::vector<std::string> settings;  // "classifier.name=value": classify the windows again in memory first
};
// Holds or --refine integrate: MPI is then initialised and the checks run as farm tasks on every
// rank of the job; without them one process reads the file (rank 0 under mpirun).
inline bool thresholds_integrate(const ThresholdsArgs& a) { return !a.no_hold || a.refine > 0; }
int thresholds_command(const ThresholdsArgs& args);

// astrojax replay: one window of a sweep file re-run from its stored start, dense samples into a
// run file; 0 reproduced, 2 bad input (nothing written), 3 written but not reproduced or failed.
struct ReplayArgs {
  std::string input;           // a sweep's HDF5 file
  long chain = -1, window = -1;
  std::string output;          // the run file to write
  double sample_rate = 200.0;  // dense samples per second [1/s]
  double before = 0.0;         // also sample this long before the window, within its task [s]
  bool force = false;          // replace an existing output
  bool quiet = false;
  std::string command_line;
};
int replay_command(const ReplayArgs& args);

// astrojax windows: every computed window with its class and the classifier's reason -> CSV.
struct WindowsArgs {
  std::string input;   // a sweep's HDF5 file
  std::string output;  // CSV path, "-" for stdout
  bool force = false;
};
int windows_command(const WindowsArgs& args);

struct ClassifyArgs {
  std::string input;                  // a sweep's HDF5 file
  std::string output;                 // the reclassified copy; empty: rewrite input (needs force)
  bool force = false;                 // rewrite input in place, or replace an existing output
  std::vector<std::string> settings;  // "classifier.name=value" of ClassifierSettings fields
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
  bool lag = false;                    // the lagging orbits of the slipping tie instead (orbits/lagging_orbit.hpp)
  std::string map_parameter;           // --map: the threshold curves in (this parameter, ω_m) (app/orbits_map.hpp)
  std::vector<std::string> map_curves; // --curves: fold, cone_up, cone_down, hopf (default: all the model has)
  std::string curves_csv;              // --curves-csv
  std::string csv, branches_csv, events_csv, output;
  std::string command_line;
};
int orbits_command(const OrbitsArgs& args);

}  // namespace ajx::app

namespace ajx::app {

// astrojax bench work-precision: scenes (run files) x methods x tolerances or steps -> CSV.
struct WorkPrecisionArgs {
  std::vector<std::string> scenes;     // run files (sweeps/scenes/*.toml)
  std::vector<std::string> overrides;  // applied to every scene
  std::string output = "out/work_precision.csv";
  double horizon = 10.0;               // error measured at t0 + horizon [s]
  std::vector<std::string> methods{"euler", "rk4", "dopri5", "dop853"};
  std::vector<double> rtols{1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12};
  std::vector<double> steps{4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4, 6.25e-5};
  int repeats = 5;                     // timed runs per point (median kept)
  double cpu_budget = 2.0;             // stop repeating a point after this much CPU [s]
};
int bench_work_precision_command(const WorkPrecisionArgs& args);

}  // namespace ajx::app

namespace ajx::app {

// astrojax bench stability: the largest acceptable fixed step against ω_m held -> CSV.
struct StabilityArgs {
  std::string scene;                   // a run file; its schedule is replaced by each held ω_m
  std::vector<std::string> overrides;
  std::string output = "out/stability.csv";
  double horizon = 20.0;               // [s]
  std::vector<std::string> methods{"euler", "rk4"};
  std::vector<double> omegas_pi{2, 4, 6, 8, 10, 12, 14};  // ω_m / π
  double h_max = 0.1, h_min = 2e-6;    // scanned steps [s]
  double energy_tol = 1e-2;            // acceptable |energy residual|
};
int bench_stability_command(const StabilityArgs& args);

}  // namespace ajx::app

namespace ajx::app {

// astrojax bench friction: event-driven stick-slip against tanh(ṡ/ε) as ε -> 0 -> CSV.
struct FrictionArgs {
  std::string scene;                   // a run file with layers.friction = "stick_slip"
  std::vector<std::string> overrides;
  std::string output = "out/friction.csv";
  double horizon = 10.0;               // [s]
  std::vector<double> eps{1e-1, 1e-2, 1e-3, 1e-4, 1e-5};  // ε [m/s]
  std::vector<std::string> laws{"regularised", "stribeck"};  // the regularised layers compared
  double rtol = 1e-8;                  // of dopri5 and dop853
  std::vector<double> rk4_steps{1e-3, 1e-4};
  std::vector<double> radau_steps{2e-3, 5e-4};
  long max_steps = 5'000'000;          // a run needing more is reported as too costly
  int repeats = 3;
};
int bench_friction_command(const FrictionArgs& args);

}  // namespace ajx::app

namespace ajx::app {

// astrojax bench constraints: none / Baumgarte / projection on a one-mode scene -> CSV.
struct ConstraintsArgs {
  std::string scene;
  std::vector<std::string> overrides;
  std::string output = "out/constraints.csv";
  double horizon = 100.0;  // [s]
  std::vector<double> alphas{1, 10, 100, 1000};  // Baumgarte gains α [1/s]
  std::vector<std::string> settings{"euler@5e-4", "rk4@5e-4", "dopri5@1e-6", "dop853@1e-9"};
  int repeats = 3;
};
int bench_constraints_command(const ConstraintsArgs& args);

}  // namespace ajx::app

namespace ajx::app {

// astrojax bench threshold: ω_fall from a short ramp, per method and tolerance -> CSV.
int bench_threshold_command(const WorkPrecisionArgs& args, double sample_dt);

}  // namespace ajx::app

namespace ajx::app {

// astrojax keys: the configuration reference, plain or as Markdown.
int keys_command(bool markdown);

}  // namespace ajx::app
