// astrojax replay: one window of a sweep file re-run from its task's stored start state (the
// previous task's /tasks/final_state, or the chain's seed for its first task) with the file's
// own model, variant, integrator and classifier settings, into a run file with dense samples.
// The task is integrated twice from the same start: once exactly as the sweep did (its sample
// grid, rounded to the stored precision, classified), which must give the stored window's
// class and ω_ball back; once with samples every 1/--sample-rate s over the window (and
// --before seconds ahead of it), which the run file keeps for animations and pictures.
#include <cmath>
#include <cstdio>
#include <fmt/format.h>
#include <numbers>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "app/output_paths.hpp"
#include "config/config.hpp"
#include "config/text.hpp"
#include "physics/state.hpp"
#include "results/provenance.hpp"
#include "results/replay_file.hpp"
#include "results/reclassify.hpp"
#include "results/sweep_reader.hpp"
#include "sweep/plan.hpp"
#include "sweep/task.hpp"

namespace ajx::app {

namespace {

constexpr double pi = std::numbers::pi;

struct ReplayError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// What a replay reads of a sweep file, all of it here: the plan made again from the stored
// configuration, the window's stored row and the start state of its task.
struct StoredWindow {
  config::SweepConfig cfg;          // the file's configuration: its one part, or the chain's
  sweep::SweepPlan plan;
  sweep::ClassifierSettings settings;
  std::size_t task = 0;             // the window's task, its index in the chain
  physics::State start;             // that task's start state
  results::WindowRow stored;
  results::ReplayInfo info;
};

// The window's place in its chain and file, for /replay and the printed summary.
void describe_window(StoredWindow& s, const std::string& path, const std::string& src_commit, std::size_t c,
                     std::size_t k) {
  const sweep::ChainSetup& setup = s.plan.setups[c];
  const auto& spans = s.plan.spans[c];
  const sweep::Window& w = setup.protocol.windows[k];
  results::ReplayInfo& in = s.info;
  in.source = path;
  in.source_commit = src_commit;
  in.chain = std::int64_t(c);
  in.window = std::int64_t(k);
  in.task = std::int64_t(s.task);
  if (!s.cfg.parts.empty()) {
    const config::SweepConfig& part = s.cfg.parts[s.plan.part[c]];
    in.group = part.group;
    in.variant = part.variant;
    in.variant_label = part.variant_label;
  }
  in.task_begin = spans[s.task].t_begin;
  in.t_begin = w.t_begin;
  in.t_end = w.t_end;
  in.omega_begin = w.omega_begin;
  in.omega_end = w.omega_end;
  in.direction = w.direction;
  in.sweep_sample_rate = setup.sample_rate;
  in.stored = s.stored;
}

// Reads the stored window (chain, window) of `path` through the one reader (which validates the
// whole file first: a damaged file, or one without samples, throws SweepFileError naming it);
// throws ReplayError naming the file and what is wrong with the chosen window.
StoredWindow read_stored_window(const std::string& path, long chain, long window) {
  const results::SweepReader in(path);
  StoredWindow s;
  s.cfg = in.config();
  s.plan = config::make_plan(s.cfg);
  if (s.plan.chains() != in.chains())
    throw ReplayError(fmt::format("{}: its configuration makes {} chains, the file has {}", path, s.plan.chains(),
                                  in.chains()));
  if (chain < 0 || std::size_t(chain) >= s.plan.chains())
    throw ReplayError(fmt::format("{}: --chain {}: outside 0..{} (the file has {} chains)", path, chain,
                                  s.plan.chains() - 1, s.plan.chains()));
  const std::size_t c = std::size_t(chain);
  const std::size_t n_windows = s.plan.setups[c].protocol.windows.size();
  if (window < 0 || std::size_t(window) >= n_windows)
    throw ReplayError(fmt::format("{}: --window {}: outside 0..{} (chain {} has {} windows)", path, window,
                                  n_windows - 1, chain, n_windows));
  const std::size_t k = std::size_t(window);
  if (in.classes()(c, k) < 0)
    throw ReplayError(fmt::format("{}: window {} of chain {} was never computed (its task did not run): finish the "
                                  "sweep with --resume first", path, k, c));
  if (in.count()(c, k) <= 0)
    throw ReplayError(fmt::format("{}: window {} of chain {} stores no samples: nothing to reproduce", path, k, c));
  s.settings = sweep::parse_classifier_settings(in.classifier_settings());
  s.stored.cls = in.classes()(c, k);
  for (std::size_t i = 0; i < results::kNumStats; ++i) s.stored.stats[i] = in.stat(results::kStats[i].name)(c, k);

  const auto& spans = s.plan.spans[c];
  while (s.task + 1 < spans.size() && std::size_t(spans[s.task].first_window + spans[s.task].num_windows) <= k) ++s.task;
  const std::size_t first = s.plan.first_task[c];
  if (s.task > 0 && in.status()[first + s.task - 1] != results::TaskStatus::Ok)
    throw ReplayError(fmt::format("{}: the task before window {} of chain {} has no stored final state (status {})",
                                  path, k, c, int(in.status()[first + s.task - 1])));
  // The start: the chain's seed for its first task, else the previous task's /tasks/final_state.
  s.start = s.task == 0 ? s.plan.start_state(c) : in.final_state(first + s.task - 1);
  describe_window(s, path, in.git_commit(), c, k);
  return s;
}

// ω_ball agrees to the stored precision: both undefined, or within what the float32 samples
// the classifier reads resolve (6e-8 relative each; 1e-6 leaves room for the averaging).
bool same_omega(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return std::abs(a - b) <= 1e-6 * std::max(1.0, std::abs(b));
}

// The sweep's own integration of the task, classified as the sweep classified it.
void replay_as_swept(const StoredWindow& s, results::ReplayInfo& info) {
  const std::size_t c = std::size_t(info.chain);
  const sweep::ChainSetup& setup = s.plan.setups[c];
  sweep::TaskOutput out = sweep::run_task(setup, s.plan.spans[c][s.task], s.start);
  for (sweep::WindowRecord& rec : out.windows) results::round_to_stored(rec);
  const auto classes = sweep::classify_windows(setup, out, s.settings);
  for (std::size_t i = 0; i < out.windows.size(); ++i)
    if (out.windows[i].index == info.window) {
      info.replayed = results::window_row(classes[i]);
      info.reason = classes[i].reason;
    }
  const double a = results::row_stat(info.replayed, "omega_ball"), b = results::row_stat(info.stored, "omega_ball");
  info.omega_ball_difference = std::isnan(a) && std::isnan(b) ? 0.0 : a - b;
  info.reproduced = info.replayed.cls == info.stored.cls && same_omega(a, b);
}

std::string omega_text(double w) { return std::isnan(w) ? std::string("undefined") : fmt::format("{:.6f}π rad/s", w / pi); }

}  // namespace

int replay_command(const ReplayArgs& args) {
  StoredWindow s;
  double t_from = 0.0;
  try {
    check_output_path(args.input, "-o", args.output, {args.input}, {});
    check_not_overwriting(args.input, "-o", args.output, args.force);
    s = read_stored_window(args.input, args.chain, args.window);
    t_from = std::max(s.info.task_begin, s.info.t_begin - args.before);
    const double samples = (s.info.t_end - t_from) * args.sample_rate;
    if (samples > 2e7)
      throw ReplayError(fmt::format("{}: --sample-rate {:g} over {:g} s makes {:.3g} samples, more than 2e7: lower it "
                                    "or --before", args.input, args.sample_rate, s.info.t_end - t_from, samples));
  } catch (const std::exception& e) {  // ReplayError, ConfigError, or the file's own (HDF5, layout)
    std::fprintf(stderr, "error: %s\n", config::printable(e.what()).c_str());
    return kExitBadInput;
  }
  if (args.before > 0.0 && t_from > s.info.t_begin - args.before && !args.quiet)
    std::printf("note: --before %g s reaches before the task's start; the samples start there, at t = %g s\n",
                args.before, t_from);

  replay_as_swept(s, s.info);

  // The dense run: the same start, integrator and model, samples every 1/rate s from t_from.
  const std::size_t c = std::size_t(args.chain);
  const sweep::ChainSetup& setup = s.plan.setups[c];
  const physics::MotorSchedule schedule = setup.motor();
  sim::RunOptions run = setup.run;
  run.run_statistics = false;
  sweep::add_settle_spans(setup, s.plan.spans[c][s.task], run);  // settled as the sweep settled it
  run.sample_spans = {{t_from, s.info.t_end + 0.5 / args.sample_rate}};
  results::Trajectory traj;
  physics::State state = s.start;
  state.t = s.info.task_begin;
  const sim::SampleObserver add = [&](const sim::Sample& x) { traj.add(x, setup.model.p, schedule); };
  const sim::RunSummary sum = sim::Simulation(setup.model, schedule, run).run(state, s.info.t_end, 1.0 / args.sample_rate,
                                                                             add, 0.0);
  s.info.sample_rate = args.sample_rate;

  // The chain's configuration in force (its part's, with the chain's own model) as provenance.
  config::SweepConfig cfg = s.cfg.parts.empty() ? s.cfg : s.cfg.parts[s.plan.part[c]];
  cfg.model = setup.model;
  cfg.run = setup.run;
  try {
    results::write_replay(args.output, args.command_line, cfg, traj, s.info, sum);
  } catch (const std::exception& e) {  // nothing is left behind: the file is written beside it, then renamed
    std::fprintf(stderr, "error: cannot write %s: %s\n", args.output.c_str(), e.what());
    return kExitOutputFailed;
  }

  const results::ReplayInfo& in = s.info;
  const char* arrow = in.direction > 0 ? "▲" : in.direction < 0 ? "▼" : "●";
  const std::string who =
      in.group.empty() ? "" : fmt::format(" ({}, {})", config::printable(in.group), config::printable(in.variant));
  std::printf("replayed %s chain %ld%s, window %ld: ω_m %.4f–%.4fπ rad/s %s, t %g–%g s, from the start of its task %ld "
              "(t = %g s)\n",
              args.input.c_str(), args.chain, who.c_str(), args.window,
              in.omega_begin / pi, in.omega_end / pi, arrow, in.t_begin, in.t_end, long(in.task), in.task_begin);
  const auto name = [](std::int32_t cls) { return std::string(sweep::to_string(static_cast<sweep::OrbitClass>(cls))); };
  std::printf("  stored:   %-17s ω_ball %s  confidence %.3f\n", name(in.stored.cls).c_str(),
              omega_text(results::row_stat(in.stored, "omega_ball")).c_str(), results::row_stat(in.stored, "confidence"));
  std::printf("  replayed: %-17s ω_ball %s  confidence %.3f  (%s)\n", name(in.replayed.cls).c_str(),
              omega_text(results::row_stat(in.replayed, "omega_ball")).c_str(), results::row_stat(in.replayed, "confidence"),
              in.reason.c_str());
  if (in.reproduced)
    std::printf("  reproduced: same class, ω_ball differs by %.2g rad/s\n", in.omega_ball_difference);
  else
    std::printf("  NOT reproduced (the file was written by commit %s, this is %s)\n",
                in.source_commit.empty() ? "unknown" : in.source_commit.c_str(), results::program_commit().c_str());
  std::printf("%s  %zu samples at %g Hz over t %g–%g s  steps %ld  -> %s\n", sum.ok() ? "ok" : ("FAILED: " + sum.failure).c_str(),
              traj.t.size(), args.sample_rate, traj.t.empty() ? t_from : traj.t.front(),
              traj.t.empty() ? t_from : traj.t.back(), sum.steps, args.output.c_str());
  return sum.ok() && in.reproduced ? 0 : kExitRunFailed;
}

}  // namespace ajx::app
