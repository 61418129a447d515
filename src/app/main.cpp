// astrojax: the driven-Astrojax explorer. Subcommands: run (one trajectory into HDF5) and
// sweep (the MPI farm over a sweep file's chains).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fmt/format.h>

#include "app/commands.hpp"
#include "config/did_you_mean.hpp"
#include "parallel/mpi_env.hpp"
#include "config/config.hpp"
#include "results/basin_file.hpp"
#include "results/provenance.hpp"

namespace {

// Every floating-point option of `app` and its subcommands refuses NaN and infinity (CLI11
// converts "nan" and "inf", and its ranges let NaN through).
void require_finite(CLI::App& app) {
  static const CLI::Validator finite(
      [](std::string& s) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(s.c_str(), &end);
        return end != s.c_str() && !std::isfinite(v) ? fmt::format("{} is not a finite number", s) : std::string();
      },
      "", "FINITE");
  for (CLI::Option* o : app.get_options())
    if (o->get_type_name().rfind("FLOAT", 0) == 0) o->check(finite);
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) require_finite(*sub);
}

const CLI::Validator non_empty([](std::string& s) { return s.empty() ? std::string("the output path is empty") : std::string(); },
                               "", "NONEMPTY");

// A command run with MPI started: an MPI or I/O failure on one rank leaves the others unable to
// go on, so the whole job ends.
template <class Command>
int on_mpi(int& argc, char**& argv, Command command) {
  ajx::parallel::MpiEnvironment mpi(argc, argv);
  try {
    return command();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error on rank %d: %s\n", mpi.rank(), e.what());
    if (mpi.size() > 1) mpi.abort(1);
    return 1;
  }
}

}  // namespace

// Long for a reason: the command line's declaration, one CLI11 block per subcommand, read top to
// bottom as the reference of every option; the commands themselves are in src/app/*_command.cpp.
int main(int argc, char** argv) {
  ajx::config::set_stored_orbit_reader(&ajx::results::read_stored_orbit);  // basin.state reads sweep files
  CLI::App app{"astrojax: bifurcation explorer for the motor-driven Astrojax pendulum"};
  app.require_subcommand(1);
  app.footer("Exit codes (also of mpirun, which returns rank 0's): 0 done; 1 internal error (a bug, an MPI failure); "
             "2 bad input, refused before any work, nothing written; 3 done, but some integrations or tasks failed "
             "(marked in the file); 4 interrupted, resumable with --resume; 5 the output could not be written while "
             "running (disk full, file too large), resumable with --resume once the cause is fixed. mpirun itself sent "
             "SIGTERM or SIGINT (Ctrl-C) returns 1 whatever the ranks return; the sweep's .part and journal are "
             "resumable (stop with SIGUSR1 to get 4). See docs/reference/exit-codes.md.");
  std::string command_line;
  for (int i = 0; i < argc; ++i) command_line += (i ? " " : "") + std::string(argv[i]);

  ajx::app::RunArgs run;
  run.command_line = command_line;
  CLI::App* run_cmd = app.add_subcommand(
      "run", "Integrate one trajectory from a TOML file (sweeps/*.toml) and write it to HDF5");
  run_cmd->add_option("config", run.config_path, "TOML file with [model], [layers], [integrator], [initial], [[schedule]], [output]")
      ->required();
  run_cmd->add_option("-s,--set", run.overrides, "Override a key, e.g. --set model.drive_radius=0.005 (repeatable)");
  run_cmd->add_option("-o,--output", run.output, "HDF5 output path (overrides output.path)")->check(non_empty);
  run_cmd->add_flag("-q,--quiet", run.quiet, "No progress or notes: only the one-line result and errors");
  run_cmd->add_flag("--force", run.force, "Replace an existing output file");
  run_cmd->add_option("--max-memory", run.max_memory,
                      "Memory the run may plan for [MB]; a run whose samples need more is refused before it starts "
                      "(default: half the machine's memory)")
      ->check(CLI::NonNegativeNumber);

  ajx::app::SweepArgs sweep;
  sweep.command_line = command_line;
  CLI::App* sweep_cmd = app.add_subcommand(
      "sweep", "Run a sweep file (sweeps/*.toml) on all MPI ranks: mpirun -n N astrojax sweep FILE");
  sweep_cmd->add_option("config", sweep.config_path, "TOML file with [protocol], [grid] and the [model] sections")
      ->required();
  sweep_cmd->add_option("-s,--set", sweep.overrides, "Override a key, e.g. --set grid.drive_radius=[0.005,0.01]");
  sweep_cmd->add_option("-o,--output", sweep.output, "HDF5 output path (overrides output.path)")->check(non_empty);
  sweep_cmd->add_flag("-q,--quiet", sweep.quiet, "No progress or notes: only the one-line result and errors");
  sweep_cmd->add_flag("--resume", sweep.resume,
                      "Continue an interrupted sweep from <output>.part (same file and overrides)");
  sweep_cmd->add_flag("--dry-run", sweep.dry_run,
                      "Check the file and print the plan (chains, tasks, simulated seconds, a CPU estimate); run nothing");
  sweep_cmd->add_flag("--force", sweep.force,
                      "Replace an existing <output>, or start afresh where an interrupted sweep left "
                      "<output>.part or <output>.journal (their finished tasks are discarded)");
  sweep_cmd->add_option("--max-tasks", sweep.max_tasks,
                        "Stop after this many task results, as an interruption would (resume later with --resume)")
      ->check(CLI::NonNegativeNumber);
  sweep_cmd->add_option("--task-timeout", sweep.task_timeout,
                        "Wall-clock bound of one task [s]: a task not back within it is handed to another rank, its "
                        "rank given up (after 3 such timeouts the task fails), and the job ended once the rest is "
                        "done (default 0: automatic, 20 times the slowest finished task, at least --min-task-timeout)")
      ->check(CLI::Range(0.0, 1e7));
  sweep_cmd->add_option("--max-memory", sweep.max_memory,
                        "Memory one rank may plan for [MB]; a sweep whose tasks or plan need more is refused before it "
                        "starts (default: half the machine's memory)")
      ->check(CLI::NonNegativeNumber);
  sweep_cmd->add_option("--threads", sweep.threads,
                        "Threads of rank 0 that integrate tasks beside the master: with mpirun, 1 (default: every rank "
                        "computes) or 0 (rank 0 only hands out and writes); in one process (as root, or without MPI), "
                        "the number of cores to use, e.g. --threads 2. The file does not depend on it")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  sweep_cmd->add_option("--min-task-timeout", sweep.min_task_timeout,
                        "The least automatic task bound [s] (see --task-timeout)")
      ->check(CLI::Range(0.1, 1e7))
      ->capture_default_str();

  ajx::app::VerifyArgs verify;
  CLI::App* verify_cmd = app.add_subcommand(
      "verify", "Check a sweep's file, finished or .part, against its own sweep file and its journal; report damage "
                "(exit 0 intact, 2 damaged)");
  verify_cmd->add_option("file", verify.input, "HDF5 file written by astrojax sweep, or its .part")->required();

  ajx::app::ReplayArgs replay;
  replay.command_line = command_line;
  CLI::App* replay_cmd = app.add_subcommand(
      "replay", "Re-run one window of a sweep file from its stored start state with the file's own model, variant and "
                "integrator; check it reproduces the stored class and ω_ball; write dense samples to a run file");
  replay_cmd->add_option("file", replay.input, "HDF5 file written by astrojax sweep")->required();
  replay_cmd->add_option("--chain", replay.chain, "Chain index (astrojax thresholds and the report name them)")->required();
  replay_cmd->add_option("--window", replay.window, "Window index within the chain")->required();
  replay_cmd->add_option("-o,--output", replay.output, "Run file (HDF5) to write")->required()->check(non_empty);
  replay_cmd->add_option("--sample-rate", replay.sample_rate, "Dense samples per second in the run file [1/s]")
      ->check(CLI::Range(1.0, 1e4))
      ->capture_default_str();
  replay_cmd->add_option("--before", replay.before,
                         "Also sample this many seconds before the window (within its task) [s]")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  replay_cmd->add_flag("--force", replay.force, "Replace an existing output file");
  replay_cmd->add_flag("-q,--quiet", replay.quiet, "No notes: only the result and errors");

  ajx::app::WindowsArgs windows;
  CLI::App* windows_cmd = app.add_subcommand(
      "windows", "Every computed window of a sweep file as a CSV row: its ω_m, class, ω_ball, confidence and the "
                 "classifier's reason (classified again from the stored samples)");
  windows_cmd->add_option("file", windows.input, "HDF5 file written by astrojax sweep")->required();
  windows_cmd->add_option("-o,--output", windows.output, "CSV to write, - for stdout")->required()->check(non_empty);
  windows_cmd->add_flag("--force", windows.force, "Replace an existing output file");

  bool keys_markdown = false;
  CLI::App* keys_cmd = app.add_subcommand(
      "keys", "List every configuration key with its type, unit, allowed values, default and meaning (the "
              "configuration reference, made from the parameter table and the key catalogue the reader uses)");
  keys_cmd->add_flag("--markdown", keys_markdown, "Markdown tables, one per section (the docs' reference page)");

  ajx::app::ThresholdsArgs thresholds;
  CLI::App* thresholds_cmd = app.add_subcommand(
      "thresholds", "ω_rise, ω_fall, ω1, ω2 per model variant: brackets with their widths and hold verdicts, "
                    "next to the paper's values; ω2 also as the lag's Hopf point where held levels allow");
  thresholds_cmd->add_option("file", thresholds.input, "HDF5 file written by astrojax sweep")->required();
  thresholds_cmd->add_option("--csv", thresholds.csv, "Also write the table as CSV");
  thresholds_cmd->add_option("--markdown", thresholds.markdown, "Also write the report as Markdown");
  thresholds_cmd->add_option("--refine", thresholds.refine,
                             "Re-run each bracket from the stored state before it, this many times slower "
                             "(ramps: rate/F; staircases: F times more levels)")
      ->check(CLI::Range(1, 1000));
  thresholds_cmd->add_option("-j,--jobs", thresholds.jobs,
                             "Threads of rank 0 that run the holds and --refine: in one process, the cores to use; "
                             "with mpirun (every rank takes holds and refinements as farm tasks), those beside the "
                             "master. The report does not depend on it")
      ->check(CLI::Range(1, 1024))
      ->default_str("the number of cores in one process, 1 with mpirun");
  thresholds_cmd->add_option("--hold", thresholds.hold,
                             "Hold ω_m at both sides of each bracket for T (seconds, or e.g. 5tau: drag times "
                             "max(m1,m2)/c_D) and judge: bifurcation, excursion or time-limited transient")
      ->expected(0, 1)
      ->default_str("5tau");
  thresholds_cmd->add_flag("--no-hold", thresholds.no_hold, "Brackets only: no holds, no verdicts (fast)");
  thresholds_cmd->add_option("--onset-span", thresholds.onset_span,
                             "The Hopf fit of ω2 takes held levels up to this far above the first flower [π rad/s]")
      ->check(CLI::Range(0.1, 100.0))
      ->capture_default_str();
  thresholds_cmd->add_flag("--sequence", thresholds.sequence,
                           "Print each chain's orbit class sequence and compare it with the paper's");
  thresholds_cmd->add_option("--sequence-csv", thresholds.sequence_csv, "Also write the class sequence as CSV");
  thresholds_cmd->add_flag("--absorb-blips", thresholds.absorb_blips,
                           "In the sequence, absorb one not-settled window between two of the same class");
  thresholds_cmd->add_option("-s,--set", thresholds.settings,
                             "A classifier setting, e.g. --set classifier.locked_tol=0.05: the windows are "
                             "classified again in memory from their samples first (the file is not changed)");

  ajx::app::ClassifyArgs classify;
  CLI::App* classify_cmd = app.add_subcommand(
      "classify", "Classify every window of a sweep file again from its stored samples (no integration)");
  classify_cmd->add_option("file", classify.input, "HDF5 file written by astrojax sweep")->required();
  classify_cmd->add_option("-o,--output", classify.output, "Write the reclassified file here (a copy of the input)");
  classify_cmd->add_flag("--force", classify.force,
                         "Without -o: rewrite the input in place; with -o: replace an existing output");
  classify_cmd->add_option("-s,--set", classify.settings,
                           "A classifier setting, e.g. --set classifier.locked_tol=0.05 (astrojax keys lists them)");

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
  orbits_cmd->add_flag("--lag", orbits.lag,
                       "The lagging orbits of the slipping tie (layers.tie = clutch) with the bead stuck at each --s: "
                       "at each --omega, and their Hopf point and cone limits along the branch (over --range in ω_ball)");
  orbits_cmd->add_option("--map", orbits.map_parameter,
                         "Follow the threshold curves (fold, cone exits, the lag's Hopf point) of the bead stuck at "
                         "each --s in the plane of ω_m and this parameter: drive_radius, mass, s, ...");
  orbits_cmd->add_option("--curves", orbits.map_curves, "With --map: fold, cone_up, cone_down, hopf (default: all)")
      ->delimiter(',');
  orbits_cmd->add_option("--curves-csv", orbits.curves_csv, "With --map: write the curves and their codimension-2 points as CSV");
  orbits_cmd->add_option("--csv", orbits.csv, "Write every orbit found as CSV");
  orbits_cmd->add_option("--branches-csv", orbits.branches_csv, "Write the continuation's points as CSV");
  orbits_cmd->add_option("--events-csv", orbits.events_csv, "Write the continuation's events as CSV");
  orbits_cmd->add_option("-o,--output", orbits.output, "Write everything to this HDF5 file");
  ajx::app::WorkPrecisionArgs wp;
  CLI::App* bench_cmd = app.add_subcommand("bench", "Accuracy against speed: work-precision diagrams");
  bench_cmd->require_subcommand(1);
  CLI::App* wp_cmd = bench_cmd->add_subcommand(
      "work-precision", "Each method over tolerances / steps on each scene: CPU time, achieved error, drift, energy -> CSV");
  wp_cmd->add_option("scenes", wp.scenes, "Run files (sweeps/scenes/*.toml)")->required();
  wp_cmd->add_option("-o,--output", wp.output, "CSV output path")->capture_default_str();
  wp_cmd->add_option("-s,--set", wp.overrides, "Override a key in every scene (repeatable)");
  wp_cmd->add_option("--horizon", wp.horizon, "Error measured at this time [s]")->capture_default_str();
  wp_cmd->add_option("--methods", wp.methods, "Methods")->delimiter(',')->capture_default_str();
  wp_cmd->add_option("--rtols", wp.rtols, "Relative tolerances of the adaptive methods (atol = 1e-3 rtol)")
      ->delimiter(',');
  wp_cmd->add_option("--steps", wp.steps, "Steps of the fixed-step methods [s]")->delimiter(',');
  wp_cmd->add_option("--repeats", wp.repeats, "Timed runs per point (the median is kept)")->capture_default_str();
  wp_cmd->add_option("--budget", wp.cpu_budget, "Stop repeating a point after this much CPU [s]")
      ->capture_default_str();

  ajx::app::StabilityArgs st;
  CLI::App* st_cmd = bench_cmd->add_subcommand(
      "stability", "Largest acceptable step of each fixed-step method against ω_m held, and explicit Euler at the paper's step 1/2000 s -> CSV");
  st_cmd->add_option("scene", st.scene, "Run file (its schedule is replaced by each held ω_m)")->required();
  st_cmd->add_option("-o,--output", st.output, "CSV output path")->capture_default_str();
  st_cmd->add_option("-s,--set", st.overrides, "Override a key of the scene (repeatable)");
  st_cmd->add_option("--horizon", st.horizon, "Run length [s]")->capture_default_str();
  st_cmd->add_option("--methods", st.methods, "Fixed-step methods")->delimiter(',')->capture_default_str();
  st_cmd->add_option("--omegas-pi", st.omegas_pi, "Held ω_m in units of π rad/s")->delimiter(',');
  st_cmd->add_option("--h-max", st.h_max, "Largest step scanned [s]")->capture_default_str();
  st_cmd->add_option("--h-min", st.h_min, "Smallest step scanned [s]")->capture_default_str();
  st_cmd->add_option("--energy-tol", st.energy_tol, "Acceptable |energy-balance residual|")->capture_default_str();

  ajx::app::FrictionArgs fr;
  CLI::App* fr_cmd = bench_cmd->add_subcommand(
      "friction", "Event-driven stick-slip against the regularised laws (tanh(ṡ/ε), Stribeck) as ε -> 0: creep error "
      "and cost, explicit and implicit -> CSV");
  fr_cmd->add_option("scene", fr.scene, "Run file with layers.friction = \"stick_slip\"")->required();
  fr_cmd->add_option("-o,--output", fr.output, "CSV output path")->capture_default_str();
  fr_cmd->add_option("-s,--set", fr.overrides, "Override a key of the scene (repeatable)");
  fr_cmd->add_option("--horizon", fr.horizon, "Run length [s]")->capture_default_str();
  fr_cmd->add_option("--eps", fr.eps, "ε values [m/s]")->delimiter(',');
  fr_cmd->add_option("--laws", fr.laws,
                     "Regularised layers: regularised (tanh, saturates at μ_k), stribeck (peak μ_s, decays to μ_k "
                     "over layers.stribeck_speed; ε >= v_s is skipped)")
      ->delimiter(',');
  fr_cmd->add_option("--rtol", fr.rtol, "rtol of dopri5 and dop853")->capture_default_str();
  fr_cmd->add_option("--rk4-steps", fr.rk4_steps, "Steps of RK4 [s]")->delimiter(',');
  fr_cmd->add_option("--radau-steps", fr.radau_steps, "Steps of Radau IIA [s]")->delimiter(',');
  fr_cmd->add_option("--max-steps", fr.max_steps, "Steps after which a run counts as too costly")->capture_default_str();
  fr_cmd->add_option("--repeats", fr.repeats, "Timed runs per point (median kept)")->capture_default_str();

  ajx::app::ConstraintsArgs cs;
  CLI::App* cs_cmd = bench_cmd->add_subcommand(
      "constraints", "Constraint handling on a one-mode scene: none, Baumgarte gains, projection (drift, cost) -> CSV");
  cs_cmd->add_option("scene", cs.scene, "Run file whose reference stays in one contact mode")->required();
  cs_cmd->add_option("-o,--output", cs.output, "CSV output path")->capture_default_str();
  cs_cmd->add_option("-s,--set", cs.overrides, "Override a key of the scene (repeatable)");
  cs_cmd->add_option("--horizon", cs.horizon, "Run length [s]")->capture_default_str();
  cs_cmd->add_option("--alphas", cs.alphas, "Baumgarte gains α [1/s]")->delimiter(',');
  cs_cmd->add_option("--runs", cs.settings, "method@rtol or method@step")->delimiter(',')->capture_default_str();
  cs_cmd->add_option("--repeats", cs.repeats, "Timed runs per point (median kept)")->capture_default_str();

  ajx::app::WorkPrecisionArgs th;
  th.output = "out/threshold.csv";
  th.horizon = 40.0;
  double th_sample = 1e-3;
  CLI::App* th_cmd = bench_cmd->add_subcommand(
      "threshold", "ω_fall (the bead's first landing on a ramp down) or ω1 (the lock lost on a ramp up) per method and "
                   "tolerance, against a reference -> CSV");
  th_cmd->add_option("scenes", th.scenes, "Run files with a ramp down (sweeps/scenes/fall_ramp.toml) or up (lock_loss_ramp.toml)")->required();
  th_cmd->add_option("-o,--output", th.output, "CSV output path")->capture_default_str();
  th_cmd->add_option("-s,--set", th.overrides, "Override a key in every scene (repeatable)");
  th_cmd->add_option("--horizon", th.horizon, "Run length [s]")->capture_default_str();
  th_cmd->add_option("--methods", th.methods, "Methods")->delimiter(',')->capture_default_str();
  th_cmd->add_option("--rtols", th.rtols, "Relative tolerances of the adaptive methods (atol = 1e-3 rtol)")
      ->delimiter(',');
  th_cmd->add_option("--steps", th.steps, "Steps of the fixed-step methods [s]")->delimiter(',');
  th_cmd->add_option("--repeats", th.repeats, "Timed runs per point (the median is kept)")->capture_default_str();
  th_cmd->add_option("--sample", th_sample, "Sampling step that brackets the landing [s]")->capture_default_str();

  require_finite(app);
  app.set_version_flag("--version", fmt::format("astrojax {} (git commit {}; {})", ajx::results::program_version(),
                                                  ajx::results::program_commit(), ajx::results::program_commit_origin()));
  // A mistyped command or option: name the nearest one, as git and cargo do.
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
  if (argc > 1 && argv[1][0] != '-' && std::find(names.begin(), names.end(), argv[1]) == names.end()) {
    const std::string near = ajx::config::closest(argv[1], names);
    std::fprintf(stderr, "error: '%s' is not an astrojax command%s; the commands: %s (astrojax --help)\n", argv[1],
                 near.empty() ? "" : fmt::format(" (did you mean '{}'?)", near).c_str(),
                 fmt::format("{}", fmt::join(names, ", ")).c_str());
    return ajx::app::kExitBadInput;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ExtrasError& e) {
    const int code = app.exit(e);
    for (const CLI::App* sub : app.get_subcommands()) {  // the command that was given
      std::vector<std::string> options;
      for (const CLI::Option* o : sub->get_options())
        for (const std::string& n : o->get_lnames()) options.push_back("--" + n);
      for (int i = 2; i < argc; ++i)
        if (argv[i][0] == '-' && argv[i][1] == '-')
          if (const std::string near = ajx::config::closest(std::string(argv[i]).substr(0, std::string(argv[i]).find('=')), options);
              !near.empty() && near != argv[i])
            std::fprintf(stderr, "did you mean '%s' for '%s'? (astrojax %s --help)\n", near.c_str(), argv[i],
                         sub->get_name().c_str());
    }
    return code == 0 ? 0 : ajx::app::kExitBadInput;
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : ajx::app::kExitBadInput;
  }
  if (*keys_cmd) return ajx::app::keys_command(keys_markdown);
  if (*run_cmd) return ajx::app::run_command(run);
  if (*verify_cmd) return ajx::app::verify_command(verify);
  if (*replay_cmd) return ajx::app::replay_command(replay);
  if (*windows_cmd) return ajx::app::windows_command(windows);
  if (*thresholds_cmd) {
    // The holds and refinements run on the farm; without them MPI is needed only to keep the
    // ranks of an mpirun from each printing the report.
    if (!ajx::app::thresholds_integrate(thresholds) && !ajx::parallel::launched_as_rank())
      return ajx::app::thresholds_command(thresholds);
    return on_mpi(argc, argv, [&] { return ajx::app::thresholds_command(thresholds); });
  }
  if (*classify_cmd) return ajx::app::classify_command(classify);
  if (*orbits_cmd) return ajx::app::orbits_command(orbits);
  if (*wp_cmd) return ajx::app::bench_work_precision_command(wp);
  if (*st_cmd) return ajx::app::bench_stability_command(st);
  if (*fr_cmd) return ajx::app::bench_friction_command(fr);
  if (*cs_cmd) return ajx::app::bench_constraints_command(cs);
  if (*th_cmd) return ajx::app::bench_threshold_command(th, th_sample);
  if (*sweep_cmd) return on_mpi(argc, argv, [&] { return ajx::app::sweep_command(sweep); });
  return 0;
}
