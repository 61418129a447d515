// astrojax sweep: the master/worker farm over a sweep file's chains (one per grid point),
// every window classified on rank 0, and one HDF5 file with the ω_ball map.
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <functional>
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

// The sweep's file on rank 0, written while the sweep runs: every result dataset is made at
// the start, filled with "not computed" (NaN, class -1, status 0), and each finished task
// writes its windows and its final state and flushes. An interrupted sweep keeps all that.
class SweepFile {
 public:
  // The per-window statistics, in the order of kStats.
  static constexpr const char* kStats[][3] = {
      {"confidence", "1", "confidence of the class, in [0, 1]"},
      {"omega_ball", "rad/s", "mean ω_ball of the balls with a reliable azimuth"},
      {"omega_ball_bead", "rad/s", "ω_ball of the bead (NaN when unreliable)"},
      {"omega_ball_bottom", "rad/s", "ω_ball of the bottom ball (NaN when unreliable)"},
      {"rotation_number", "1", "ω_ball / mean ω_m"},
      {"radius_bead_mean", "m", "mean horizontal radius of the bead"},
      {"radius_bead_std", "m", "its standard deviation"},
      {"radius_bottom_mean", "m", "mean horizontal radius of the bottom ball"},
      {"radius_bottom_std", "m", "its standard deviation"},
      {"height_bead_mean", "m", "mean height of the bead"},
      {"height_bottom_mean", "m", "mean height of the bottom ball"},
      {"L1_mean", "m", "mean bead position s = L1"},
      {"L1_std", "m", "its standard deviation"},
      {"L1_min", "m", "smallest L1"},
      {"L1_max", "m", "largest L1"},
      {"T1_mean", "N", "mean tension above the bead"},
      {"T2_mean", "N", "mean tension below the bead"},
  };
  static constexpr std::size_t kNumStats = sizeof(kStats) / sizeof(kStats[0]);
  static constexpr const char* kSamples[] = {"t", "omega_m", "L1", "T1", "T2", "mode"};
  static constexpr std::size_t kStateCols = physics::idx::dim + 5;

  SweepFile(io::File file, std::size_t chains, std::size_t windows, std::size_t cap, std::size_t tasks)
      : f_(std::move(file)), C_(chains), W_(windows), cap_(cap), T_(tasks) {}

  // A new file: the configuration, the layout and the empty result datasets.
  void create(const config::SweepConfig& cfg, const std::vector<config::GridPoint>& points,
              const std::vector<sweep::ChainSetup>& setups, const std::vector<std::vector<sweep::TaskSpan>>& spans) {
    auto config = f_.write_string_dataset("config", cfg.source_text);
    config.set_attribute("source", cfg.source_name);
    config.set_attribute("overrides", joined_overrides(cfg));
    write_chains(cfg, points);
    write_window_layout(setups);
    io::Group wg = f_.open_group("windows");
    const io::Dims dims{C_, W_}, chunk{1, W_};
    auto cls = wg.create_filled("class", dims, io::DType::Int32, -1.0, chunk);
    cls.set_attribute("description", "orbit class; -1 = not computed (the task never ran)");
    cls.set_attribute("names", "0 fallen,1 locked-circular,2 lagging-circular,3 flower,4 not-settled,5 failed");
    for (const auto& st : kStats) {
      auto d = wg.create_filled(st[0], dims, io::DType::Float64, nan, chunk);
      d.set_attribute("units", st[1]);
      d.set_attribute("description", st[2]);
    }
    wg.create_filled("mode_fraction", {C_, W_, 5}, io::DType::Float64, nan, {1, W_, 5})
        .set_attribute("description", "time fraction in modes 0 sliding, 1 bottom stop, 2 stuck, 3 top stop, 4 slack");
    io::Group sg = f_.create_group("samples");
    sg.set_attribute("sample_rate", cfg.sample_rate);
    sg.set_attribute("description", "every window's samples, padded with NaN beyond count");
    sg.create_filled("count", dims, io::DType::Int32, 0.0, chunk);
    for (const char* name : kSamples) sg.create_filled(name, {C_, W_, cap_}, io::DType::Float64, nan, {1, 1, cap_}, 4);
    for (const char* name : {"r1", "r2"}) sg.create_filled(name, {C_, W_, cap_, 3}, io::DType::Float64, nan, {1, 1, cap_, 3}, 4);
    io::Group tg = f_.create_group("tasks");
    std::vector<std::int64_t> chain, index;
    std::vector<double> tb, te;
    for (std::size_t c = 0; c < C_; ++c)
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
    tg.create_filled("status", {T_}, io::DType::Int32, 0.0, {T_})
        .set_attribute("names", "0 never ran,1 ok,2 failed,3 not run (an earlier task of its chain failed)");
    tg.create_filled("steps", {T_}, io::DType::Int64, 0.0, {T_});
    tg.create_filled("final_state", {T_, kStateCols}, io::DType::Float64, nan, {1, kStateCols})
        .set_attribute("columns", "t, mode, sigma, s_star, impact_loss, then r1, r2, v1, v2, motor_work, drag_loss, "
                                  "friction_loss (SI units)");
    f_.flush();
  }

  // An existing file, to resume: it must come from the same configuration.
  void check_same(const config::SweepConfig& cfg) const {
    const io::Dataset config = f_.open_dataset("config");
    if (config.read_string() != cfg.source_text || config.read_string_attribute("overrides") != joined_overrides(cfg))
      throw config::ConfigError(fmt::format(
          "{}: key 'output.path': {} was written by a different sweep file or overrides; resume it with the same "
          "ones, or remove it to start afresh",
          cfg.source_name, f_.disk_path().string()));
  }

  std::vector<std::int32_t> status() const { return f_.read_int32s("tasks/status").data; }
  physics::State state(std::size_t task) const {
    const auto all = f_.read_doubles("tasks/final_state");
    const double* st = &all.data[task * kStateCols];
    physics::State s;
    s.t = st[0];
    s.contact.mode = static_cast<physics::Mode>(int(st[1]));
    s.contact.sigma = int(st[2]);
    s.contact.s_star = st[3];
    s.impact_loss = st[4];
    for (int k = 0; k < physics::idx::dim; ++k) s.y(k) = st[5 + k];
    return s;
  }

  void write_not_run(std::size_t task) {
    const std::int32_t v = 3;
    f_.open_dataset("tasks/status").write_region({task}, {1}, std::span<const std::int32_t>(&v, 1));
    f_.flush();
  }

  void write_task(std::size_t task, std::size_t chain, const sweep::TaskOutput& out,
                  const std::vector<sweep::OrbitClassification>& classes) {
    for (std::size_t i = 0; i < out.windows.size(); ++i) write_window(chain, out.windows[i], classes[i]);
    const std::int32_t st = out.ok ? 1 : 2;
    f_.open_dataset("tasks/status").write_region({task}, {1}, std::span<const std::int32_t>(&st, 1));
    const std::int64_t steps = out.steps;
    f_.open_dataset("tasks/steps").write_region({task}, {1}, std::span<const std::int64_t>(&steps, 1));
    const physics::State& s = out.final_state;
    std::vector<double> row{s.t, double(s.contact.mode), double(s.contact.sigma), s.contact.s_star, s.impact_loss};
    row.insert(row.end(), s.y.data(), s.y.data() + s.y.size());
    f_.open_dataset("tasks/final_state").write_region({task, 0}, {1, kStateCols}, std::span<const double>(row));
    f_.flush();
  }

  // Failures of this run join those of earlier runs of the same sweep (one line each, sorted).
  void finish(std::vector<std::string> failures, const std::function<void(io::Group&)>& provenance) {
    io::Group tg = f_.open_group("tasks");
    if (tg.has_attribute("failures")) {
      const std::string old = tg.read_string_attribute("failures");
      for (std::size_t a = 0, b; a < old.size(); a = b + 1) {
        b = old.find('\n', a);
        if (b == std::string::npos) b = old.size();
        if (b > a) failures.push_back(old.substr(a, b - a));
      }
    }
    std::sort(failures.begin(), failures.end());
    failures.erase(std::unique(failures.begin(), failures.end()), failures.end());
    tg.set_attribute("failures", fmt::format("{}", fmt::join(failures, "\n")));
    io::Group prov = f_.require_group("provenance");
    provenance(prov);
    f_.close();
  }

 private:
  static std::string joined_overrides(const config::SweepConfig& cfg) {
    return fmt::format("{}", fmt::join(cfg.overrides, "\n"));
  }

  void write_chains(const config::SweepConfig& cfg, const std::vector<config::GridPoint>& points) {
    io::Group cg = f_.create_group("chains");
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
    if (!names.empty()) cg.write_dataset("grid_values", std::span<const double>(values), io::Dims{C_, names.size()});
    cg.write_dataset("model", std::span<const double>(model), io::Dims{C_, 10})
        .set_attribute("columns", "string_length [m],bead_mass [kg],ball_mass [kg],drag [kg/s],mu_static,mu_kinetic,"
                                  "gravity [m/s^2],drive_radius [m],contact_distance [m],top_stop [m]");
  }

  void write_window_layout(const std::vector<sweep::ChainSetup>& setups) {
    io::Group wg = f_.create_group("windows");
    std::vector<double> tb(C_ * W_, nan), te(C_ * W_, nan), wb(C_ * W_, nan), we(C_ * W_, nan);
    std::vector<std::int32_t> dir(C_ * W_, 0), seg(C_ * W_, -1);
    for (std::size_t c = 0; c < C_; ++c)
      for (std::size_t k = 0; k < setups[c].protocol.windows.size(); ++k) {
        const auto& w = setups[c].protocol.windows[k];
        const std::size_t i = c * W_ + k;
        tb[i] = w.t_begin;
        te[i] = w.t_end;
        wb[i] = w.omega_begin;
        we[i] = w.omega_end;
        dir[i] = w.direction;
        seg[i] = w.segment;
      }
    const io::Dims dims{C_, W_};
    const auto put = [&](const char* name, const std::vector<double>& v, const char* unit, const char* what) {
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
  }

  void write_window(std::size_t chain, const sweep::WindowRecord& rec, const sweep::OrbitClassification& c) {
    const io::Dims at{chain, std::size_t(rec.index)}, one{1, 1};
    const std::int32_t cls = static_cast<std::int32_t>(c.cls);
    f_.open_dataset("windows/class").write_region(at, one, std::span<const std::int32_t>(&cls, 1));
    const auto& s = c.stats;
    const double stats[kNumStats] = {c.confidence,     s.omega_ball,     s.ball[0].omega,  s.ball[1].omega,
                                     s.rotation_number, s.ball[0].rho.mean, s.ball[0].rho.std, s.ball[1].rho.mean,
                                     s.ball[1].rho.std, s.ball[0].z.mean, s.ball[1].z.mean, s.L1.mean,
                                     s.L1.std,         s.L1.min,         s.L1.max,         s.T1.mean,
                                     s.T2.mean};
    for (std::size_t k = 0; k < kNumStats; ++k)
      f_.open_dataset(std::string("windows/") + kStats[k][0]).write_region(at, one, std::span<const double>(&stats[k], 1));
    f_.open_dataset("windows/mode_fraction")
        .write_region({chain, std::size_t(rec.index), 0}, {1, 1, 5}, std::span<const double>(s.mode_fraction));
    const std::size_t n = std::min(rec.size(), cap_);
    const std::int32_t count = std::int32_t(n);
    f_.open_dataset("samples/count").write_region(at, one, std::span<const std::int32_t>(&count, 1));
    if (n == 0) return;
    std::vector<double> mode(rec.mode.begin(), rec.mode.begin() + long(n));
    const std::vector<double>* columns[] = {&rec.t, &rec.omega_m, &rec.L1, &rec.T1, &rec.T2, &mode};
    for (std::size_t k = 0; k < 6; ++k)
      f_.open_dataset(std::string("samples/") + kSamples[k])
          .write_region({chain, std::size_t(rec.index), 0}, {1, 1, n}, std::span<const double>(columns[k]->data(), n));
    f_.open_dataset("samples/r1").write_region({chain, std::size_t(rec.index), 0, 0}, {1, 1, n, 3},
                                               std::span<const double>(rec.r1.data(), 3 * n));
    f_.open_dataset("samples/r2").write_region({chain, std::size_t(rec.index), 0, 0}, {1, 1, n, 3},
                                               std::span<const double>(rec.r2.data(), 3 * n));
  }

  io::File f_;
  std::size_t C_, W_, cap_, T_;
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

  // Chains: one per grid point, each split into tasks on window boundaries.
  std::vector<sweep::ChainSetup> setups;
  std::vector<std::vector<sweep::TaskSpan>> spans;
  std::vector<std::size_t> first_task;  // id of each chain's task 0
  std::size_t n_windows = 0, cap = 0, n_tasks = 0;
  double total_sim = 0.0;
  if (error.empty()) {
    for (const auto& g : points) {
      sweep::ChainSetup c;
      c.model = g.model;
      c.protocol = sweep::compile(g.protocol, cfg.start_omega);
      c.run = cfg.run;
      c.sample_rate = cfg.sample_rate;
      spans.push_back(sweep::split(c.protocol, cfg.windows_per_task));
      first_task.push_back(n_tasks);
      n_tasks += spans.back().size();
      n_windows = std::max(n_windows, c.protocol.windows.size());
      for (const auto& w : c.protocol.windows)
        cap = std::max(cap, std::size_t(std::ceil((w.t_end - w.t_begin) * c.sample_rate)) + 1);
      total_sim += c.protocol.duration;
      setups.push_back(std::move(c));
    }
  }

  // Rank 0 opens the file: "<path>.part" while the sweep runs, renamed to <path> when every
  // task has finished. --resume reopens the .part of an interrupted sweep.
  const std::filesystem::path final_path(cfg.output_path), part_path(cfg.output_path + ".part");
  std::optional<SweepFile> file;
  std::vector<std::int32_t> status;
  if (master && error.empty()) {
    try {
      if (args.resume) {
        if (!std::filesystem::exists(part_path)) {
          throw config::ConfigError(fmt::format(
              "{}: key 'output.path': nothing to resume: {} does not exist{}", cfg.source_name, part_path.string(),
              std::filesystem::exists(final_path) ? fmt::format(" ({} is complete)", final_path.string()) : ""));
        }
        file.emplace(io::File::open_rw(part_path), setups.size(), n_windows, cap, n_tasks);
        file->check_same(cfg);
        status = file->status();
        if (status.size() != n_tasks)
          throw config::ConfigError(fmt::format("{}: key 'output.path': {} has {} tasks, the sweep {}",
                                                cfg.source_name, part_path.string(), status.size(), n_tasks));
      } else {
        std::error_code ec;
        if (final_path.has_parent_path()) std::filesystem::create_directories(final_path.parent_path(), ec);
        file.emplace(io::File::create(part_path), setups.size(), n_windows, cap, n_tasks);
        file->create(cfg, points, setups, spans);
        status.assign(n_tasks, 0);
      }
    } catch (const io::Hdf5Error& e) {
      error = fmt::format("{}: key 'output.path': cannot write '{}' ({})", cfg.source_name, part_path.string(), e.what());
    } catch (const config::ConfigError& e) {
      error = e.what();
    }
  }
  if (!agree(error.empty())) {
    if (master) std::fprintf(stderr, "error: %s\n", error.empty() ? "invalid sweep file" : error.c_str());
    return kExitBadInput;
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

  // The chains still to run: each from its first task that never ran, with the state its
  // predecessor left (stored in the file); chains that finished or failed are done.
  std::vector<parallel::Chain> chains;
  double done_sim = 0.0;
  if (master) {
    for (std::size_t c = 0; c < setups.size(); ++c) {
      std::size_t k = 0;
      while (k < spans[c].size() && status[first_task[c] + k] == 1) ++k;
      if (k > 0) done_sim += spans[c][k - 1].t_end;
      if (k == spans[c].size() || status[first_task[c] + k] != 0) continue;
      parallel::Chain ch;
      ch.id = std::int64_t(c);
      const physics::MotorSchedule sched(setups[c].protocol.schedule);
      ch.carry = sweep::encode(k == 0 ? sim::hanging_at_rest(setups[c].model, sched)
                                      : file->state(first_task[c] + k - 1));
      for (std::size_t j = k; j < spans[c].size(); ++j) {
        sweep::ByteWriter w;
        w.put<std::int64_t>(std::int64_t(c));
        w.put<std::int64_t>(std::int64_t(j));
        ch.tasks.push_back({std::int64_t(first_task[c] + j), ch.id, std::int64_t(j), w.take()});
      }
      chains.push_back(std::move(ch));
    }
    if (args.resume && !args.quiet)
      std::printf("resuming %s: %zu of %zu chains to continue, %.0f of %.0f simulated s done\n", part_path.c_str(),
                  chains.size(), setups.size(), done_sim, total_sim);
  }

  std::vector<std::string> failures;
  double simulated = done_sim;
  std::atomic<bool> stop{false};
  if (master)
    parallel::install_stop_handlers(stop);
  else
    parallel::ignore_stop_signals();

  parallel::FarmOptions fo;
  fo.stop = &stop;
  long results = 0;
  fo.on_result = [&](const parallel::TaskResult& r) {
    if (args.max_tasks > 0 && ++results >= args.max_tasks) stop = true;
    const auto id = std::size_t(r.task_id);
    if (!r.ran) {
      status[id] = 3;
      file->write_not_run(id);
      return;
    }
    const sweep::TaskOutput out = sweep::decode_output(r.output);
    status[id] = out.ok ? 1 : 2;
    simulated += out.simulated;
    if (!out.ok) failures.push_back(fmt::format("task {} (chain {}, part {}): {}", r.task_id, r.chain, r.index, out.failure));
    const auto chain = std::size_t(r.chain);
    const sweep::OrbitScales scales = sweep::orbit_scales(setups[chain].model.p);
    std::vector<sweep::OrbitClassification> classes;
    for (const auto& rec : out.windows) {
      // A window the failed integration did not finish is recorded as failed.
      const double t_end = setups[chain].protocol.windows[std::size_t(rec.index)].t_end;
      const bool complete = out.ok || (rec.size() > 0 && rec.t.back() >= t_end - 2.0 / cfg.sample_rate);
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
      classes.push_back(sweep::classify_orbit(w, scales));
    }
    file->write_task(id, chain, out, classes);  // written and flushed at once
  };
  const auto wall0 = std::chrono::steady_clock::now();
  const bool terminal = isatty(fileno(stdout));
  fo.on_progress = [&](const parallel::Progress& p) {
    if (args.quiet) return;
    const double elapsed = p.elapsed_seconds;
    const double rate = elapsed > 0 ? (simulated - done_sim) / elapsed : 0.0;
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

  std::sort(failures.begin(), failures.end());
  file->finish(failures, [&](io::Group& prov) {
    char host[256] = "?";
    gethostname(host, sizeof host - 1);
    prov.set_attribute("program", "astrojax-explorer");
    prov.set_attribute("command_line", args.command_line);
    prov.set_attribute("ranks", ranks);
    prov.set_attribute("host", std::string(host));
    prov.set_attribute(args.resume ? "resume_start_time" : "start_time", started);
    prov.set_attribute("end_time", now_iso());
    prov.set_attribute(args.resume ? "resume_wall_time" : "wall_time", wall);
    prov.set_attribute("farm_status", parallel::to_string(fs.status));
    prov.set_attribute("tasks_per_second", fs.tasks_per_second);
#ifdef ASTROJAX_GIT_COMMIT
    prov.set_attribute("git_commit", ASTROJAX_GIT_COMMIT);
#endif
  });
  const bool complete = std::none_of(status.begin(), status.end(), [](std::int32_t v) { return v == 0; });
  if (complete) std::filesystem::rename(part_path, final_path);

  std::printf("%s  %zu chains, %zu tasks (%lld failed, %lld not run, %lld never started), %.0f of %.0f simulated s "
              "in %.1f s wall on %d ranks -> %s\n",
              complete ? "ok" : "INTERRUPTED", setups.size(), n_tasks, (long long)fs.failed, (long long)fs.not_run,
              (long long)fs.unstarted, simulated, total_sim, wall, ranks,
              complete ? final_path.c_str() : part_path.c_str());
  for (const auto& fl : failures) std::printf("  failed: %s\n", fl.c_str());
  if (!complete) {
    std::printf("the finished tasks are in %s; continue with the same command and --resume\n", part_path.c_str());
    return kExitInterrupted;
  }
  return failures.empty() ? 0 : kExitRunFailed;
}

}  // namespace ajx::app
