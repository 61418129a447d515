// astrojax sweep: the master/worker farm over a sweep file's chains (one per grid point),
// every window classified on rank 0, and one HDF5 file with the ω_ball map.
#include <mpi.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fmt/format.h>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "config/config.hpp"
#include "io/hdf5_file.hpp"
#include "parallel/farm.hpp"
#include "parallel/mpi_env.hpp"
#include "parallel/signals.hpp"
#include "sim/simulation.hpp"
#include "sweep/codec.hpp"
#include "sweep/orbit_classifier.hpp"
#include "sweep/task.hpp"

namespace ajx::app {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// What rank 0 keeps of every window until the file is written.
struct WindowResults {
  std::size_t chains, windows, cap;  // cap: samples stored per window at most
  std::vector<std::int32_t> cls, count;
  std::vector<double> confidence, omega_ball, omega_bead, omega_ball2, rotation, rho1_mean, rho1_std, rho2_mean,
      rho2_std, z1_mean, z2_mean, L1_mean, L1_std, L1_min, L1_max, T1_mean, T2_mean, modes;
  std::vector<double> s_t, s_omega, s_r1, s_r2, s_L1, s_T1, s_T2, s_mode;

  WindowResults(std::size_t n_chains, std::size_t n_windows, std::size_t cap_)
      : chains(n_chains), windows(n_windows), cap(cap_), cls(n_chains * n_windows, -1), count(n_chains * n_windows, 0) {
    const std::size_t n = n_chains * n_windows;
    for (auto* v : {&confidence, &omega_ball, &omega_bead, &omega_ball2, &rotation, &rho1_mean, &rho1_std, &rho2_mean,
                    &rho2_std, &z1_mean, &z2_mean, &L1_mean, &L1_std, &L1_min, &L1_max, &T1_mean, &T2_mean})
      v->assign(n, nan);
    modes.assign(n * 5, nan);
    for (auto* v : {&s_t, &s_omega, &s_L1, &s_T1, &s_T2, &s_mode}) v->assign(n * cap, nan);
    for (auto* v : {&s_r1, &s_r2}) v->assign(n * cap * 3, nan);
  }

  void store(std::size_t chain, const sweep::WindowRecord& rec, const sweep::OrbitClassification& c) {
    const std::size_t i = chain * windows + std::size_t(rec.index);
    cls[i] = static_cast<std::int32_t>(c.cls);
    confidence[i] = c.confidence;
    const auto& s = c.stats;
    omega_ball[i] = s.omega_ball;
    omega_bead[i] = s.ball[0].omega;
    omega_ball2[i] = s.ball[1].omega;
    rotation[i] = s.rotation_number;
    rho1_mean[i] = s.ball[0].rho.mean;
    rho1_std[i] = s.ball[0].rho.std;
    rho2_mean[i] = s.ball[1].rho.mean;
    rho2_std[i] = s.ball[1].rho.std;
    z1_mean[i] = s.ball[0].z.mean;
    z2_mean[i] = s.ball[1].z.mean;
    L1_mean[i] = s.L1.mean;
    L1_std[i] = s.L1.std;
    L1_min[i] = s.L1.min;
    L1_max[i] = s.L1.max;
    T1_mean[i] = s.T1.mean;
    T2_mean[i] = s.T2.mean;
    for (int k = 0; k < 5; ++k) modes[i * 5 + std::size_t(k)] = s.mode_fraction[std::size_t(k)];
    const std::size_t n = std::min(rec.size(), cap);
    count[i] = std::int32_t(n);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t j = i * cap + k;
      s_t[j] = rec.t[k];
      s_omega[j] = rec.omega_m[k];
      s_L1[j] = rec.L1[k];
      s_T1[j] = rec.T1[k];
      s_T2[j] = rec.T2[k];
      s_mode[j] = rec.mode[k];
      for (int a = 0; a < 3; ++a) {
        s_r1[3 * j + std::size_t(a)] = rec.r1[3 * k + std::size_t(a)];
        s_r2[3 * j + std::size_t(a)] = rec.r2[3 * k + std::size_t(a)];
      }
    }
  }
};

std::string now_iso() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

// Rank 0 decides, every rank learns: a collective yes/no.
bool agree(bool ok_on_master) {
  int v = ok_on_master ? 1 : 0;
  MPI_Bcast(&v, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return v != 0;
}

}  // namespace

int sweep_command(const SweepArgs& args) {
  const int rank = parallel::comm_rank(MPI_COMM_WORLD), ranks = parallel::comm_size(MPI_COMM_WORLD);
  const bool master = rank == 0;

  // Every rank parses the same file: the chains are then known everywhere and only task ids,
  // states and results travel. Rank 0 reports errors; all ranks stop on them.
  config::SweepConfig cfg;
  std::vector<config::GridPoint> points;
  std::optional<io::File> file;
  std::string error;
  try {
    cfg = config::load_sweep_config(args.config_path, args.overrides);
    if (!args.output.empty()) cfg.output_path = args.output;
    points = config::expand_grid(cfg);
    if (cfg.initial.preset != "hanging")
      throw config::ConfigError(fmt::format("{}: key 'initial.preset': sweeps start every chain from 'hanging'",
                                            cfg.source_name));
  } catch (const config::ConfigError& e) {
    error = e.what();
  }
  if (master && error.empty()) {
    const std::filesystem::path out(cfg.output_path);
    std::error_code ec;
    if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path(), ec);
    try {
      file.emplace(io::File::create_temporary(out));
    } catch (const io::Hdf5Error& e) {
      error = fmt::format("{}: key 'output.path': cannot write '{}' ({})", cfg.source_name, cfg.output_path, e.what());
    }
  }
  if (!agree(error.empty())) {
    if (master) std::fprintf(stderr, "error: %s\n", error.empty() ? "invalid sweep file" : error.c_str());
    return kExitBadInput;
  }

  // Chains: one per grid point, each split into tasks on window boundaries.
  std::vector<sweep::ChainSetup> setups;
  std::vector<std::vector<sweep::TaskSpan>> spans;
  for (const auto& g : points) {
    sweep::ChainSetup c;
    c.model = g.model;
    c.protocol = sweep::compile(g.protocol, cfg.start_omega);
    c.run = cfg.run;
    c.sample_rate = cfg.sample_rate;
    spans.push_back(sweep::split(c.protocol, cfg.windows_per_task));
    setups.push_back(std::move(c));
  }
  std::size_t n_windows = 0, cap = 0, n_tasks = 0;
  double total_sim = 0.0;
  for (std::size_t c = 0; c < setups.size(); ++c) {
    n_windows = std::max(n_windows, setups[c].protocol.windows.size());
    for (const auto& w : setups[c].protocol.windows)
      cap = std::max(cap, std::size_t(std::ceil((w.t_end - w.t_begin) * cfg.sample_rate)) + 1);
    n_tasks += spans[c].size();
    total_sim += setups[c].protocol.duration;
  }

  // The work: decode (chain, span), integrate, return the windows and the carry.
  const parallel::WorkFunction work = [&](const parallel::Task& task, const parallel::Bytes& carry) {
    sweep::ByteReader r(task.input.data(), task.input.size());
    const auto chain = std::size_t(r.get<std::int64_t>());
    const auto span = std::size_t(r.get<std::int64_t>());
    sweep::TaskOutput out = sweep::run_task(setups[chain], spans[chain][span], sweep::decode_state(carry));
    parallel::Outcome o;
    o.ok = out.ok;
    o.error = out.failure;
    o.carry = sweep::encode(out.final_state);
    o.output = sweep::encode(out);
    return o;
  };

  std::vector<parallel::Chain> chains;
  std::int64_t next_id = 0;
  if (master) {
    for (std::size_t c = 0; c < setups.size(); ++c) {
      parallel::Chain ch;
      ch.id = std::int64_t(c);
      const physics::MotorSchedule sched(setups[c].protocol.schedule);
      ch.carry = sweep::encode(sim::hanging_at_rest(setups[c].model, sched));
      for (std::size_t k = 0; k < spans[c].size(); ++k) {
        sweep::ByteWriter w;
        w.put<std::int64_t>(std::int64_t(c));
        w.put<std::int64_t>(std::int64_t(k));
        ch.tasks.push_back({next_id++, ch.id, std::int64_t(k), w.take()});
      }
      chains.push_back(std::move(ch));
    }
  }

  // Rank 0: results per window, and per task what a later run needs.
  WindowResults windows(master ? setups.size() : 0, master ? n_windows : 0, master ? cap : 0);
  std::vector<std::int32_t> task_status(master ? n_tasks : 0, 0);  // 0 never ran, 1 ok, 2 failed, 3 not run
  std::vector<double> task_state(master ? n_tasks * (physics::idx::dim + 5) : 0, nan);
  std::vector<std::int64_t> task_steps(master ? n_tasks : 0, 0);
  std::vector<std::string> failures;
  double simulated = 0.0;

  std::atomic<bool> stop{false};
  if (master)
    parallel::install_stop_handlers(stop);
  else
    parallel::ignore_stop_signals();

  parallel::FarmOptions fo;
  fo.stop = &stop;
  fo.on_result = [&](const parallel::TaskResult& r) {
    const auto id = std::size_t(r.task_id);
    if (!r.ran) {
      task_status[id] = 3;
      return;
    }
    const sweep::TaskOutput out = sweep::decode_output(r.output);
    task_status[id] = out.ok ? 1 : 2;
    task_steps[id] = out.steps;
    simulated += out.simulated;
    if (!out.ok) failures.push_back(fmt::format("task {} (chain {}, part {}): {}", r.task_id, r.chain, r.index, out.failure));
    const physics::State& s = out.final_state;
    double* st = &task_state[id * (physics::idx::dim + 5)];
    st[0] = s.t;
    st[1] = double(s.contact.mode);
    st[2] = double(s.contact.sigma);
    st[3] = s.contact.s_star;
    st[4] = s.impact_loss;
    for (int k = 0; k < physics::idx::dim; ++k) st[5 + k] = s.y(k);
    const auto chain = std::size_t(r.chain);
    const sweep::OrbitScales scales = sweep::orbit_scales(setups[chain].model.p);
    for (const auto& rec : out.windows) {
      // A window the failed integration did not finish is recorded as failed.
      const bool complete = out.ok || (rec.size() > 0 && rec.t.back() >= setups[chain].protocol.windows[std::size_t(rec.index)].t_end - 2.0 / cfg.sample_rate);
      sweep::OrbitWindow w;
      w.t = rec.t;
      w.omega_m = rec.omega_m;
      w.r1 = rec.r1;
      w.r2 = rec.r2;
      w.L1 = rec.L1;
      w.T1 = rec.T1;
      w.T2 = rec.T2;
      w.mode = std::span<const int>(reinterpret_cast<const int*>(rec.mode.data()), rec.mode.size());
      w.failed = !complete;
      w.failure = out.failure;
      windows.store(chain, rec, sweep::classify_orbit(w, scales));
    }
  };
  const auto wall0 = std::chrono::steady_clock::now();
  const bool terminal = isatty(fileno(stdout));
  fo.on_progress = [&](const parallel::Progress& p) {
    if (args.quiet) return;
    const double rate = p.elapsed_seconds > 0 ? simulated / p.elapsed_seconds : 0.0;
    const double eta = rate > 0 ? (total_sim - simulated) / rate : nan;
    std::printf("%s%lld/%lld tasks, %lld failed, %.1f simulated s per wall s, ETA %.0f s%s", terminal ? "\r" : "",
                (long long)p.done, (long long)p.total, (long long)p.failed, rate, eta, terminal ? "   " : "\n");
    std::fflush(stdout);
  };
  fo.progress_interval = terminal ? 0.5 : 10.0;
  const std::string started = now_iso();
  const parallel::FarmSummary fs = parallel::run_farm(std::move(chains), work, fo);
  if (!master) return fs.status == parallel::FarmStatus::Completed ? 0 : kExitInterrupted;
  if (terminal && !args.quiet) std::printf("\n");
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();

  // The file: everything but /provenance depends on the tasks alone, not on the ranks.
  io::File& f = *file;
  auto config = f.write_string_dataset("config", cfg.source_text);
  config.set_attribute("source", cfg.source_name);
  config.set_attribute("overrides", fmt::format("{}", fmt::join(cfg.overrides, "\n")));
  io::Group prov = f.create_group("provenance");
  char host[256] = "?";
  gethostname(host, sizeof host - 1);
  prov.set_attribute("program", "astrojax-explorer");
  prov.set_attribute("command_line", args.command_line);
  prov.set_attribute("ranks", ranks);
  prov.set_attribute("host", std::string(host));
  prov.set_attribute("start_time", started);
  prov.set_attribute("end_time", now_iso());
  prov.set_attribute("wall_time", wall);
  prov.set_attribute("farm_status", parallel::to_string(fs.status));
  prov.set_attribute("tasks_per_second", fs.tasks_per_second);
#ifdef ASTROJAX_GIT_COMMIT
  prov.set_attribute("git_commit", ASTROJAX_GIT_COMMIT);
#endif

  const std::size_t C = setups.size(), W = n_windows;
  io::Group cg = f.create_group("chains");
  {
    std::vector<std::string> names;
    for (const auto& a : cfg.grid) names.push_back(a.key);
    cg.set_attribute("axes", fmt::format("{}", fmt::join(names, ",")));
    std::vector<double> values, model;
    for (const auto& g : points) {
      values.insert(values.end(), g.values.begin(), g.values.end());
      const physics::Parameters& p = g.model.p;
      for (double v : {p.string_length, p.bead_mass, p.ball_mass, p.drag, p.mu_static, p.mu_kinetic, p.gravity,
                       p.drive_radius, p.contact_distance, p.top_stop})
        model.push_back(v);
    }
    if (!names.empty()) cg.write_dataset("grid_values", std::span<const double>(values), io::Dims{C, names.size()});
    auto md = cg.write_dataset("model", std::span<const double>(model), io::Dims{C, 10});
    md.set_attribute("columns", "string_length [m],bead_mass [kg],ball_mass [kg],drag [kg/s],mu_static,mu_kinetic,"
                                "gravity [m/s^2],drive_radius [m],contact_distance [m],top_stop [m]");
  }
  io::Group wg = f.create_group("windows");
  {
    std::vector<double> tb(C * W, nan), te(C * W, nan), wb(C * W, nan), we(C * W, nan);
    std::vector<std::int32_t> dir(C * W, 0), seg(C * W, -1);
    for (std::size_t c = 0; c < C; ++c)
      for (std::size_t k = 0; k < setups[c].protocol.windows.size(); ++k) {
        const auto& w = setups[c].protocol.windows[k];
        const std::size_t i = c * W + k;
        tb[i] = w.t_begin;
        te[i] = w.t_end;
        wb[i] = w.omega_begin;
        we[i] = w.omega_end;
        dir[i] = w.direction;
        seg[i] = w.segment;
      }
    const io::Dims dims{C, W};
    auto put = [&](const char* name, const std::vector<double>& v, const char* unit, const char* what) {
      auto d = wg.write_dataset(name, std::span<const double>(v), dims);
      d.set_attribute("units", unit);
      d.set_attribute("description", what);
    };
    put("t_begin", tb, "s", "window start");
    put("t_end", te, "s", "window end");
    put("omega_m_begin", wb, "rad/s", "motor ω_m at the window start");
    put("omega_m_end", we, "rad/s", "motor ω_m at the window end");
    wg.write_dataset("direction", std::span<const std::int32_t>(dir), dims)
        .set_attribute("description", "+1 ω_m rising, -1 falling, 0 held");
    wg.write_dataset("segment", std::span<const std::int32_t>(seg), dims)
        .set_attribute("description", "protocol segment index");
    auto cls = wg.write_dataset("class", std::span<const std::int32_t>(windows.cls), dims);
    cls.set_attribute("description", "orbit class; -1 = not computed (the task never ran)");
    cls.set_attribute("names", "0 fallen,1 locked-circular,2 lagging-circular,3 flower,4 not-settled,5 failed");
    put("confidence", windows.confidence, "1", "confidence of the class, in [0, 1]");
    put("omega_ball", windows.omega_ball, "rad/s", "mean ω_ball of the balls with a reliable azimuth");
    put("omega_ball_bead", windows.omega_bead, "rad/s", "ω_ball of the bead (NaN when unreliable)");
    put("omega_ball_bottom", windows.omega_ball2, "rad/s", "ω_ball of the bottom ball (NaN when unreliable)");
    put("rotation_number", windows.rotation, "1", "ω_ball / mean ω_m");
    put("radius_bead_mean", windows.rho1_mean, "m", "mean horizontal radius of the bead");
    put("radius_bead_std", windows.rho1_std, "m", "its standard deviation");
    put("radius_bottom_mean", windows.rho2_mean, "m", "mean horizontal radius of the bottom ball");
    put("radius_bottom_std", windows.rho2_std, "m", "its standard deviation");
    put("height_bead_mean", windows.z1_mean, "m", "mean height of the bead");
    put("height_bottom_mean", windows.z2_mean, "m", "mean height of the bottom ball");
    put("L1_mean", windows.L1_mean, "m", "mean bead position s = L1");
    put("L1_std", windows.L1_std, "m", "its standard deviation");
    put("L1_min", windows.L1_min, "m", "smallest L1");
    put("L1_max", windows.L1_max, "m", "largest L1");
    put("T1_mean", windows.T1_mean, "N", "mean tension above the bead");
    put("T2_mean", windows.T2_mean, "N", "mean tension below the bead");
    auto mf = wg.write_dataset("mode_fraction", std::span<const double>(windows.modes), io::Dims{C, W, 5});
    mf.set_attribute("description", "time fraction in modes 0 sliding, 1 bottom stop, 2 stuck, 3 top stop, 4 slack");
  }
  io::Group sg = f.create_group("samples");
  {
    sg.set_attribute("sample_rate", cfg.sample_rate);
    sg.set_attribute("description", "every window's samples, padded with NaN beyond count: astrojax classify reads these");
    const io::Dims d3{C, W, cap}, d4{C, W, cap, 3};
    sg.write_dataset("count", std::span<const std::int32_t>(windows.count), io::Dims{C, W});
    auto put = [&](const char* name, const std::vector<double>& v, const io::Dims& dims, const char* unit) {
      sg.write_dataset(name, std::span<const double>(v), dims).set_attribute("units", unit);
    };
    put("t", windows.s_t, d3, "s");
    put("omega_m", windows.s_omega, d3, "rad/s");
    put("r1", windows.s_r1, d4, "m");
    put("r2", windows.s_r2, d4, "m");
    put("L1", windows.s_L1, d3, "m");
    put("T1", windows.s_T1, d3, "N");
    put("T2", windows.s_T2, d3, "N");
    put("mode", windows.s_mode, d3, "1");
  }
  io::Group tg = f.create_group("tasks");
  {
    std::vector<std::int64_t> chain, index, steps(task_steps.begin(), task_steps.end());
    std::vector<double> tb, te;
    for (std::size_t c = 0; c < C; ++c)
      for (std::size_t k = 0; k < spans[c].size(); ++k) {
        chain.push_back(std::int64_t(c));
        index.push_back(std::int64_t(k));
        tb.push_back(spans[c][k].t_begin);
        te.push_back(spans[c][k].t_end);
      }
    tg.write_dataset("chain", std::span<const std::int64_t>(chain));
    tg.write_dataset("index", std::span<const std::int64_t>(index));
    tg.write_dataset("t_begin", std::span<const double>(tb)).set_attribute("units", "s");
    tg.write_dataset("t_end", std::span<const double>(te)).set_attribute("units", "s");
    tg.write_dataset("status", std::span<const std::int32_t>(task_status))
        .set_attribute("names", "0 never ran,1 ok,2 failed,3 not run (an earlier task of its chain failed)");
    tg.write_dataset("steps", std::span<const std::int64_t>(steps));
    tg.write_dataset("final_state", std::span<const double>(task_state), io::Dims{n_tasks, physics::idx::dim + 5})
        .set_attribute("columns", "t, mode, sigma, s_star, impact_loss, then r1, r2, v1, v2, motor_work, drag_loss, "
                                  "friction_loss (SI units)");
    std::sort(failures.begin(), failures.end());
    tg.write_string_dataset("failures", fmt::format("{}", fmt::join(failures, "\n")));
  }
  f.commit();

  const bool interrupted = fs.status != parallel::FarmStatus::Completed;
  std::printf("%s  %lld chains, %lld tasks (%lld failed, %lld not run, %lld never started), %.0f simulated s in %.1f s "
              "wall on %d ranks -> %s\n",
              interrupted ? "INTERRUPTED" : "ok", (long long)C, (long long)n_tasks, (long long)fs.failed,
              (long long)fs.not_run, (long long)fs.unstarted, simulated, wall, ranks, cfg.output_path.c_str());
  for (const auto& fl : failures) std::printf("  failed: %s\n", fl.c_str());
  if (interrupted)
    std::printf("interrupted: the finished tasks are in %s; resuming is not available yet, rerun the sweep\n",
                cfg.output_path.c_str());
  return interrupted ? kExitInterrupted : (failures.empty() ? 0 : kExitRunFailed);
}

}  // namespace ajx::app
