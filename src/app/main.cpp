// astrojax: the driven-Astrojax explorer. Subcommands: run (one trajectory into HDF5).
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "app/commands.hpp"

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

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : ajx::app::kExitBadInput;
  }
  if (*run_cmd) return ajx::app::run_command(run);
  return 0;
}
