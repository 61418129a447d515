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
  sweep_cmd->add_option("--task-timeout", sweep.task_timeout,
                        "Wall-clock bound of one task [s]: a task not back within it is reported failed, its rank "
                        "given up, and the job ended once the rest is done (default 0: no bound)")
      ->check(CLI::NonNegativeNumber);

  ajx::app::ThresholdsArgs thresholds;
  CLI::App* thresholds_cmd = app.add_subcommand(
      "thresholds", "ω_rise, ω_fall, ω1, ω2 of every chain of a sweep file, as brackets next to the paper's values");
  thresholds_cmd->add_option("file", thresholds.input, "HDF5 file written by astrojax sweep")->required();
  thresholds_cmd->add_option("--csv", thresholds.csv, "Also write the table as CSV");

  ajx::app::ClassifyArgs classify;
  CLI::App* classify_cmd = app.add_subcommand(
      "classify", "Classify every window of a sweep file again from its stored samples (no integration)");
  classify_cmd->add_option("file", classify.input, "HDF5 file written by astrojax sweep (rewritten in place)")
      ->required();
  classify_cmd->add_option("-s,--set", classify.settings,
                           "A classifier setting, e.g. --set locked_tol=0.05 (see src/sweep/orbit_classifier.hpp)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : ajx::app::kExitBadInput;
  }
  if (*run_cmd) return ajx::app::run_command(run);
  if (*thresholds_cmd) return ajx::app::thresholds_command(thresholds);
  if (*classify_cmd) return ajx::app::classify_command(classify);
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
