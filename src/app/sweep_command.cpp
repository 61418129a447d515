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
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "app/progress.hpp"
#include "app/output_paths.hpp"
#include "results/sweep_file.hpp"
#include "results/sweep_recovery.hpp"
#include "results/sweep_result.hpp"
#include "config/config.hpp"
#include "io/hdf5_file.hpp"
#include "io/journal.hpp"
#include "numerics/stepper.hpp"
#include "parallel/farm.hpp"
#include "parallel/mpi_env.hpp"
#include "parallel/signals.hpp"
#include "sim/paper_scheme.hpp"
#include "sim/simulation.hpp"
#include "sweep/bisection.hpp"
#include "sweep/codec.hpp"
#include "sweep/orbit_classifier.hpp"
#include "sweep/plan.hpp"
#include "sweep/task.hpp"

namespace ajx::app {

namespace {

// Without --task-timeout, a task still out after this many times the slowest finished task (and
// at least --min-task-timeout) is taken as hung: its rank is given up and the task runs elsewhere.
constexpr double kTaskTimeoutFactor = 20.0;
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

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

// --dry-run: what the sweep would do, per chain group and variant, and in all.
void print_plan(const config::SweepConfig& cfg, const sweep::SweepPlan& plan) {
  struct Part {
    std::size_t chains = 0, tasks = 0, windows = 0;
    double simulated = 0.0;
  };
  std::vector<Part> parts(std::max<std::size_t>(cfg.parts.size(), 1));
  std::size_t windows = 0;
  for (std::size_t c = 0; c < plan.chains(); ++c) {
    Part& p = parts[plan.part[c]];
    ++p.chains;
    p.tasks += plan.spans[c].size();
    p.windows += plan.setups[c].protocol.windows.size();
    p.simulated += plan.setups[c].protocol.duration;
    windows += plan.setups[c].protocol.windows.size();
  }
  std::printf("plan of %s -> %s\n", cfg.source_name.c_str(), cfg.output_path.c_str());
  if (!cfg.parts.empty()) {
    std::printf("  %-12s %-12s %8s %8s %8s %14s\n", "group", "variant", "chains", "tasks", "windows", "simulated [s]");
    for (std::size_t i = 0; i < parts.size(); ++i)
      std::printf("  %-12s %-12s %8zu %8zu %8zu %14.0f\n", cfg.parts[i].group.c_str(), cfg.parts[i].variant.c_str(),
                  parts[i].chains, parts[i].tasks, parts[i].windows, parts[i].simulated);
  }
  // The rate of the main job, sweeps/paper.toml (27 649 simulated s in about 17 s of CPU with
  // dop853 at rtol 1e-9): a rough guide only; climbs, flowers and tight tolerances cost more.
  constexpr double kSimulatedPerCpuSecond = 1600.0;
  std::printf("  in all: %zu chains, %zu tasks, %zu windows of up to %zu samples, %.0f simulated s; "
              "about %.0f s of CPU at the main job's rate (%.0f simulated s per CPU s)\n",
              plan.chains(), plan.n_tasks, windows, plan.max_samples, plan.total_duration,
              plan.total_duration / kSimulatedPerCpuSecond, kSimulatedPerCpuSecond);
}

// ---- parse ----------------------------------------------------------------------------------

// Every rank parses the same file: the chains are then known everywhere and only task ids,
// states and results travel. Returns the error (empty: none); rank 0 reports it, all ranks
// stop on it.
std::string parse_sweep(const SweepArgs& args, config::SweepConfig& cfg, sweep::SweepPlan& plan) {
  try {
    cfg = config::load_sweep_config(args.config_path, args.overrides);
    if (!args.output.empty()) cfg.output_path = args.output;
    if (cfg.initial.preset != "hanging")
      throw config::ConfigError(fmt::format("{}: key 'initial.preset': sweeps start every chain from 'hanging'",
                                            cfg.source_name));
    if (sim::paper_variant(cfg.run.method))
      throw config::ConfigError(fmt::format("{}: key 'integrator.method': the paper's two-step scheme runs with "
                                            "`astrojax run` only; allowed here: {}", cfg.source_name,
                                            numerics::stepper_names()));
    plan = config::make_plan(cfg);  // chains, each split into tasks on window boundaries
    results::check_sweep_memory(cfg, plan, args.max_memory);
  } catch (const config::ConfigError& e) {
    return e.what();
  }
  return {};
}

// ---- the output: the file, the journal and the tasks' status (rank 0) -----------------------

// Rank 0 opens the file: "<path>.part" while the sweep runs, renamed to <path> when every
// task has finished. --resume reopens the .part of an interrupted sweep. Every result goes
// first to the journal "<path>.journal" and then into the .part: a resume replays the
// journal onto the .part, or onto a new one when the old cannot be read (killed mid-write).
struct SweepOutput {
  const SweepArgs& args;
  const config::SweepConfig& cfg;
  const sweep::SweepPlan& plan;
  const std::filesystem::path final_path, part_path, journal_path;
  std::optional<results::SweepFile> file;
  std::optional<io::Journal> journal;
  io::JournalContents replay;
  std::vector<results::TaskStatus> status;  // per task
  std::vector<std::string> failures;
  double skipped = 0.0;  // simulated seconds of settling not integrated, the orbit known [s]
  std::map<std::size_t, std::vector<std::byte>> probe_carry;  // per finished bisection probe: the next one's carry

  SweepOutput(const SweepArgs& a, const config::SweepConfig& c, const sweep::SweepPlan& p)
      : args(a), cfg(c), plan(p), final_path(c.output_path), part_path(c.output_path + ".part"),
        journal_path(c.output_path + ".journal") {}

  void make_file() {
    file.emplace(part_path, plan);
    file->create(cfg, plan);
  }

  // --resume: the journal checked and reopened, the .part made again from the sweep file.
  void open_resume() {
    if (!std::filesystem::exists(part_path) && !std::filesystem::exists(journal_path)) {
      throw config::ConfigError(fmt::format(
          "{}: key 'output.path': nothing to resume: {} does not exist{}", cfg.source_name, part_path.string(),
          std::filesystem::exists(final_path) ? fmt::format(" ({} is complete)", final_path.string()) : ""));
    }
    // Only the journal is trusted: its records carry CRC-32s, while a byte of the .part may have
    // flipped anywhere (a carried state, /chains, a sample chunk) without HDF5 noticing.
    if (!std::filesystem::exists(journal_path))
      throw config::ConfigError(fmt::format(
          "{}: key 'output.path': {} has no journal {}, so what it holds cannot be checked; start afresh with "
          "--force", cfg.source_name, part_path.string(), journal_path.string()));
    // Locked (no other sweep writes it), and checked before its damage, if any, is cut away.
    journal.emplace(io::Journal::open_append(journal_path, [&](const io::JournalContents& c) {
      results::check_journal_identity(cfg, journal_path, c);
    }));
    replay = std::move(journal->found());
    if (replay.records.empty())  // killed before its first record
      journal->append(results::kJournalIdentity, results::journal_identity(cfg));
    results::report_journal_damage(journal_path, replay);
    // Every dataset made again from the sweep file, and every result from the journal (below).
    std::printf("%s rebuilt from the sweep file and %s (%zu checksummed results)\n", part_path.c_str(),
                journal_path.c_str(), replay.records.empty() ? 0 : replay.records.size() - 1);
    std::filesystem::remove(part_path);
    make_file();
    status.assign(plan.n_tasks, results::TaskStatus::NeverRan);  // the journal's replay below says what is done
  }

  // Rank 0: the output checked and opened (afresh or resumed). Returns the error (empty: none).
  std::string open() {
    try {
      check_output_path(cfg.source_name, "output.path", cfg.output_path, {args.config_path}, {".part", ".journal"});
      // A sweep running on this output holds its journal's lock: said first, --resume or not.
      if (io::Journal::in_use(journal_path))
        throw config::ConfigError(fmt::format("{}: key 'output.path': {} is in use by another running sweep (wait for "
                                              "it to end, or end it)", cfg.source_name, journal_path.string()));
      if (!args.resume) check_not_overwriting(cfg.source_name, "output.path", cfg.output_path, args.force);
      if (!args.resume && !args.force) results::check_no_unfinished_sweep(cfg, part_path, journal_path);
      if (args.resume) {
        open_resume();
      } else {
        results::check_space(cfg, final_path, plan.setups, plan.max_samples);
        std::error_code ec;
        if (final_path.has_parent_path()) std::filesystem::create_directories(final_path.parent_path(), ec);
        journal.emplace(io::Journal::create(journal_path));  // locked first: no other sweep writes here
        make_file();
        journal->append(results::kJournalIdentity, results::journal_identity(cfg));
        status.assign(plan.n_tasks, results::TaskStatus::NeverRan);
      }
    } catch (const io::Hdf5Error& e) {
      return fmt::format("{}: key 'output.path': cannot write '{}' ({})", cfg.source_name, part_path.string(), e.what());
    } catch (const io::JournalError& e) {
      return fmt::format("{}: key 'output.path': {}", cfg.source_name, e.what());
    } catch (const config::ConfigError& e) {
      return e.what();
    }
    return {};
  }

  // One result into the file (the journal holds it already): the windows as the worker
  // classified and compressed them (sweep_result.hpp), written and flushed. The record's kind
  // (results::RecordKind) says what follows it. Returns the simulated seconds of the task.
  double commit(std::size_t id, std::span<const std::byte> record) {
    const auto& first_task = plan.first_task;
    using results::RecordKind;
    if (record.empty() || RecordKind(record[0]) == RecordKind::NotRun) {
      status[id] = results::TaskStatus::NotRun;
      file->write_not_run(id);
      return 0.0;
    }
    const std::size_t chain = std::size_t(std::upper_bound(first_task.begin(), first_task.end(), id) - first_task.begin()) - 1;
    results::TaskResult result;
    sweep::TaskOutput& out = result.summary;
    if (RecordKind(record[0]) == RecordKind::FailedWithoutOutput) {
      out.ok = false;
      out.failure.assign(reinterpret_cast<const char*>(record.data() + 1), record.size() - 1);
      out.final_state.t = nan;
      out.final_state.y.setConstant(nan);
    } else {
      result = results::decode_result(record.subspan(1));
    }
    if (result.probe) probe_carry[id] = result.probe->carry;
    status[id] = out.ok ? results::TaskStatus::Ok : results::TaskStatus::Failed;
    if (!out.ok) failures.push_back(fmt::format("task {} (chain {}, part {}): {}", id, chain, id - first_task[chain], out.failure));
    file->write_task(id, chain, result);  // written (flushed at most every second: the journal has it)
    skipped += out.skipped;
    return out.simulated;  // [s]
  }

  // --resume: every journal record committed again, onto a new .part when the old cannot be written.
  void replay_journal() {
    const auto replay_all = [&] {
      for (std::size_t k = 1; k < replay.records.size(); ++k) {
        const std::int64_t id = replay.records[k].key;
        if (id < 0 || std::size_t(id) >= plan.n_tasks)
          throw io::JournalError(fmt::format("{}: record {} names task {} of {}", journal_path.string(), k, id, plan.n_tasks));
        commit(std::size_t(id), replay.records[k].payload);
      }
      file->write_pending();  // a .part that cannot be written says so here, and is rebuilt
    };
    try {
      replay_all();
    } catch (const io::Hdf5Error& e) {
      std::fprintf(stderr, "warning: %s cannot be written (%s); rebuilding it from %s\n", part_path.c_str(), e.what(),
                   journal_path.c_str());
      file.reset();
      std::filesystem::remove(part_path);
      make_file();
      status.assign(plan.n_tasks, results::TaskStatus::NeverRan);
      failures.clear();
      replay_all();
    }
  }
};

// ---- plan: the chains still to run (rank 0) --------------------------------------------------

// Each chain from its first task that never ran, with the state its predecessor left (stored
// in the file); chains that finished or failed are done. done_sim: the simulated seconds of
// the tasks already done.
std::vector<parallel::Chain> chains_to_run(const SweepOutput& output, double& done_sim) {
  const sweep::SweepPlan& plan = output.plan;
  const auto& spans = plan.spans;
  const auto& first_task = plan.first_task;
  const auto& status = output.status;
  std::vector<parallel::Chain> chains;
  for (std::size_t c = 0; c < plan.setups.size(); ++c) {
    std::size_t k = 0;
    while (k < spans[c].size() && status[first_task[c] + k] == results::TaskStatus::Ok) ++k;
    if (k > 0 && !plan.bisect[c]) done_sim += spans[c][k - 1].t_end;  // a probe's times are not planned
    if (k == spans[c].size() || status[first_task[c] + k] != results::TaskStatus::NeverRan) continue;
    parallel::Chain ch;
    ch.id = std::int64_t(c);
    if (plan.bisect[c])  // probe 0 starts from the seed; a later one from the carry its predecessor left
      ch.carry = k == 0 ? sweep::encode(sweep::BisectCarry{}) : output.probe_carry.at(first_task[c] + k - 1);
    else
      ch.carry = sweep::encode(k == 0 ? plan.start_state(c) : output.file->state(first_task[c] + k - 1));
    for (std::size_t j = k; j < spans[c].size(); ++j) {
      sweep::ByteWriter w;
      w.put<std::int64_t>(std::int64_t(c));
      w.put<std::int64_t>(std::int64_t(j));
      ch.tasks.push_back({std::int64_t(first_task[c] + j), ch.id, std::int64_t(j), w.take()});
    }
    chains.push_back(std::move(ch));
  }
  return chains;
}

// ---- execute: the farm ------------------------------------------------------------------------

// The work: decode (chain, span), integrate, return the windows and the carry.
parallel::WorkFunction task_work(const sweep::SweepPlan& plan) {
  return [&plan](const parallel::Task& task, const parallel::Bytes& carry) {
    const auto& setups = plan.setups;
    sweep::ByteReader r(task.input.data(), task.input.size());
    const auto chain = std::size_t(r.get<std::int64_t>());
    const auto span = std::size_t(r.get<std::int64_t>());
    if (const auto& b = plan.bisect[chain]) {  // a bisection's probe: one held level
      const sweep::ChainSetup& c = setups[chain];
      sweep::Probe probe = sweep::run_probe(*b, c.model, c.run, c.sample_rate, int(span), sweep::decode_carry(carry));
      parallel::Outcome o;
      o.ok = probe.out.ok;
      o.error = probe.out.failure;
      o.carry = sweep::encode(probe.next);
      o.output = results::encode(results::probe_result(std::move(probe)));
      return o;
    }
    sweep::TaskOutput out = sweep::run_task(setups[chain], plan.spans[chain][span], sweep::decode_state(carry));
    parallel::Outcome o;
    o.ok = out.ok;
    o.error = out.failure;
    o.carry = sweep::encode(out.final_state);
    o.output = results::encode(results::make_result(setups[chain], std::move(out), plan.max_samples));  // classified and compressed here
    return o;
  };
}

// The simulated seconds: done before this job, done so far, in all.
struct SimulatedSeconds {
  double done_before = 0.0, done = 0.0, total = 0.0;
};

// The farm's options: each result journalled and committed on rank 0 (stopping after
// --max-tasks), the progress line, the task time bounds.
parallel::FarmOptions farm_options(const SweepArgs& args, SweepOutput& output, SimulatedSeconds& sim,
                                   std::atomic<bool>& stop, long& results, bool terminal) {
  parallel::FarmOptions fo;
  fo.stop = &stop;
  fo.on_result = [&args, &output, &sim, &stop, &results](const parallel::TaskResult& r) {
    if (args.max_tasks > 0 && ++results >= args.max_tasks) stop = true;
    const auto id = std::size_t(r.task_id);
    const bool no_output = r.ran && !r.ok && r.output.empty();
    using results::RecordKind;
    parallel::Bytes record{std::byte(!r.ran ? RecordKind::NotRun : no_output ? RecordKind::FailedWithoutOutput : RecordKind::Ran)};
    if (no_output)
      record.insert(record.end(), reinterpret_cast<const std::byte*>(r.error.data()),
                    reinterpret_cast<const std::byte*>(r.error.data() + r.error.size()));
    else if (r.ran)
      record.insert(record.end(), r.output.begin(), r.output.end());
    output.journal->append(r.task_id, record);  // committed: a resume replays it
    sim.done += output.commit(id, record);
  };
  fo.on_progress = [&args, &sim, terminal](const parallel::Progress& p) {
    if (args.quiet) return;
    const double elapsed = p.elapsed_seconds;
    const double rate = elapsed > 0 ? (sim.done - sim.done_before) / elapsed : 0.0;
    const double eta = rate > 0 ? (sim.total - sim.done) / rate : nan;
    const double share = sim.total > 0 ? sim.done / sim.total : 1.0;
    std::printf("%s%s%s", terminal ? "\r" : "",
                progress_line(p.done, p.total, p.failed, share, rate, eta, terminal).c_str(), terminal ? "   " : "\n");
    std::fflush(stdout);
  };
  fo.progress_interval = terminal ? 0.5 : 10.0;
  fo.task_timeout = args.task_timeout;
  fo.timeout_factor = kTaskTimeoutFactor;  // without --task-timeout: a task this many times the slowest is hung
  fo.min_task_timeout = args.min_task_timeout;
  fo.threads = args.threads;
  return fo;
}

// ---- report -----------------------------------------------------------------------------------

results::SweepRunRecord run_record(const SweepArgs& args, int ranks, const std::string& started, double wall,
                                   const parallel::FarmSummary& fs) {
  char host[256] = "?";
  gethostname(host, sizeof host - 1);
  results::SweepRunRecord r{args.command_line, std::string(host), ranks, args.resume, started, now_iso(), wall,
                            std::string(parallel::to_string(fs.status)), fs.tasks_per_second, fs.bytes_sent,
                            fs.bytes_received, 0.0, fs.result_seconds};
  for (double b : fs.busy_seconds) r.work_seconds += b;
  r.threads = args.threads;
  r.master_cpu_seconds = fs.master_cpu_seconds;
  return r;
}

// Rank 0 after the farm: the file finished (and renamed when complete), the summary line, the
// failures; returns the job's exit code.
int report_sweep(const SweepArgs& args, SweepOutput& output, const parallel::FarmSummary& fs,
                 const SimulatedSeconds& sim, const std::string& started, double wall, int ranks) {
  std::vector<std::string>& failures = output.failures;
  const std::vector<results::TaskStatus>& status = output.status;
  const std::filesystem::path &final_path = output.final_path, &part_path = output.part_path;
  std::sort(failures.begin(), failures.end());
  results::SweepRunRecord record = run_record(args, ranks, started, wall, fs);
  record.settle_seconds_skipped = output.skipped;  // [s] of every run of the sweep (resumes included)
  output.file->finish(failures, record);
  const bool complete = std::none_of(status.begin(), status.end(), [](results::TaskStatus v) { return v == results::TaskStatus::NeverRan; });
  if (complete) {
    std::filesystem::rename(part_path, final_path);
    // The file holds everything now. The journal goes while still locked: released first, a
    // resume started in between would find it unlocked beside the finished file and redo it.
    std::filesystem::remove(output.journal_path);
    output.journal.reset();
  }

  // The settling the early stop skipped (sim/settle_watch.hpp), when there was any.
  const std::string skipped =
      output.skipped > 0 ? fmt::format(" ({:.0f} s of settling skipped, the orbit known)", output.skipped) : "";
  std::printf("%s  %zu chains, %zu tasks (%lld failed, %lld not run, %lld never started), %.0f of %.0f simulated s%s "
              "in %.1f s wall on %d ranks -> %s\n",
              !complete ? "INTERRUPTED" : failures.empty() ? "ok" : "FAILED", output.plan.setups.size(),
              output.plan.n_tasks, (long long)fs.failed, (long long)fs.not_run, (long long)fs.unstarted, sim.done,
              sim.total, skipped.c_str(), wall, ranks, complete ? final_path.c_str() : part_path.c_str());
  for (const auto& fl : failures) std::printf("  failed: %s\n", fl.c_str());
  if (!complete)
    std::printf("the finished tasks are in %s; continue with the same command and --resume\n", part_path.c_str());
  const int code = !complete ? kExitInterrupted : failures.empty() ? 0 : kExitRunFailed;
  if (!fs.lost_ranks.empty()) {
    // A hung rank never reaches MPI_Finalize: the file is closed, so end the job here.
    std::printf("ranks %s did not return their task within the task bound and were given up (their tasks ran "
                "elsewhere); ending the job\n", fmt::format("{}", fmt::join(fs.lost_ranks, ", ")).c_str());
    std::fflush(stdout);
    MPI_Abort(MPI_COMM_WORLD, code);
  }
  return code;
}

}  // namespace

int sweep_command(const SweepArgs& args) {
  const int rank = parallel::comm_rank(MPI_COMM_WORLD), ranks = parallel::comm_size(MPI_COMM_WORLD);
  const bool master = rank == 0;

  config::SweepConfig cfg;
  sweep::SweepPlan plan;
  std::string error = parse_sweep(args, cfg, plan);
  if (args.dry_run) {  // the plan, checked like the sweep's, and nothing run or written
    const bool ok = agree(error.empty());
    if (master) {
      if (ok)
        print_plan(cfg, plan);
      else
        std::fprintf(stderr, "error: %s\n", error.empty() ? "invalid sweep file" : error.c_str());
    }
    return ok ? 0 : kExitBadInput;
  }

  SweepOutput output(args, cfg, plan);
  if (master && error.empty()) error = output.open();
  if (!agree(error.empty())) {
    if (master) std::fprintf(stderr, "error: %s\n", error.empty() ? "invalid sweep file" : error.c_str());
    return kExitBadInput;
  }
  if (master && output.replay.records.size() > 1) output.replay_journal();

  std::vector<parallel::Chain> chains;
  SimulatedSeconds sim;
  sim.total = plan.total_duration;
  if (master) {
    chains = chains_to_run(output, sim.done_before);
    if (args.resume && !args.quiet)
      std::printf("resuming %s: %zu of %zu chains to continue, %.0f of %.0f simulated s done\n",
                  output.part_path.c_str(), chains.size(), plan.setups.size(), sim.done_before, sim.total);
  }
  sim.done = sim.done_before;

  std::atomic<bool> stop{false};
  if (master)
    parallel::install_stop_handlers(stop);
  else
    parallel::ignore_stop_signals();
  long results = 0;
  const auto wall0 = std::chrono::steady_clock::now();
  const bool terminal = isatty(fileno(stdout));
  const parallel::FarmOptions fo = farm_options(args, output, sim, stop, results, terminal);
  const std::string started = now_iso();
  parallel::FarmSummary fs;
  try {
    fs = parallel::run_farm(std::move(chains), task_work(plan), fo);
  } catch (const std::runtime_error& e) {  // io::Hdf5Error, io::JournalError: disk full, ...
    if (!master || !(dynamic_cast<const io::Hdf5Error*>(&e) || dynamic_cast<const io::JournalError*>(&e))) throw;
    // The workers have been told to stop; every result committed to the journal is safe.
    std::fprintf(stderr, "error: %s\nthe finished tasks are in %s (with %s); fix the cause and continue with the "
                 "same command and --resume\n", e.what(), output.part_path.c_str(), output.journal_path.c_str());
    return kExitOutputFailed;
  }
  // The job's exit code is the master's: mpirun returns the first non-zero code of any rank,
  // so a worker that returned its own view (4 when the master stopped the farm) could decide it.
  if (!master) return 0;
  if (terminal && !args.quiet) std::printf("\n");
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return report_sweep(args, output, fs, sim, started, wall, ranks);
}

}  // namespace ajx::app
