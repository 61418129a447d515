// astrojax: the driven-Astrojax explorer. Subcommands: run (one trajectory into HDF5) and
// sweep (the MPI farm over a sweep file's chains).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <fmt/format.h>

#include "app/commands.hpp"
#include "parallel/mpi_env.hpp"

int main(int argc, char** argv) {
  CLI::App app{"astrojax: bifurcation explorer for the motor-driven Astrojax pendulum"};
  app.require_subcommand(1);
  std::string command_line;
  for (int i = 0; i < argc; ++i) command_line += (i ? " " : "") + std::string(argv[i]);

  ajx::app::RunArgs run;
  run.command_line = command_line;
  CLI::App* run_cmd = app.add_subcommand(
      "run", "Integrate one trajectory from a TOML file (sweeps/*.toml) and write it to HDF5");
  run_cmd->add_option("config", run.config_path, "TOML file with [model], [layers], [integrator], [initial], [[schedule]], [output]")
      ->required();
  run_cmd->add_option("-s,--set", run.overrides, "Override a key, e.g. --set model.drive_radius=0.005 (repeatable)");
  run_cmd->add_option("-o,--output", run.output, "HDF5 output path (overrides output.path)");
  run_cmd->add_flag("-q,--quiet", run.quiet, "Print only errors");

  ajx::app::SweepArgs sweep;
  sweep.command_line = command_line;
  CLI::App* sweep_cmd = app.add_subcommand(
      "sweep", "Run a sweep file (sweeps/*.toml) on all MPI ranks: mpirun -n N astrojax sweep FILE");
  sweep_cmd->add_option("config", sweep.config_path, "TOML file with [protocol], [grid] and the [model] sections")
      ->required();
  sweep_cmd->add_option("-s,--set", sweep.overrides, "Override a key, e.g. --set grid.drive_radius=[0.005,0.01]");
  sweep_cmd->add_option("-o,--output", sweep.output, "HDF5 output path (overrides output.path)");
  sweep_cmd->add_flag("-q,--quiet", sweep.quiet, "No progress lines");
  sweep_cmd->add_flag("--resume", sweep.resume,
                      "Continue an interrupted sweep from <output>.part (same file and overrides)");
  sweep_cmd->add_option("--max-tasks", sweep.max_tasks,
                        "Stop after this many task results, as an interruption would (resume later with --resume)")
      ->check(CLI::NonNegativeNumber);

  ajx::app::ThresholdsArgs thresholds;
  CLI::App* thresholds_cmd = app.add_subcommand(
      "thresholds", "ω_rise, ω_fall, ω1, ω2 of every chain of a sweep file, as brackets next to the paper's values");
  thresholds_cmd->add_option("file", thresholds.input, "HDF5 file written by astrojax sweep")->required();
  thresholds_cmd->add_option("--csv", thresholds.csv, "Also write the table as CSV");
  thresholds_cmd->add_option("--refine", thresholds.refine,
                             "Re-run each bracket from the stored state before it, this many times slower "
                             "(ramps: rate/F; staircases: F times more levels)")
      ->check(CLI::Range(1, 1000));
  thresholds_cmd->add_option("-j,--jobs", thresholds.jobs, "Threads for --refine")->check(CLI::Range(1, 1024));

  ajx::app::ClassifyArgs classify;
  CLI::App* classify_cmd = app.add_subcommand(
      "classify", "Classify every window of a sweep file again from its stored samples (no integration)");
  classify_cmd->add_option("file", classify.input, "HDF5 file written by astrojax sweep (rewritten in place)")
      ->required();
  classify_cmd->add_option("-s,--set", classify.settings,
                           "A classifier setting, e.g. --set locked_tol=0.05 (see src/sweep/orbit_classifier.hpp)");

  ajx::app::OrbitsArgs orbits;
  orbits.command_line = command_line;
  CLI::App* orbits_cmd = app.add_subcommand(
      "orbits", "Locked circular orbits as equilibria of the co-rotating frame: all of them at given ω_m, "
                "continued in a parameter, and the thresholds they predict");
  orbits_cmd->add_option("config", orbits.config_path, "TOML file: [model], [layers] and an optional [orbits] table")
      ->required();
  orbits_cmd->add_option("-s,--set", orbits.overrides, "Override a key, e.g. --set model.drive_radius=0.005");
  orbits_cmd->add_option("-w,--omega", orbits.omega, "ω_m in rad/s, or a multiple of π like 4.7pi (repeatable)");
  orbits_cmd->add_option("--s", orbits.s, "Continue the stuck orbits with the bead at this s [m] (repeatable)");
  orbits_cmd->add_option("--continue", orbits.parameter, "Continue in this parameter: omega, s, drive_radius, ...");
  orbits_cmd->add_option("--range", orbits.range, "Continuation interval LO HI")->expected(2);
  orbits_cmd->add_option("--s-points", orbits.s_points, "Bead positions sampled along the string")->check(CLI::Range(2, 10000));
  orbits_cmd->add_flag("--all", orbits.all, "Print every stuck orbit, not only the summary of the family");
  orbits_cmd->add_flag("--thresholds", orbits.thresholds, "Predict ω_rise, ω_fall and ω1 from the branches");
  orbits_cmd->add_option("--threshold-s-points", orbits.threshold_s_points, "Bead positions for --thresholds")
      ->check(CLI::Range(2, 1000));
  orbits_cmd->add_option("--compare", orbits.compare,
                         "Predict the thresholds and show the brackets of this sweep's chains that have the same model");
  orbits_cmd->add_option("--csv", orbits.csv, "Write every orbit found as CSV");
  orbits_cmd->add_option("--branches-csv", orbits.branches_csv, "Write the continuation's points as CSV");
  orbits_cmd->add_option("--events-csv", orbits.events_csv, "Write the continuation's events as CSV");
  orbits_cmd->add_option("-o,--output", orbits.output, "Write everything to this HDF5 file");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : ajx::app::kExitBadInput;
  }
  if (*run_cmd) return ajx::app::run_command(run);
  if (*thresholds_cmd) return ajx::app::thresholds_command(thresholds);
  if (*classify_cmd) return ajx::app::classify_command(classify);
  if (*orbits_cmd) return ajx::app::orbits_command(orbits);
  if (*sweep_cmd) {
    ajx::parallel::MpiEnvironment mpi(argc, argv);
    try {
      return ajx::app::sweep_command(sweep);
    } catch (const std::exception& e) {
      // An MPI or I/O failure on one rank: the others cannot go on, so the whole job ends.
      std::fprintf(stderr, "error on rank %d: %s\n", mpi.rank(), e.what());
      if (mpi.size() > 1) mpi.abort(1);
      return 1;
    }
  }
  return 0;
}
