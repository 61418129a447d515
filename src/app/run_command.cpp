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
#include "app/resource_budget.hpp"
#include "app/provenance.hpp"
#include "config/config.hpp"
#include "io/hdf5_file.hpp"
#include "physics/energy.hpp"
#include "sim/paper_scheme.hpp"
#include "sim/simulation.hpp"
#include "sim/table1_starts.hpp"

namespace ajx::app {

namespace {

using physics::idx::dim;

// Columns of the sampled trajectory, in memory until the run ends.
struct Trajectory {
  std::vector<double> t, r1, r2, v1, v2, T1, T2, contact, L1, psi, omega_m, phi, energy;
  std::vector<double> motor_work, drag_loss, friction_loss, impact_loss;
  std::vector<std::int32_t> mode;

  void add(const sim::Sample& s, const physics::Parameters& p) {
    t.push_back(s.t);
    for (int i = 0; i < 3; ++i) {
      r1.push_back(s.y(physics::idx::r1 + i));
      r2.push_back(s.y(physics::idx::r2 + i));
      v1.push_back(s.y(physics::idx::v1 + i));
      v2.push_back(s.y(physics::idx::v2 + i));
    }
    mode.push_back(static_cast<std::int32_t>(s.contact.mode));
    T1.push_back(s.dyn.T1);
    T2.push_back(s.dyn.T2);
    contact.push_back(s.dyn.contact);
    L1.push_back(s.dyn.g.L1);
    psi.push_back(s.dyn.g.psi);
    omega_m.push_back(s.top.motor_omega);
    phi.push_back(s.top.phi);
    energy.push_back(physics::mechanical_energy(p, s.y));
    motor_work.push_back(s.y(physics::idx::motor_work));
    drag_loss.push_back(s.y(physics::idx::drag_loss));
    friction_loss.push_back(s.y(physics::idx::friction_loss));
    impact_loss.push_back(s.impact_loss);
  }

  void write(io::Group& g) const {
    const std::size_t n = t.size();
    // One dataset per quantity, n rows of `width` columns, with units and a description.
    auto put = [&](const char* name, const std::vector<double>& v, std::size_t width, const char* unit,
                   const char* what) {
      auto d = g.write_dataset(name, std::span<const double>(v), width == 1 ? io::Dims{n} : io::Dims{n, width});
      d.set_attribute("units", unit);
      d.set_attribute("description", what);
    };
    auto col = [&](const char* name, const std::vector<double>& v, const char* unit, const char* what) {
      put(name, v, 1, unit, what);
    };
    auto vec = [&](const char* name, const std::vector<double>& v, const char* unit, const char* what) {
      put(name, v, 3, unit, what);
    };
    col("t", t, "s", "time");
    vec("r1", r1, "m", "bead (middle ball) position, z up, motor axis at x = y = 0");
    vec("r2", r2, "m", "bottom ball position");
    vec("v1", v1, "m/s", "bead velocity");
    vec("v2", v2, "m/s", "bottom ball velocity");
    auto m = g.write_dataset("mode", std::span<const std::int32_t>(mode), io::Dims{n});
    m.set_attribute("units", "1");
    m.set_attribute("description", "contact mode: 0 sliding (taut), 1 bead on the bottom ball, 2 bead stuck on the string, 3 bead at the top stop, 4 slack string");
    col("T1", T1, "N", "tension above the bead");
    col("T2", T2, "N", "tension below the bead (at the stop: the one closest to the link force)");
    col("contact", contact, "N", "push of the stop (bottom ball or top) on the bead (0 elsewhere)");
    col("L1", L1, "m", "string length above the bead, s = L1");
    col("psi", psi, "rad", "deflection of the string at the bead, arccos(u1.u2)");
    col("omega_m", omega_m, "rad/s", "motor angular velocity");
    col("phi", phi, "rad", "motor phase");
    col("energy", energy, "J", "kinetic + potential energy of both balls");
    col("motor_work", motor_work, "J", "cumulative work done by the motor (with layers.pair_couple: and by the couple on the pair)");
    col("drag_loss", drag_loss, "J", "cumulative drag dissipation");
    col("friction_loss", friction_loss, "J", "cumulative friction dissipation");
    col("impact_loss", impact_loss, "J", "cumulative dissipation in impacts");
  }
};

// The two positions a two-step start gives: Table 1's pair, the explicit pair, or an explicit
// state's r and r + h v (h = integrator.step).
sim::PairStart pair_start(const config::RunConfig& c, const physics::MotorSchedule& schedule) {
  const double h = c.run.integ.h_fixed;
  if (c.initial.preset == "table1")
    return sim::table1_pair(c.initial.orbit,
                            std::isnan(c.initial.orbit_omega) ? schedule.top(c.model.p.drive_radius, 0.0).omega
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
// before any work when they cannot fit (Trajectory's 25 doubles and one int a sample; its
// vectors grow by doubling, so up to 3 times that while one is reallocated).
void check_run_size(const config::RunConfig& cfg, double duration, double max_memory_mb) {
  constexpr double kBytesPerSample = 25 * sizeof(double) + sizeof(std::int32_t);
  const double samples = std::floor(duration / cfg.output.sample_interval) + 2;
  const std::string what = fmt::format("{:.4g} samples ({:.6g} s every {:.3g} s)", samples, duration,
                                       cfg.output.sample_interval);
  check_memory(cfg.source_name, "output.sample_interval", what, 3 * kBytesPerSample * samples,
               memory_budget(max_memory_mb), max_memory_mb);
  const double need = kBytesPerSample * samples, free = free_bytes_for(cfg.output.path);
  if (need > free)
    throw config::ConfigError(fmt::format("{}: key 'output.path': {} make {:.4g} MB of output, but only {:.4g} MB are "
                                          "free there", cfg.source_name, what, need / 1e6, free / 1e6));
}

// The trajectory, the summary and the provenance into the run's file, then committed.
// `start_projection`: with the paper's scheme, |L1 + L2 - l| of its starting pair before projection.
void write_run(io::File& f, const std::string& command_line, const config::RunConfig& cfg,
               const physics::MotorSchedule& schedule, const Trajectory& traj, const sim::RunSummary& sum,
               const physics::State& state, double wall, std::optional<double> start_projection) {
  write_format(f, "run");
  write_provenance(f, command_line, cfg);
  io::Group tg = f.create_group("trajectory");
  traj.write(tg);
  io::Group sg = f.create_group("summary");
  sg.set_attribute("status", sum.ok() ? std::string("ok") : sum.failure);
  sg.set_attribute("final_mode", std::string(physics::to_string(state.contact.mode)));
  sg.set_attribute("t_end", sum.t_end);
  sg.set_attribute("omega_ball", sum.omega_ball);
  sg.set_attribute("omega_window", cfg.run.omega_window);
  sg.set_attribute("energy_residual_relative", sum.energy.relative());
  sg.set_attribute("motor_work", sum.energy.motor_work);
  sg.set_attribute("max_constraint_drift", sum.max_drift);
  sg.set_attribute("max_sample_drift", sum.max_sample_drift);
  sg.set_attribute("steps", sum.steps);
  sg.set_attribute("rejected_steps", sum.rejected);
  sg.set_attribute("rhs_evaluations", sum.rhs_evals);
  sg.set_attribute("mode_switches", sum.mode_switches);
  sg.set_attribute("impacts", sum.impacts);
  sg.set_attribute("sticks", sum.sticks);
  sg.set_attribute("first_stick", sum.first_stick);
  sg.set_attribute("slack_phases", sum.slack_phases);
  sg.set_attribute("tie_slips", sum.tie_slips);
  sg.set_attribute("first_tie_slip", sum.first_tie_slip);
  sg.set_attribute("chatter_episodes", sum.chatter);
  sg.set_attribute("first_chatter", sum.first_chatter);
  // Assumptions of omitted layers that the run found violated, one group each.
  io::Group vg = sg.create_group("violations");
  for (std::size_t i = 0; i < sum.violations.size(); ++i) {
    const sim::Violation& v = sum.violations[i];
    io::Group g = vg.create_group(fmt::format("{}", i));
    g.set_attribute("what", v.what);
    g.set_attribute("count", v.count);
    g.set_attribute("first_time", v.first_time);
    g.set_attribute("worst", v.worst);
    g.set_attribute("worst_units", v.unit);
  }
  if (start_projection) sg.set_attribute("start_projection", *start_projection);
  if (cfg.initial.preset == "table1" || cfg.initial.preset == "pair") {
    // The raw pair: its speeds |q^(1) - q^(0)|/h and its L1 + L2 - l at t = 0.
    const sim::PairStart raw = pair_start(cfg, schedule);
    const double h = cfg.run.integ.h_fixed;
    sg.set_attribute("start_pair_speed_bead", (raw.r1_1 - raw.r1_0).norm() / h);
    sg.set_attribute("start_pair_speed_ball", (raw.r2_1 - raw.r2_0).norm() / h);
    sg.set_attribute("start_pair_length_excess", (raw.r1_0 - schedule.top(cfg.model.p.drive_radius, 0.0).a).norm() +
                                                     (raw.r2_0 - raw.r1_0).norm() - cfg.model.p.string_length);
  }
  sg.set_attribute("wall_time", wall);
  f.commit();
}

}  // namespace

int run_command(const RunArgs& args) {
  config::RunConfig cfg;
  physics::MotorSchedule schedule;
  physics::State state;
  std::optional<io::File> file;
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
    schedule = physics::MotorSchedule(cfg.schedule);
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
    const std::filesystem::path out(cfg.output.path);
    std::error_code ec;
    if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path(), ec);
    try {
      file.emplace(io::File::create_temporary(out));
    } catch (const io::Hdf5Error& e) {
      throw config::ConfigError(fmt::format("{}: key 'output.path': cannot write '{}' ({})",
                                            cfg.source_name, cfg.output.path, e.what()));
    }
  } catch (const config::ConfigError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  }

  Trajectory traj;
  const auto wall0 = std::chrono::steady_clock::now();
  const sim::SampleObserver add = [&](const sim::Sample& s) { traj.add(s, cfg.model.p); };
  const sim::RunSummary sum =
      paper ? sim::run_paper_scheme(cfg.model, schedule, *paper, cfg.run.integ.h_fixed, pair, schedule.duration(),
                                    cfg.output.sample_interval, add, state, cfg.run.omega_window)
            : sim::Simulation(cfg.model, schedule, cfg.run).run(state, schedule.duration(), cfg.output.sample_interval, add);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();

  try {
    write_run(*file, args.command_line, cfg, schedule, traj, sum, state, wall,
              paper ? std::optional<double>(start_projection) : std::nullopt);
  } catch (const io::Hdf5Error& e) {  // disk full, file too large, I/O error
    file.reset();  // an uncommitted temporary file is removed
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
