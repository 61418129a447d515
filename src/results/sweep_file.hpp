// The HDF5 file of a sweep (layout: docs/reference/file-format.md): made at the start with every
// result "not computed", filled task by task, reopened to resume or to reclassify.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <algorithm>
#include <chrono>
#include <fmt/format.h>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <sstream>
#include <stdexcept>
#include "results/basin_file.hpp"
#include "results/provenance.hpp"
#include "config/config.hpp"
#include "physics/parameter_table.hpp"
#include "physics/state_row.hpp"
#include "io/hdf5_file.hpp"
#include "results/brackets_file.hpp"
#include "results/sweep_result.hpp"
#include "sweep/orbit_classes.hpp"
#include "sweep/orbit_classifier.hpp"
#include "sweep/plan.hpp"
#include "sweep/task.hpp"

namespace ajx::results {

inline constexpr double kNotComputed = std::numeric_limits<double>::quiet_NaN();

// /chains/model holds one row per chain: every model parameter, in the order of the parameter
// table (physics/parameter_table.hpp), named with units in the dataset's "columns" attribute.
inline constexpr std::size_t kModelColumns = std::size(physics::kParameters);

// /chains/model read back by column name: each chain's parameters (the defaults where the file
// has no such column: files of format 1 hold the first 10 or 14 columns), with the names of
// the columns present and of the parameters the file lacks.
struct StoredModels {
  std::vector<physics::Parameters> chains;
  std::vector<std::string> present, lacking;
};
// `columns`: the names of /chains/model's columns ("drive_radius [m]", ...); `model` its rows.
StoredModels stored_models(const std::vector<std::string>& columns, const io::Array<double>& model);

// /tasks/status of a sweep file, per task.
enum class TaskStatus : std::int32_t {
  NeverRan = 0,  // no result yet (an interrupted sweep, or a task beyond --max-tasks)
  Ok = 1,
  Failed = 2,
  NotRun = 3,    // an earlier task of its chain failed, so its start state does not exist
};
inline constexpr const char* kTaskStatusNames = "0 never ran,1 ok,2 failed,3 not run (an earlier task of its chain failed)";

inline constexpr std::int32_t kMaxTaskStatus = 3;

// The sweep's file on rank 0, written while the sweep runs: every result dataset is made at
// the start, filled with "not computed" (NaN, class -1, status 0), and each finished task
// writes its windows and its final state and flushes. An interrupted sweep keeps all that.
class SweepFile {
 public:
  // One row of physics/state_row.hpp per task.
  static constexpr std::size_t kStateCols = physics::kStateCols;

  SweepFile(io::File file, std::size_t chains, std::size_t windows, std::size_t cap, std::size_t tasks)
      : f_(std::move(file)), C_(chains), W_(windows), cap_(cap), T_(tasks) {}
  // A new, empty file at `path` (truncated if there) sized for the plan; create() fills it.
  SweepFile(const std::filesystem::path& path, const sweep::SweepPlan& plan)
      : SweepFile(io::File::create(path), plan.setups.size(), plan.max_windows, plan.max_samples, plan.n_tasks) {}

  // A new file: the configuration, the layout and the empty result datasets.
  void create(const config::SweepConfig& cfg, const sweep::SweepPlan& plan) {
    const auto& spans = plan.spans;
    write_format(f_, "sweep");
    auto config = f_.write_string_dataset("config", cfg.source_text);
    config.set_attribute("source", cfg.source_name);
    config.set_attribute("overrides", std::span<const std::string>(cfg.overrides));
    write_resolved_parts(cfg);
    write_classes();
    write_chains(cfg, plan);
    write_window_layout(plan.setups);
    io::Group wg = f_.open_group("windows");
    const io::Dims dims{C_, W_}, chunk{chunk_rows(W_), W_};
    auto cls = wg.create_filled("class", dims, io::DType::Int32, -1.0, chunk);
    cls.set_attribute("description", "orbit class; -1 = not computed (the task never ran)");
    for (const auto& st : kStats) {
      auto d = wg.create_filled(st.name, dims, io::DType::Float64, kNotComputed, chunk);
      d.set_attribute("units", st.units);
      d.set_attribute("description", st.description);
    }
    for (const auto& st : kPowers) {
      auto d = wg.create_filled(st.name, dims, io::DType::Float64, kNotComputed, chunk);
      d.set_attribute("units", st.units);
      d.set_attribute("description", st.description);
    }
    wg.create_filled("mode_fraction", {C_, W_, kNumModes}, io::DType::Float64, kNotComputed,
                     {chunk_rows(W_ * kNumModes), W_, kNumModes})
        .set_attribute("description", "time fraction in modes 0 sliding, 1 bottom stop, 2 stuck, 3 top stop, 4 slack");
    io::Group sg = f_.create_group("samples");
    sg.set_attribute("sample_rate", cfg.sample_rate);
    sg.set_attribute("description", "every window's samples, padded with NaN beyond count; t float64, the others float32");
    sg.set_attribute("format_version", std::int64_t(kSampleFormatVersion));
    sg.create_filled("count", dims, io::DType::Int32, 0.0, chunk);
    // One chunk per window: the workers compress it (sweep_result.hpp), the master stores it.
    for (std::size_t k = 0; k < kNumSampleColumns; ++k) {
      const io::DType type = kSampleFloat32[k] ? io::DType::Float32 : io::DType::Float64;
      if (k < 6)
        sg.create_filled(kSampleColumns[k], {C_, W_, cap_}, type, kNotComputed, {1, 1, cap_}, kSampleDeflate);
      else
        sg.create_filled(kSampleColumns[k], {C_, W_, cap_, 3}, type, kNotComputed, {1, 1, cap_, 3}, kSampleDeflate);
    }
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
        .set_attribute("names", kTaskStatusNames);
    tg.create_filled("steps", {T_}, io::DType::Int64, 0.0, {T_});
    tg.create_filled("final_state", {T_, kStateCols}, io::DType::Float64, kNotComputed, {chunk_rows(kStateCols), kStateCols})
        .set_attribute("columns", std::span<const std::string>(physics::state_column_names()));
    write_basin_layout(f_, cfg, plan);
    brackets_.emplace(plan);
    create_brackets(f_, plan, *brackets_);
    f_.flush();
  }

  // An existing file, to resume: it must come from the same configuration.
  void check_same(const config::SweepConfig& cfg) const {
    const io::Dataset config = f_.open_dataset("config");
    if (config.read_string() != cfg.source_text || config.read_strings_attribute("overrides") != cfg.overrides)
      throw config::ConfigError(fmt::format(
          "{}: key 'output.path': {} was written by a different sweep file or overrides; resume it with the same "
          "ones, or remove it to start afresh",
          cfg.source_name, f_.disk_path().string()));
  }

  // Read back from the file: results still waiting in memory must have been written (write_pending).
  std::vector<TaskStatus> status() const {
    check_nothing_pending();
    std::vector<TaskStatus> out;
    for (std::int32_t v : f_.read_int32s("tasks/status").data) out.push_back(TaskStatus(v));
    return out;
  }
  physics::State state(std::size_t task) const {
    check_nothing_pending();
    const auto all = f_.read_doubles("tasks/final_state");
    return physics::state_from_row(std::span<const double>(&all.data[task * kStateCols], kStateCols));
  }

  // A task's result waits in memory until the next flush (at most kFlushInterval), then goes to
  // the file with the results around it: one write per dataset for every run of neighbouring
  // tasks instead of some thirty per task (write_pending). Nothing is lost by the wait: the sweep
  // journal holds every result before it reaches here.
  void write_not_run(std::size_t task) {
    pending_.push_back(Pending{task, 0, std::int32_t(TaskStatus::NotRun), 0, {}, {}});
    flush_due();
  }

  void write_task(std::size_t task, std::size_t chain, const TaskResult& result) {
    const std::vector<WindowResult>& windows = result.windows;
    for (std::size_t i = 1; i < windows.size(); ++i)
      if (windows[i].index != windows[0].index + std::int32_t(i)) throw io::Hdf5Error("sweep file: a task's windows are not consecutive");
    if (result.probe) {
      if (!brackets_ || brackets_->probe_row.at(task) < 0) throw io::Hdf5Error("sweep file: a probe's result for a task that is not a probe");
      write_probe([this](const std::string& p) -> io::Dataset& { return ds(p); }, *brackets_, task, chain, *result.probe);
    }
    const sweep::TaskOutput& out = result.summary;
    pending_.push_back(Pending{task, chain, std::int32_t(out.ok ? TaskStatus::Ok : TaskStatus::Failed), out.steps,
                               physics::state_row(out.final_state), windows});
    flush_due();
  }

  // Every result waiting in memory written to the file (done by each flush, finish and close).
  void write_pending() {
    if (pending_.empty()) return;
    // Stable: a task committed twice (a resume's replay) keeps its last result, as written in order.
    std::stable_sort(pending_.begin(), pending_.end(), [](const Pending& a, const Pending& b) { return a.task < b.task; });
    const auto next_task = [](const Pending& a, const Pending& b) { return b.task == a.task + 1; };
    for_runs(pending_, next_task, [&](const Pending* p, std::size_t n) {
      std::vector<std::int32_t> st(n);
      for (std::size_t i = 0; i < n; ++i) st[i] = p[i].status;
      ds("tasks/status").write_region({p->task}, {n}, std::span<const std::int32_t>(st));
    });
    std::vector<Pending> ran;  // the tasks with a final state and windows (not "not run")
    for (Pending& p : pending_)
      if (p.status != std::int32_t(TaskStatus::NotRun)) ran.push_back(std::move(p));
    pending_.clear();
    for_runs(ran, next_task, [&](const Pending* p, std::size_t n) {
      std::vector<std::int64_t> steps(n);
      std::vector<double> rows;
      for (std::size_t i = 0; i < n; ++i) {
        steps[i] = p[i].steps;
        rows.insert(rows.end(), p[i].state.begin(), p[i].state.end());
      }
      ds("tasks/steps").write_region({p->task}, {n}, std::span<const std::int64_t>(steps));
      ds("tasks/final_state").write_region({p->task, 0}, {n, kStateCols}, std::span<const double>(rows));
    });
    std::erase_if(ran, [](const Pending& p) { return p.windows.empty(); });
    // Blocks of /windows: one task's windows, or the same windows of tasks on consecutive chains.
    const auto below = [](const Pending& a, const Pending& b) {
      return b.chain == a.chain + 1 && b.windows.front().index == a.windows.front().index &&
             b.windows.size() == a.windows.size();
    };
    for_runs(ran, below, [&](const Pending* p, std::size_t n) { write_windows(p, n); });
  }
  // Failures of this run join those of earlier runs of the same sweep (one line each, sorted).
  void finish(std::vector<std::string> failures, const SweepRunRecord& run) {
    io::Group tg = f_.open_group("tasks");
    if (tg.has_attribute("failures"))
      for (std::string& old : tg.read_strings_attribute("failures")) failures.push_back(std::move(old));
    std::sort(failures.begin(), failures.end());
    failures.erase(std::unique(failures.begin(), failures.end()), failures.end());
    tg.set_attribute("failures", std::span<const std::string>(failures));
    write_pending();
    write_basin_results(f_);  // the fractions of the samples done
    io::Group prov = f_.require_group("provenance");
    write_run_record(prov, run);
    close();
  }

  // Writes what waits, closes the datasets held open for writing, then the file.
  void close() {
    write_pending();
    open_.clear();
    f_.close();
  }

 private:
  // The file is flushed at most every kFlushInterval, not after every task: a flush writes the
  // HDF5 metadata, most of the master's cost per result when results come fast (10^4 short
  // chains). Nothing is lost: the sweep journal holds every result before it is written here,
  // and a resume commits the journal's records again (onto a new .part if this one cannot be
  // read). The file closes, flushed, when the sweep finishes or is interrupted.
  static constexpr std::chrono::milliseconds kFlushInterval{1000};
  void flush_due() {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_flush_ < kFlushInterval) return;
    write_pending();
    f_.flush();
    last_flush_ = now;
  }
  std::chrono::steady_clock::time_point last_flush_ = std::chrono::steady_clock::now();

  // A result not written yet (write_task, write_not_run).
  struct Pending {
    std::size_t task = 0, chain = 0;
    std::int32_t status = 0;
    std::int64_t steps = 0;
    std::vector<double> state;  // the final state's row
    std::vector<WindowResult> windows;
  };
  std::vector<Pending> pending_;
  void check_nothing_pending() const {
    if (!pending_.empty()) throw std::logic_error("sweep file: read back with results not written yet (write_pending)");
  }

  // fn(first, n) for each run of items where every item follows the one before (joined(a, b)).
  template <class Joined, class Fn>
  static void for_runs(const std::vector<Pending>& items, const Joined& joined, const Fn& fn) {
    for (std::size_t b = 0, e = 0; b < items.size(); b = e) {
      for (e = b + 1; e < items.size() && joined(items[e - 1], items[e]); ++e) {
      }
      fn(&items[b], e - b);
    }
  }

  // Rows per chunk of a dataset whose rows hold `row` values: chunks of about 4096 values, so
  // that a sweep of many short chains (one window each) does not store, index and checksum a
  // chunk per value; a chain of hundreds of windows keeps a few rows per chunk.
  std::size_t chunk_rows(std::size_t row) const { return std::max<std::size_t>(1, 4096 / std::max<std::size_t>(row, 1)); }

  // /classes: the orbit classes' table (sweep/orbit_classes.hpp), indexed by class code.
  void write_classes() {
    io::Group g = f_.create_group("classes");
    g.set_attribute("description", "the orbit classes, indexed by the class code of /windows/class");
    std::vector<std::string> name, description, colour;
    std::vector<std::int8_t> circular;
    for (const sweep::OrbitClassInfo& c : sweep::kOrbitClasses) {
      name.emplace_back(c.name);
      description.emplace_back(c.description);
      colour.emplace_back(c.colour);
      circular.push_back(c.circular ? 1 : 0);
    }
    g.write_dataset("name", std::span<const std::string>(name));
    g.write_dataset("circular", std::span<const std::int8_t>(circular))
        .set_attribute("description", "1 for a circular orbit, else 0");
    g.write_dataset("description", std::span<const std::string>(description));
    g.write_dataset("colour", std::span<const std::string>(colour)).set_attribute("description", "#rrggbb in every figure");
  }

  void write_chains(const config::SweepConfig& cfg, const sweep::SweepPlan& plan) {
    io::Group cg = f_.create_group("chains");
    const std::vector<std::string>& names = plan.axes;
    cg.set_attribute("axes", std::span<const std::string>(names));
    std::vector<double> values, model;
    for (const auto& g : plan.points) {
      values.insert(values.end(), g.values.begin(), g.values.end());
      const physics::Parameters& p = g.model.p;
      const auto row = physics::parameter_row(p);
      model.insert(model.end(), row.begin(), row.end());
    }
    if (!names.empty())
      cg.write_dataset("grid_values", std::span<const double>(values), io::Dims{C_, names.size()})
          .set_attribute("description", "each chain's value on each grid axis; NaN where its group has no such axis");
    cg.write_dataset("model", std::span<const double>(model), io::Dims{C_, kModelColumns})
        .set_attribute("columns", std::span<const std::string>(physics::parameter_column_names()));
    if (!cfg.parts.empty()) write_groups(cfg, plan);
    if (cfg.hold) write_holds(cfg, plan);
  }

  // The configuration in force as values (provenance.hpp): /resolved for a plain file; for a
  // file of parts, /resolved/0, /1, ... one per (group, variant) with its names, and
  // /chains/part saying which a chain ran. A [grid] axis sets its chains' parameters, which
  // /chains/model holds.
  void write_resolved_parts(const config::SweepConfig& cfg) {
    io::Group rg = f_.create_group("resolved");
    if (cfg.parts.empty()) return write_resolved(rg, cfg);
    for (std::size_t i = 0; i < cfg.parts.size(); ++i) {
      io::Group pg = rg.create_group(fmt::format("{}", i));
      pg.set_attribute("group", cfg.parts[i].group);
      pg.set_attribute("variant", cfg.parts[i].variant);
      write_resolved(pg, cfg.parts[i]);
    }
  }

  // A grouped file: each chain's group and model variant, by index into the names (attributes
  // `names`, and `purposes` or `labels`, one line each), and where it starts.
  void write_groups(const config::SweepConfig& cfg, const sweep::SweepPlan& plan) {
    std::vector<std::string> groups, purposes, variants, labels, seeds;
    const auto index = [](std::vector<std::string>& list, const std::string& name) {
      auto it = std::find(list.begin(), list.end(), name);
      if (it == list.end()) it = list.insert(list.end(), name);
      return std::int32_t(it - list.begin());
    };
    std::vector<std::int32_t> group, variant, seed, part_of;
    std::vector<double> omega;
    for (std::size_t c = 0; c < C_; ++c) {
      const config::SweepConfig& part = cfg.parts[plan.part[c]];
      part_of.push_back(std::int32_t(plan.part[c]));
      const std::size_t g = groups.size();
      group.push_back(index(groups, part.group));
      if (groups.size() > g) purposes.push_back(part.group_purpose);
      const std::size_t v = variants.size();
      variant.push_back(index(variants, part.variant));
      if (variants.size() > v) labels.push_back(part.variant_label);
      seed.push_back(index(seeds, plan.starts[c].seed));
      omega.push_back(plan.starts[c].omega);
    }
    io::Group cg = f_.open_group("chains");
    auto gd = cg.write_dataset("group", std::span<const std::int32_t>(group));
    gd.set_attribute("names", std::span<const std::string>(groups));
    gd.set_attribute("purposes", std::span<const std::string>(purposes));
    auto vd = cg.write_dataset("variant", std::span<const std::int32_t>(variant));
    vd.set_attribute("names", std::span<const std::string>(variants));
    vd.set_attribute("labels", std::span<const std::string>(labels));
    cg.write_dataset("start_seed", std::span<const std::int32_t>(seed))
        .set_attribute("names", std::span<const std::string>(seeds));
    cg.write_dataset("start_omega", std::span<const double>(omega)).set_attribute("units", "rad/s");
    cg.write_dataset("part", std::span<const std::int32_t>(part_of))
        .set_attribute("description", "the (group, variant) part each chain ran: its configuration is /resolved/<part>");
  }

  // A hold sweep: which ω_m, seed and perturbation each chain holds.
  void write_holds(const config::SweepConfig& cfg, const sweep::SweepPlan& plan) {
    std::vector<double> w;
    std::vector<std::int32_t> seed, pert;
    const std::vector<std::string>& seeds = cfg.hold->seeds;
    for (const sweep::ChainStart& s : plan.starts) {
      w.push_back(s.omega);
      seed.push_back(std::int32_t(std::find(seeds.begin(), seeds.end(), s.seed) - seeds.begin()));
      pert.push_back(s.perturbation);
    }
    io::Group cg = f_.open_group("chains");
    cg.write_dataset("hold_omega", std::span<const double>(w)).set_attribute("units", "rad/s");
    cg.write_dataset("seed", std::span<const std::int32_t>(seed)).set_attribute("names", std::span<const std::string>(seeds));
    cg.write_dataset("perturbation", std::span<const std::int32_t>(pert))
        .set_attribute("description", "0: the seed itself; k >= 1: the seed with velocity kick k");
  }

  void write_window_layout(const std::vector<sweep::ChainSetup>& setups) {
    io::Group wg = f_.create_group("windows");
    std::vector<double> tb(C_ * W_, kNotComputed), te(C_ * W_, kNotComputed), wb(C_ * W_, kNotComputed), we(C_ * W_, kNotComputed);
    std::vector<double> phase(C_ * W_, kNotComputed);
    std::vector<std::int32_t> dir(C_ * W_, 0), seg(C_ * W_, -1);
    for (std::size_t c = 0; c < C_; ++c) {
      if (setups[c].protocol.windows.empty()) continue;  // a bisection: its probes are in /brackets
      const physics::MotorSchedule motor = setups[c].motor();
      for (std::size_t k = 0; k < setups[c].protocol.windows.size(); ++k) {
        const auto& w = setups[c].protocol.windows[k];
        const std::size_t i = c * W_ + k;
        double omega = 0.0, omega_dot = 0.0;
        motor.phase(w.t_begin, phase[i], omega, omega_dot);
        tb[i] = w.t_begin;
        te[i] = w.t_end;
        wb[i] = w.omega_begin;
        we[i] = w.omega_end;
        dir[i] = w.direction;
        seg[i] = w.segment;
      }
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
    put("phi_begin", phase, "rad", "motor phase φ at the window start; inside the window φ = phi_begin + ∫ω_m dt");
    wg.write_dataset("direction", std::span<const std::int32_t>(dir), dims)
        .set_attribute("description", "+1 ω_m rising, -1 falling (ramp or staircase), 0 a single held level");
    wg.write_dataset("segment", std::span<const std::int32_t>(seg), dims)
        .set_attribute("description", "protocol segment index");
  }

  // The windows of n tasks (p[0 .. n-1]): one task's consecutive windows, or the same windows of
  // tasks on consecutive chains; their rows of /windows and /samples/count in one write per
  // dataset, and each window's sample chunks as the worker made them.
  void write_windows(const Pending* p, std::size_t n) {
    const std::size_t chain = p->chain, first = std::size_t(p->windows.front().index), m = p->windows.size();
    std::vector<WindowRow> rows;
    std::vector<std::int32_t> count;
    for (std::size_t t = 0; t < n; ++t)
      for (const WindowResult& w : p[t].windows) {
        rows.push_back(w.row);
        count.push_back(w.count);
      }
    write_rows(chain, first, rows, n);
    std::vector<double> column(rows.size());
    for (std::size_t k = 0; k < kNumPowers; ++k) {
      std::size_t i = 0;
      for (std::size_t t = 0; t < n; ++t)
        for (const WindowResult& w : p[t].windows) column[i++] = w.powers[k];
      ds(std::string("windows/") + kPowers[k].name).write_region({chain, first}, {n, m}, std::span<const double>(column));
    }
    ds("samples/count").write_region({chain, first}, {n, m}, std::span<const std::int32_t>(count));
    for (std::size_t t = 0; t < n; ++t)
      for (const WindowResult& w : p[t].windows)
        for (std::size_t k = 0; k < w.chunks.size(); ++k)
          ds(std::string("samples/") + kSampleColumns[k])
              .write_chunk(k < 6 ? io::Dims{p[t].chain, std::size_t(w.index), 0} : io::Dims{p[t].chain, std::size_t(w.index), 0, 0},
                           w.chunks[k]);
  }

 public:
  // Rows of /windows for consecutive windows from `first` (also what astrojax classify rewrites);
  // with `chains` > 1, the same windows of that many consecutive chains from `chain`, row by row.
  void write_rows(std::size_t chain, std::size_t first, std::span<const WindowRow> rows, std::size_t chains = 1) {
    const std::size_t n = rows.size();
    if (n == 0) return;
    const io::Dims at{chain, first}, block{chains, n / chains};
    std::vector<std::int32_t> cls(n);
    std::vector<double> column(n), modes(kNumModes * n);
    for (std::size_t i = 0; i < n; ++i) {
      cls[i] = rows[i].cls;
      std::copy(rows[i].mode_fraction.begin(), rows[i].mode_fraction.end(), modes.begin() + long(kNumModes * i));
    }
    ds("windows/class").write_region(at, block, std::span<const std::int32_t>(cls));
    for (std::size_t k = 0; k < kNumStats; ++k) {
      for (std::size_t i = 0; i < n; ++i) column[i] = rows[i].stats[k];
      ds(std::string("windows/") + kStats[k].name).write_region(at, block, std::span<const double>(column));
    }
    ds("windows/mode_fraction").write_region({chain, first, 0}, {chains, n / chains, kNumModes}, std::span<const double>(modes));
  }

  io::File& file() { return f_; }

 private:
  // The result datasets stay open while the sweep writes them: opening and closing one per
  // window costs more than the write (closing a chunked dataset also flushes its chunk cache).
  io::Dataset& ds(const std::string& path) {
    auto it = open_.find(path);
    if (it == open_.end()) it = open_.emplace(path, f_.open_dataset(path)).first;
    return it->second;
  }

  io::File f_;
  std::map<std::string, io::Dataset> open_;
  std::optional<BracketsLayout> brackets_;  // set by create()
  std::size_t C_, W_, cap_, T_;
};

}  // namespace ajx::results
