// astrojax run: one trajectory, sampled on a fixed grid, into HDF5 with units as attributes
// and the configuration stored verbatim.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <numbers>
#include <optional>
#include <vector>

#include "app/commands.hpp"
#include "app/output_paths.hpp"
#include "results/resource_budget.hpp"
#include "results/run_file.hpp"
#include "config/config.hpp"
#include "physics/energy.hpp"
#include "sim/paper_scheme.hpp"
#include "sim/simulation.hpp"
#include "sim/table1_starts.hpp"

namespace ajx::app {

namespace {

using physics::idx::dim;

// The two positions a two-step start gives: Table 1's pair, the explicit pair, or an explicit
// state's r and r + h v (h = integrator.step).
sim::PairStart pair_start(const config::RunConfig& c, const physics::MotorSchedule& schedule) {
  const double h = c.run.integ.h_fixed;
  if (c.initial.preset == "table1")
    return sim::table1_pair(c.initial.orbit,
                            std::isnan(c.initial.orbit_omega) ? schedule.top(0.0).omega
                                                              : c.initial.orbit_omega,
                            h);
  sim::PairStart p;
  p.r1_0 = c.initial.r1;
  p.r2_0 = c.initial.r2;
  p.r1_1 = c.initial.preset == "pair" ? c.initial.r1_next : physics::Vec3(c.initial.r1 + h * c.initial.v1);
  p.r2_1 = c.initial.preset == "pair" ? c.initial.r2_next : physics::Vec3(c.initial.r2 + h * c.initial.v2);
  return p;
}

physics::State initial_state(const config::RunConfig& c, const physics::MotorSchedule& schedule) {
  if (c.initial.preset == "hanging") return sim::hanging_at_rest(c.model, schedule);
  if (c.initial.preset == "table1" || c.initial.preset == "pair")
    return sim::state_from_pair(c.model, schedule, pair_start(c, schedule), c.run.integ.h_fixed,
                                c.initial.length_tolerance);
  return sim::explicit_state(c.model, schedule, c.initial.r1, c.initial.r2, c.initial.v1, c.initial.v2,
                             c.initial.mode, 0.0, c.initial.length_tolerance, c.initial.tie_slip_rate);
}

// The samples of a run, held in memory until it ends and then written uncompressed: refused
// before any work when they cannot fit (Trajectory's 29 doubles and one int a sample; its
// vectors grow by doubling, so up to 3 times that while one is reallocated).
void check_run_size(const config::RunConfig& cfg, double duration, double max_memory_mb) {
  constexpr double kBytesPerSample = results::Trajectory::kBytesPerSample;
  const double samples = std::floor(duration / cfg.output.sample_interval) + 2;
  const std::string what = fmt::format("{:.4g} samples ({:.6g} s every {:.3g} s)", samples, duration,
                                       cfg.output.sample_interval);
  results::check_memory(cfg.source_name, "output.sample_interval", what, 3 * kBytesPerSample * samples,
               results::memory_budget(max_memory_mb), max_memory_mb);
  const double need = kBytesPerSample * samples, free = results::free_bytes_for(cfg.output.path);
  if (need > free)
    throw config::ConfigError(fmt::format("{}: key 'output.path': {} make {:.4g} MB of output, but only {:.4g} MB are "
                                          "free there", cfg.source_name, what, need / 1e6, free / 1e6));
}

}  // namespace

int run_command(const RunArgs& args) {
  config::RunConfig cfg;
  physics::MotorSchedule schedule;
  physics::State state;
  std::optional<results::RunFile> file;
  std::optional<sim::PaperDrag> paper;  // the paper's two-step scheme (sim/paper_scheme.hpp)
  sim::PairStart pair;
  double start_projection = 0.0;        // |L1 + L2 - l| of the pair before projection [m]
  // Everything that can be checked is checked before any work, and before any file exists.
  try {
    cfg = config::load_run_config(args.config_path, args.overrides);
    if (!args.output.empty()) cfg.output.path = args.output;
    check_output_path(cfg.source_name, "output.path", cfg.output.path,
                      {args.config_path}, {".part"});
    check_not_overwriting(cfg.source_name, "output.path", cfg.output.path, args.force);
    paper = sim::paper_variant(cfg.run.method);
    schedule = physics::MotorSchedule(cfg.model.p.drive_radius, cfg.schedule);
    check_run_size(cfg, schedule.duration(), args.max_memory);
    try {
      if (paper) {
        pair = pair_start(cfg, schedule);
        start_projection = sim::project_pair(cfg.model, schedule, cfg.run.integ.h_fixed, pair);
      } else {
        state = initial_state(cfg, schedule);
      }
    } catch (const std::invalid_argument& e) {
      throw config::ConfigError(fmt::format("{}: key 'initial.r1', 'initial.r2': {}; allowed "
                                            "|L1 + L2 - l| <= initial.length_tolerance and L2 >= d",
                                            cfg.source_name, e.what()));
    }
    try {
      file.emplace(cfg.output.path);
    } catch (const results::OutputError& e) {
      throw config::ConfigError(fmt::format("{}: key 'output.path': cannot write '{}' ({})",
                                            cfg.source_name, cfg.output.path, e.what()));
    }
  } catch (const config::ConfigError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  }

  results::Trajectory traj;
  const auto wall0 = std::chrono::steady_clock::now();
  const sim::SampleObserver add = [&](const sim::Sample& s) { traj.add(s, cfg.model.p, schedule); };
  const sim::RunSummary sum =
      paper ? sim::run_paper_scheme(cfg.model, schedule, *paper, cfg.run.integ.h_fixed, pair, schedule.duration(),
                                    cfg.output.sample_interval, add, state, cfg.run.omega_window)
            : sim::Simulation(cfg.model, schedule, cfg.run).run(state, schedule.duration(), cfg.output.sample_interval, add);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();

  try {
    const bool two_step = cfg.initial.preset == "table1" || cfg.initial.preset == "pair";
    file->write(args.command_line, cfg, schedule, traj, sum, state, wall,
                paper ? std::optional<double>(start_projection) : std::nullopt,
                two_step ? std::optional<sim::PairStart>(pair_start(cfg, schedule)) : std::nullopt);
  } catch (const results::OutputError& e) {  // disk full, file too large, I/O error
    std::fprintf(stderr, "error: cannot write %s: %s\n", cfg.output.path.c_str(), e.what());
    return kExitOutputFailed;
  }

  std::printf(
        "%s  final mode %s  ω_ball %.5f rad/s (%.4fπ) over the last %.3g s  energy residual %.2e  "
        "drift %.1e m  steps %ld  wall %.3f s  -> %s\n",
        sum.ok() ? "ok" : ("FAILED: " + sum.failure).c_str(), std::string(physics::to_string(state.contact.mode)).c_str(),
        sum.omega_ball, sum.omega_ball / std::numbers::pi,
        std::min(cfg.run.omega_window, 0.5 * schedule.duration()), sum.energy.relative(), sum.max_drift,
        sum.steps, wall, cfg.output.path.c_str());
  for (const sim::Violation& v : sum.violations)
    if (v.count > 0 && !args.quiet)
      std::printf("  layer assumption violated: %s: %ld times, first at t = %.6f s, worst %.3e %s\n", v.what.c_str(),
                  v.count, v.first_time, v.worst, v.unit.c_str());
  if (sum.chatter > 0 && !args.quiet)
    std::printf("  chattering resolved %ld times (first at t = %.6f s): switch band widened, impacts made plastic\n",
                sum.chatter, sum.first_chatter);
  return sum.ok() ? 0 : kExitRunFailed;
}

}  // namespace ajx::app
