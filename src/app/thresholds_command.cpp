// astrojax thresholds: ω_rise, ω_fall, ω1 and ω2 of a sweep file, one table per model variant,
// each threshold a bracket with its width next to the paper's measured value. By default both
// sides of each bracket are held for 5 drag times and judged a bifurcation, an excursion or a
// time-limited transient (sweep/hold_verdict.hpp); where a chain holds levels up through the
// flower's onset and back down, ω2 is also fitted as the lag's Hopf point (sweep/flower_onset.hpp).
// With --refine F each bracket is re-run from the stored state before it, F times slower
// (sweep/refine.hpp); with --sequence each chain's class sequence is printed against the paper's.
// Stages: read the file, find the brackets, judge them (onsets; holds and refinements as farm
// tasks, thresholds_farm.hpp: on the ranks of an mpirun, or on threads of one process), report.
#include <mpi.h>

#include <charconv>
#include <algorithm>
#include <cmath>
#include <functional>
#include <cstdio>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <thread>
#include <vector>

#include "app/commands.hpp"
#include "app/thresholds_brackets.hpp"
#include "app/thresholds_farm.hpp"
#include "config/config.hpp"
#include "config/text.hpp"
#include "parallel/mpi_env.hpp"
#include "results/reclassify.hpp"
#include "results/sweep_reader.hpp"
#include "sweep/bracket_check.hpp"
#include "sweep/class_sequence.hpp"
#include "sweep/flower_onset.hpp"
#include "sweep/hold_verdict.hpp"
#include "sweep/plan.hpp"
#include "sweep/refine.hpp"
#include "sweep/thresholds.hpp"

namespace ajx::app {

namespace {

constexpr double pi = std::numbers::pi;

// What a refinement needs from the file: the sweep's plan rebuilt from the stored
// configuration, and for each chain the state to start from before a given time.
struct RefineSource {
  sweep::SweepPlan plan;
  sweep::ClassifierSettings settings;
  const results::SweepReader* in = nullptr;

  // The last finished task's final state no later than t, else the chain's start state.
  physics::State state_before(std::size_t c, double t) const {
    const auto& spans = plan.spans[c];
    std::optional<std::size_t> best;
    for (std::size_t j = 0; j < spans.size() && spans[j].t_end <= t; ++j) {
      if (in->status()[plan.first_task[c] + j] != results::TaskStatus::Ok) break;
      best = j;
    }
    return best ? in->final_state(plan.first_task[c] + *best) : plan.start_state(c);
  }
};

// `settings`: the classifier's for the holds and refinements when --set gave some; else the
// settings the file's windows were classified with.
RefineSource open_refine_source(const results::SweepReader& in, const std::optional<sweep::ClassifierSettings>& settings) {
  RefineSource src;
  src.in = &in;
  src.plan = config::make_plan(in.config());
  if (src.plan.chains() != in.chains() || src.plan.max_windows != in.windows() || src.plan.n_tasks != in.tasks())
    throw std::runtime_error(fmt::format("its configuration makes {} chains of up to {} windows in {} tasks, the file "
                                         "has {} of {} in {}", src.plan.chains(), src.plan.max_windows, src.plan.n_tasks,
                                         in.chains(), in.windows(), in.tasks()));
  src.settings = settings ? *settings : sweep::parse_classifier_settings(in.classifier_settings());
  return src;
}

// --hold's value: seconds, or a multiple of the chain's drag time written "5tau".
struct HoldTime {
  double value = 0.0;
  bool in_drag_times = false;
  double seconds(const physics::Parameters& p) const { return in_drag_times ? value * sweep::drag_time(p) : value; }
};

std::optional<HoldTime> parse_hold(const std::string& text) {
  HoldTime h;
  std::string number = text;
  if (number.size() > 3 && number.compare(number.size() - 3, 3, "tau") == 0) {
    h.in_drag_times = true;
    number.resize(number.size() - 3);
  }
  const auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), h.value);
  if (ec != std::errc() || end != number.data() + number.size() || !(h.value > 0.0) || h.value > 1e5) return {};
  return h;
}

std::string csv_quoted(const std::string& s) { return "\"" + s + "\""; }

// Writes a CSV table to path; false (and the reason on stderr) if it cannot.
bool write_csv(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (out) return true;
  std::fprintf(stderr, "error: cannot write %s\n", path.c_str());
  return false;
}

std::string parameters_of(const std::vector<std::string>& axes, const results::Array<double>& grid, std::size_t c) {
  std::string params;
  for (std::size_t a = 0; a < axes.size(); ++a) params += fmt::format("{}{}={:g}", a ? " " : "", axes[a], grid(c, a));
  return params;
}

// Both sides of a bracket held, and the verdict.
struct HoldPair {
  sweep::HoldSide pre, post;
  sweep::Judgement judgement;
};

std::string side_csv(const sweep::HoldSide& s) {
  const auto num = [](double v) { return std::isfinite(v) ? fmt::format("{:.9g}", v) : std::string(); };
  return fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{}", num(s.hold), num(s.omega), sweep::to_string(s.reference),
                     sweep::to_string(s.final_class), num(s.first_change), num(s.mean.motor), num(s.mean.drag),
                     num(s.mean.other), num(s.mean.energy_rate), num(s.ratio), num(s.ratio_error), num(s.tolerance),
                     s.determined ? 1 : 0, s.sustained ? 1 : 0);
}

constexpr int kSideFields = 14;
constexpr const char* kSideColumns =
    "hold_s,omega_rad_s,class,final_class,first_change_s,motor_power_W,drag_power_W,friction_impact_power_W,energy_rate_W,"
    "ratio,ratio_error,tolerance,determined,sustained";

std::string side_header(const char* prefix) {
  std::string out;
  std::string_view cols = kSideColumns;
  while (!cols.empty()) {
    const std::size_t comma = std::min(cols.find(','), cols.size());
    out += fmt::format(",{}_{}", prefix, cols.substr(0, comma));
    cols.remove_prefix(std::min(comma + 1, cols.size()));
  }
  return out;
}


// ---- what the file says --------------------------------------------------------------------

struct Variant {
  std::string name, label;  // both "" for a plain file: one table of every chain
};

struct SweepWindows {
  std::vector<std::vector<sweep::ClassedWindow>> chains;  // classified windows, in protocol order
  std::vector<std::vector<double>> omega_ball;            // per chain, per window in `chains` [rad/s]
  std::vector<std::string> params;                        // per chain: its grid point, "a=1 b=2"
  std::vector<std::string> group;                         // per chain: its group ("" for a plain file)
  std::vector<std::size_t> variant;                       // per chain: index into `variants`
  std::vector<Variant> variants;
  results::Array<double> radius_bottom_mean, radius_bottom_std;  // chains × windows [m]
  std::size_t n_windows = 0;
};

// `settings`: classify the windows again from their samples with these (--set), in memory,
// instead of reading the file's classes. Names and labels escaped for printing.
SweepWindows read_sweep_windows(const results::SweepReader& in, const std::optional<sweep::ClassifierSettings>& settings) {
  SweepWindows s;
  auto cls = in.classes();
  const auto& dir = in.direction();
  const auto &wb = in.omega_m_begin(), &we = in.omega_m_end();
  auto ob = in.stat("omega_ball");
  s.radius_bottom_mean = in.stat("radius_bottom_mean");
  s.radius_bottom_std = in.stat("radius_bottom_std");
  if (settings)
    for (const results::ReclassifiedWindow& w : results::reclassify_windows(in, *settings)) {
      cls(w.chain, w.window) = w.row.cls;
      ob(w.chain, w.window) = results::row_stat(w.row, "omega_ball");
      s.radius_bottom_mean(w.chain, w.window) = results::row_stat(w.row, "radius_bottom_mean");
      s.radius_bottom_std(w.chain, w.window) = results::row_stat(w.row, "radius_bottom_std");
    }
  const std::size_t C = in.chains(), W = in.windows();
  s.n_windows = W;
  for (std::size_t c = 0; c < C; ++c) {
    std::vector<sweep::ClassedWindow> w;
    std::vector<double> o;
    for (std::size_t k = 0; k < W; ++k)
      if (cls(c, k) >= 0 && std::isfinite(wb(c, k))) {
        w.push_back({wb(c, k), we(c, k), dir(c, k), static_cast<sweep::OrbitClass>(cls(c, k)), int(k)});
        o.push_back(ob(c, k));
      }
    s.chains.push_back(std::move(w));
    s.omega_ball.push_back(std::move(o));
  }
  std::vector<std::string> axes;
  for (const std::string& a : in.axes()) axes.push_back(config::printable(a));
  for (std::size_t c = 0; c < C; ++c) s.params.push_back(parameters_of(axes, in.grid_values(), c));
  if (in.grouped()) {
    const results::NameList &v = in.variants(), &g = in.groups();
    for (std::size_t i = 0; i < v.names.size(); ++i)
      s.variants.push_back({config::printable(v.names[i]), config::printable(v.texts[i])});
    for (std::size_t c = 0; c < C; ++c) {
      s.variant.push_back(std::size_t(v.of_chain[c]));
      s.group.push_back(config::printable(g.names[std::size_t(g.of_chain[c])]));
    }
  } else {
    s.variants.push_back({});
    s.variant.assign(C, 0);
    s.group.assign(C, "");
  }
  return s;
}

// Each chain's start seed: a grouped file stores one a chain; an ungrouped one has its config's
// (the [bisect]'s or the protocol's); "" for a hold or basin sweep, whose chains start otherwise.
std::vector<std::string> start_seeds_of(const results::SweepReader& in, std::size_t chains) {
  const results::NameList& seeds = in.start_seeds();
  std::vector<std::string> out(chains);
  if (in.grouped()) {
    for (std::size_t c = 0; c < chains && c < seeds.of_chain.size(); ++c)
      if (seeds.of_chain[c] >= 0) out[c] = config::printable(seeds.names[std::size_t(seeds.of_chain[c])]);
    return out;
  }
  const config::SweepConfig cfg = in.config();
  const std::string seed = cfg.bisect ? cfg.bisect->start_seed : (cfg.hold || cfg.basin ? "" : cfg.start_seed);
  out.assign(chains, config::printable(seed));
  return out;
}

// ---- the brackets and their judgement --------------------------------------------------------

struct Row {
  std::size_t chain;
  sweep::Threshold threshold;
  std::optional<sweep::Bracket> bracket;
  std::optional<sweep::Refinement> refined;
  std::optional<HoldPair> held;
};

// The Hopf point of a chain's lag, fitted over its held levels (sweep/flower_onset.hpp).
struct Onset {
  double last_lag = 0.0, first_flower = 0.0;  // the classifier's bracket on the way up [rad/s]
  std::optional<sweep::HopfFit> fit;          // ω_H in rad/s
  int levels = 0;                             // levels with both legs in the fit's span
};

// Where a check's result goes: the row's refinement or one side of its hold (emplaced first).
enum class Slot { Refined, Pre, Post };

void place(Row& row, Slot slot, sweep::CheckResult result) {
  if (slot == Slot::Refined)
    row.refined = std::get<sweep::Refinement>(std::move(result));
  else
    (slot == Slot::Pre ? row.held->pre : row.held->post) = std::get<sweep::HoldSide>(std::move(result));
}

sweep::OrbitClass class_at(const std::vector<sweep::ClassedWindow>& windows, int index) {
  for (const sweep::ClassedWindow& w : windows)
    if (w.index == index) return w.cls;
  return sweep::OrbitClass::Failed;
}

// The holds (and refinements) of every bracket, each an independent integration from the
// file's stored state before it, to run on the farm (thresholds_farm.hpp).
struct Checks {
  RefineSource src;
  ChecksContext context;
  std::vector<PlannedCheck> planned;
  std::vector<std::pair<std::size_t, Slot>> to;  // per planned check: its row and slot
};

// Plans the checks of every bracket; a start state that cannot be read fails its check at once.
// Returns an error message, or "".
std::string plan_checks(const ThresholdsArgs& args, const results::SweepReader& in,
                        const std::optional<sweep::ClassifierSettings>& settings, const std::optional<HoldTime>& hold,
                        const SweepWindows& sw, std::vector<Row>& rows, Checks& checks) {
  RefineSource& src = checks.src;
  try {
    src = open_refine_source(in, settings);
  } catch (const std::exception& e) {
    return fmt::format("{}: cannot rebuild the sweep to {} it: {}", args.input, args.refine > 0 ? "refine" : "hold",
                       e.what());
  }
  if (hold && hold->in_drag_times)
    for (std::size_t c = 0; c < sw.chains.size(); ++c)
      if (!(src.plan.setups[c].model.p.drag > 0.0))
        return fmt::format("--hold {}: chain {} has no drag (c_D = 0), so no drag time: give seconds", args.hold, c);
  checks.context = {in.config_text(), in.config_source(), in.overrides(),
                    settings ? args.settings : in.classifier_settings()};
  // The start states are read from the file here, on rank 0 and in its main thread: a site's
  // HDF5 need not be built thread-safe (Debian's serial one is, its MPI one is not).
  const auto add = [&](std::size_t row, Slot slot, sweep::BracketCheck check, double t_start) {
    try {
      checks.planned.push_back({check, src.state_before(rows[row].chain, t_start)});
      checks.to.emplace_back(row, slot);
    } catch (const std::exception& e) {
      place(rows[row], slot, sweep::failed_check(check, e.what()));
    }
  };
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    if (!r.bracket) continue;
    const sweep::ChainSetup& setup = src.plan.setups[r.chain];
    if (args.refine > 0)
      add(i, Slot::Refined, sweep::RefineCheck{r.chain, r.threshold, *r.bracket, args.refine},
          setup.protocol.windows[std::size_t(r.bracket->window_before)].t_begin);
    if (!hold) continue;
    rows[i].held.emplace();
    for (const bool pre : {true, false}) {
      // Held at the middle of the bracket's window (ω_m there is the bracket's value), from the
      // last stored state before it, along the chain's own schedule.
      const int index = pre ? r.bracket->window_before : r.bracket->window_after;
      const sweep::Window& w = setup.protocol.windows[std::size_t(index)];
      const double t_cut = 0.5 * (w.t_begin + w.t_end);
      add(i, pre ? Slot::Pre : Slot::Post,
          sweep::HoldCheck{r.chain, t_cut, hold->seconds(setup.model.p), w.t_end - w.t_begin,
                           class_at(sw.chains[r.chain], index)},
          t_cut);
    }
  }
  return "";
}

// The threads of rank 0 that run checks: -j, else every core in one process and one thread
// beside the master under mpirun (whose other ranks take the other cores).
int check_threads(const ThresholdsArgs& args, std::size_t n_checks) {
  const int ranks = parallel::comm_size(MPI_COMM_WORLD);
  int threads = args.jobs > 0 ? args.jobs : ranks > 1 ? 1 : int(std::max(1u, std::thread::hardware_concurrency()));
  if (ranks == 1) threads = std::min<int>(threads, int(std::max<std::size_t>(n_checks, 1)));
  return threads;
}

// The chain's held levels (windows at one ω_m on a rising or falling staircase), keyed by ω_m
// rounded to 1e-6 π: {ω: (up window, down window)}, -1 where a leg has none.
std::map<long long, std::pair<int, int>> held_levels(const std::vector<sweep::ClassedWindow>& windows) {
  std::map<long long, std::pair<int, int>> out;
  for (const sweep::ClassedWindow& w : windows) {
    if (w.direction == 0 || w.omega_begin != w.omega_end) continue;
    auto [it, fresh] = out.try_emplace(std::llround(w.omega_begin / pi * 1e6), -1, -1);
    (w.direction > 0 ? it->second.first : it->second.second) = w.index;
  }
  return out;
}

// The bottom ball's stored samples, read from the file once, when a chain first needs them.
struct BottomBallSamples {
  const results::SweepReader& in;
  results::Array<std::int32_t> count;
  results::Array<double> r2;  // chains × windows × samples × 3
  bool read = false;
  void load() {
    if (read) return;
    count = in.count();
    r2 = in.samples("r2");
    read = true;
  }
};

// The lag's Hopf point from a chain that holds levels up through the flower's onset and back
// down over them; none without a flower that lasts to the top of the way up.
std::optional<Onset> flower_onset(BottomBallSamples& samples, const SweepWindows& sw, std::size_t c, double span) {
  using sweep::OrbitClass;
  const auto levels = held_levels(sw.chains[c]);
  std::vector<std::pair<double, int>> ups;  // (ω_m, window) on the way up
  for (const auto& [key, legs] : levels)
    if (legs.first >= 0) ups.push_back({double(key) * 1e-6 * pi, legs.first});
  // The flower that lasts to the top of the way up: a flower window that gives way to a circle
  // further up (a transient at the lock's loss) is not the onset.
  std::optional<double> first_flower;
  for (auto it = ups.rbegin(); it != ups.rend() && class_at(sw.chains[c], it->second) == OrbitClass::Flower; ++it)
    first_flower = it->first;
  if (!first_flower) return std::nullopt;
  Onset on;
  on.first_flower = *first_flower;
  on.last_lag = std::numeric_limits<double>::quiet_NaN();
  for (const auto& [w, index] : ups)
    if (w < *first_flower && class_at(sw.chains[c], index) == OrbitClass::LaggingCircular) on.last_lag = w;
  samples.load();
  const auto& count = samples.count;
  const results::Array<double>& r2 = samples.r2;
  const std::size_t cap = r2.dims[2];
  const auto a2 = [&](int w) {
    const double r = sw.radius_bottom_std(c, std::size_t(w)) / sw.radius_bottom_mean(c, std::size_t(w));
    return r * r;
  };
  const auto sampling = [&](int w) {  // a²'s error from the window's length (its two halves)
    std::vector<double> rho;
    const std::size_t n = std::size_t(count(c, std::size_t(w)));
    for (std::size_t i = 0; i < n; ++i) {
      const double* p = &r2.data[((c * sw.n_windows + std::size_t(w)) * cap + i) * 3];
      rho.push_back(std::hypot(p[0], p[1]));
    }
    return sweep::half_window_sigma(rho);
  };
  std::vector<sweep::OnsetLevel> fit_levels;
  for (const auto& [key, legs] : levels) {
    const double w = double(key) * 1e-6 * pi;
    if (w > *first_flower + span * pi || legs.first < 0 || legs.second < 0) continue;
    const double up = a2(legs.first), down = a2(legs.second);
    if (!std::isfinite(up) || !std::isfinite(down)) continue;
    // Half the legs' difference and each window's sampling error; never below a²'s rounding.
    const double s_legs = 0.5 * std::abs(up - down), s_win = std::max(sampling(legs.first), sampling(legs.second));
    const double sigma = std::max({std::hypot(s_legs, std::isfinite(s_win) ? s_win : 0.0),
                                   4 * std::numeric_limits<double>::epsilon() * std::max(up, down), 1e-300});
    fit_levels.push_back({w, 0.5 * (up + down), sigma});
  }
  on.levels = int(fit_levels.size());
  on.fit = sweep::fit_hopf(fit_levels, *first_flower);
  return on;
}

// ---- the report ---------------------------------------------------------------------------

// The paper's lagging orbit: ω_ball nearly constant at about 4.8π between ω1 and ω2 (read off
// its simulated Fig. 7(i), not measured) [rad/s].
constexpr double kPaperLagOmegaBall = 4.8 * pi;

std::string_view symbol(sweep::Threshold t) {
  switch (t) {
    case sweep::Threshold::Rise: return "ω_rise";
    case sweep::Threshold::Fall: return "ω_fall";
    case sweep::Threshold::Omega1: return "ω1";
    case sweep::Threshold::Omega2: return "ω2";
  }
  return "?";
}

// How the bracket [a, b] stands to the paper's value p: "contains it", or the range of (ω − p)/p.
std::string against_paper(double a, double b, double p) {
  const double lo = std::min(a, b), hi = std::max(a, b);
  if (lo <= p && p <= hi) return "contains it";
  return fmt::format("{:+.1f} .. {:+.1f} %", 100 * (lo - p) / p, 100 * (hi - p) / p);
}

// What a chain is: its group and its grid point ("up", "drive_radius=0.01", "").
std::string chain_label(const SweepWindows& sw, std::size_t c) {
  if (sw.group[c].empty() || sw.params[c].empty()) return sw.group[c] + sw.params[c];
  return sw.group[c] + " " + sw.params[c];
}

std::string chain_name(const SweepWindows& sw, std::size_t c) {
  const std::string label = chain_label(sw, c);
  return label.empty() ? fmt::format("{}", c) : fmt::format("{} {}", c, label);
}

// The report's table lines: Markdown rows, or text columns padded to their widths.
struct TableText {
  std::string& out;
  bool markdown;
  void line(const std::vector<std::string>& cells, const std::vector<int>& widths) const {
    if (markdown) {
      out += "| " + fmt::format("{}", fmt::join(cells, " | ")) + " |\n";
      return;
    }
    std::string l = " ";
    for (std::size_t i = 0; i < cells.size(); ++i) {
      l += " " + cells[i];
      // Pad by characters shown, not bytes (π and arrows are several bytes in UTF-8).
      const long shown = long(std::count_if(cells[i].begin(), cells[i].end(), [](char ch) { return (ch & 0xC0) != 0x80; }));
      if (i + 1 < cells.size()) l += std::string(std::size_t(std::max(0L, widths[i] - shown)), ' ');
    }
    out += l + "\n";
  }
};
const std::vector<int> kReportWidths{10, 20, 18, 10, 34, 10, 18, 0};

// The lines of threshold t in variant v: each chain's bracket (and its refinement), for ω2
// also the Hopf fits; verdict reasons appended to `reasons`. False when none was reached.
bool threshold_lines(const TableText& table, const SweepWindows& sw, const std::vector<Row>& rows,
                     const std::vector<std::optional<Onset>>& onsets, std::size_t v, sweep::Threshold t,
                     std::vector<std::string>& reasons) {
  const std::vector<int>& widths = kReportWidths;
  const double paper = sweep::paper_value(t);
  bool any = false;
  for (const Row& r : rows) {
    if (r.threshold != t || sw.variant[r.chain] != v || !r.bracket) continue;
    any = true;
    const sweep::Bracket& b = *r.bracket;
    const auto& ws = sw.chains[r.chain];
    std::string verdict = "not judged";
    if (r.held) {
      verdict = std::string(sweep::to_string(r.held->judgement.verdict));
      reasons.push_back(fmt::format("{} of chain {}: {}: {}", symbol(t), chain_name(sw, r.chain), verdict,
                                    r.held->judgement.reason));
      verdict += fmt::format(" [{}]", reasons.size());
    }
    table.line({std::string(symbol(t)), chain_name(sw, r.chain), fmt::format("{:.3f} → {:.3f}", b.before / pi, b.after / pi),
                fmt::format("{:.3f}", std::abs(b.after - b.before) / pi),
                fmt::format("{} → {}", sweep::to_string(class_at(ws, b.window_before)), sweep::to_string(class_at(ws, b.window_after))),
                fmt::format("{:.2f}", paper / pi), against_paper(b.before, b.after, paper), verdict},
               widths);
    if (r.refined) {
      const std::string cell =
          r.refined->bracket
              ? fmt::format("{:.3f} → {:.3f}", r.refined->bracket->before / pi, r.refined->bracket->after / pi)
              : (r.refined->ok ? "lost: the change moves with the ramp" : "failed: " + r.refined->failure);
      table.line({"", fmt::format("{}× slower", r.refined->factor), cell,
                  r.refined->bracket ? fmt::format("{:.3f}", std::abs(r.refined->bracket->after - r.refined->bracket->before) / pi) : "",
                  "", "", r.refined->bracket ? against_paper(r.refined->bracket->before, r.refined->bracket->after, paper) : "", ""},
                 widths);
    }
  }
  if (t == sweep::Threshold::Omega2)
    for (std::size_t c = 0; c < sw.chains.size(); ++c) {
      if (sw.variant[c] != v || !onsets[c]) continue;
      any = true;
      if (!onsets[c]->fit) {
        table.line({"ω2 (Hopf)", chain_name(sw, c), "not fitted", "",
                    fmt::format("{} levels with both legs", onsets[c]->levels), fmt::format("{:.2f}", paper / pi),
                    "", "needs 3 above the first flower"},
                   widths);
        continue;
      }
      const sweep::HopfFit& h = *onsets[c]->fit;
      table.line({"ω2 (Hopf)", chain_name(sw, c), fmt::format("{:.2f} ± {:.2f}", h.omega_h / pi, h.sigma / pi),
                  fmt::format("{:.3f}", 2 * h.sigma / pi), fmt::format("lag's Hopf point, {} levels", h.levels),
                  fmt::format("{:.2f}", paper / pi), against_paper(h.omega_h - h.sigma, h.omega_h + h.sigma, paper),
                  h.reduced_chi2 > 1.0
                      ? fmt::format("χ²/dof {:.2g}: σ {:.2f} × √ = {:.2f}; bootstrap {:.2f}", h.reduced_chi2,
                                    h.sigma_unscaled / pi, h.sigma / pi, h.sigma_bootstrap / pi)
                      : fmt::format("χ²/dof {:.2g}; bootstrap {:.2f}", h.reduced_chi2, h.sigma_bootstrap / pi)},
                 widths);
    }
  return any;
}

// The lag's plateau in variant v: per chain the longest lagging run on a rising leg, its mean
// ω_ball and slope.
void lag_plateau_lines(const TableText& table, const SweepWindows& sw, std::size_t v) {
  for (std::size_t c = 0; c < sw.chains.size(); ++c) {
    if (sw.variant[c] != v) continue;
    std::optional<sweep::ClassRun> lag;
    for (const sweep::ClassRun& r : sweep::class_runs(sw.chains[c], sw.omega_ball[c], false))
      if (r.cls == sweep::OrbitClass::LaggingCircular && r.direction > 0 && (!lag || r.windows > lag->windows)) lag = r;
    if (!lag || !std::isfinite(lag->omega_ball_mean)) continue;
    table.line({"lag ω_ball", chain_name(sw, c), fmt::format("{:.3f}", lag->omega_ball_mean / pi), "",
                fmt::format("over ω_m {:.2f} → {:.2f}π, dω_ball/dω_m {:+.3f}", lag->omega_from / pi, lag->omega_to / pi,
                            lag->omega_ball_slope),
                fmt::format("≈ {:.1f}", kPaperLagOmegaBall / pi),
                fmt::format("{:+.1f} %", 100 * (lag->omega_ball_mean - kPaperLagOmegaBall) / kPaperLagOmegaBall),
                fmt::format("{} windows", lag->windows)},
               kReportWidths);
  }
}

// Every chain of variant v that reached no threshold, said so: a table that lists only the chains
// with a bracket would leave a reader to guess about the others.
void silent_chain_lines(const TableText& table, const SweepWindows& sw, const std::vector<Row>& rows,
                        const std::vector<std::optional<Onset>>& onsets, std::size_t v) {
  for (std::size_t c = 0; c < sw.chains.size(); ++c) {
    if (sw.variant[c] != v) continue;
    bool reached = onsets[c] && onsets[c]->fit;
    for (const Row& r : rows) reached = reached || (r.chain == c && r.bracket);
    if (!reached)
      table.line({"(none)", chain_name(sw, c), "nothing reached", "", "no threshold's class change on its windows", "",
                  "", ""},
                 kReportWidths);
  }
}

// One report, as text or as Markdown: per variant, a table of its brackets, the Hopf fits,
// and the verdicts' reasons.
std::string report(const ThresholdsArgs& args, const SweepWindows& sw, const std::vector<Row>& rows,
                   const std::vector<std::optional<Onset>>& onsets, bool markdown, const std::string& hold_text) {
  std::string out;
  const TableText table{out, markdown};
  const std::vector<std::string> head{"threshold", "chain", "bracket [π rad/s]", "width [π]", "classes", "paper [π]",
                                      "bracket vs paper", "verdict"};
  if (markdown)
    out += fmt::format("# Thresholds of `{}`\n\n", args.input);
  if (!args.settings.empty())
    out += fmt::format("Windows classified again in memory with {}.\n", fmt::join(args.settings, ", "));
  out += fmt::format("{}Brackets: the mean ω_m of the last window before the class changed and of the first after.{}\n",
                     markdown ? "" : "", hold_text.empty() ? "" : " " + hold_text);
  for (std::size_t v = 0; v < sw.variants.size(); ++v) {
    const Variant& var = sw.variants[v];
    out += markdown ? fmt::format("\n## {}\n\n", var.name.empty() ? "Every chain" : var.name + ": " + var.label)
                    : fmt::format("\n{}\n", var.name.empty() ? "every chain" : "variant " + var.name + ": " + var.label);
    table.line(head, kReportWidths);
    if (markdown) out += "|---|---|---|---|---|---|---|---|\n";
    std::vector<std::string> reasons;
    for (sweep::Threshold t : sweep::kThresholds)
      if (!threshold_lines(table, sw, rows, onsets, v, t, reasons))
        table.line({std::string(symbol(t)), "", "not reached", "", "", fmt::format("{:.2f}", sweep::paper_value(t) / pi),
                    "", ""},
                   kReportWidths);
    lag_plateau_lines(table, sw, v);
    silent_chain_lines(table, sw, rows, onsets, v);
    if (!reasons.empty()) {
      out += markdown ? "\nVerdicts:\n\n" : "  verdicts:\n";
      for (std::size_t i = 0; i < reasons.size(); ++i)
        out += markdown ? fmt::format("{}. {}\n", i + 1, reasons[i]) : fmt::format("  [{}] {}\n", i + 1, reasons[i]);
    }
  }
  bool any_fit = false;
  for (const auto& o : onsets) any_fit = any_fit || (o && o->fit);
  if (any_fit)
    out += fmt::format(
        "\n{}ω2 (Hopf): where the lag turns into a flower, fitted over the held levels with both an up and a down leg up "
        "to {:g}π above the first flower: a² = μ (k + q μ), μ = max(ω_m − ω_H, 0), a = std/mean of the bottom ball's "
        "radius; ± one standard error, where χ² has risen by max(1, χ²/dof): with χ²/dof > 1 the levels scatter more "
        "than their σ (half their up and down legs' difference) say, and the error of Δχ² = 1 is scaled by "
        "√(χ²/dof). The bootstrap is half the central 68 % range of ω_H over {} resamples of the levels (an error from "
        "their scatter alone). Neither includes the spread over histories: where the bead sticks moves ω_H (the "
        "sensitivity report). The classifier's ω2 bracket lies above it: it names a flower only once the oscillation is "
        "large enough to see.\n",
        markdown ? "" : "  ", args.onset_span, sweep::kBootstrapResamples);
  return out;
}

std::string csv_table(const ThresholdsArgs& args, const SweepWindows& sw, const std::vector<Row>& rows, bool hold) {
  std::string csv = "chain,parameters,threshold,before_rad_s,after_rad_s,mid_rad_s,paper_rad_s,relative_difference";
  if (args.refine > 0) csv += ",refine_factor,refined_before_rad_s,refined_after_rad_s,refined_mid_rad_s,"
                              "refined_relative_difference,refine_note";
  if (hold) {
    csv += side_header("pre") + side_header("post") + ",verdict,verdict_reason";
    if (args.refine > 0) csv += ",rate_dependent";
  }
  csv += "\n";
  for (const Row& row : rows) {
    const std::size_t c = row.chain;
    const sweep::Threshold t = row.threshold;
    const double paper = sweep::paper_value(t);
    if (const auto& b = row.bracket)
      csv += fmt::format("{},{},{},{:.9g},{:.9g},{:.9g},{:.9g},{:.6g}", c, sw.params[c], sweep::to_string(t), b->before,
                         b->after, b->mid(), paper, (b->mid() - paper) / paper);
    else
      csv += fmt::format("{},{},{},,,,{:.9g},", c, sw.params[c], sweep::to_string(t), paper);
    std::string rate_dependent;  // with --refine: "yes" when the slower ramp lost the change
    if (args.refine > 0) {
      const auto& r = row.refined;
      if (!r) {
        csv += fmt::format(",{},,,,,", args.refine);
      } else if (r->bracket) {
        const sweep::Bracket& b = *r->bracket;
        csv += fmt::format(",{},{:.9g},{:.9g},{:.9g},{:.6g},", r->factor, b.before, b.after, b.mid(), (b.mid() - paper) / paper);
        rate_dependent = "no";
      } else {
        const std::string note =
            r->ok ? fmt::format("no change within the old bracket at {}x slower: the threshold depends on the ramp",
                                r->factor)
                  : "refinement failed: " + r->failure;
        csv += fmt::format(",{},,,,,\"{}\"", r->factor, note);
        if (r->ok) rate_dependent = "yes";
      }
    }
    if (hold) {
      if (const auto& h = row.held)
        csv += fmt::format(",{},{},{},{}", side_csv(h->pre), side_csv(h->post), sweep::to_string(h->judgement.verdict),
                           csv_quoted(h->judgement.reason));
      else
        csv += std::string(2 * kSideFields + 2, ',');  // two sides, verdict, reason: empty
      if (args.refine > 0) csv += "," + rate_dependent;
    }
    csv += "\n";
  }
  return csv;
}

// --sequence: each chain's runs of one class, and the paper's steps found in them.
std::string sequence_report(const ThresholdsArgs& args, const SweepWindows& sw, std::string& seq) {
  std::string out;
  seq = "chain,parameters,kind,leg,direction,class,omega_from_rad_s,omega_to_rad_s,windows,blips,"
        "omega_ball_mean_rad_s,omega_ball_slope,step,status,step_description\n";
  const auto num = [](double v) { return std::isfinite(v) ? fmt::format("{:.9g}", v) : std::string(); };
  const auto dir_name = [](int d) { return d > 0 ? "up" : (d < 0 ? "down" : "held"); };
  out += fmt::format("\nclass sequence{}\n{:<6} {:<28} {:<4} {:<5} {:<17} {:<22} {:<8} {:<6} {:<11} {}\n",
                     args.absorb_blips ? " (one not-settled window between two of one class is absorbed as a blip)" : "",
                     "chain", "parameters", "leg", "dir", "class", "ω_m [π rad/s]", "windows", "blips", "ω_ball [π]",
                     "dω_ball/dω_m");
  std::vector<std::vector<sweep::StepMatch>> matches;
  for (std::size_t c = 0; c < sw.chains.size(); ++c) {
    const std::string& variant = sw.variants[sw.variant[c]].name;
    const std::string params = chain_label(sw, c) + (variant.empty() ? "" : " (" + variant + ")");
    const std::vector<sweep::ClassRun> runs = sweep::class_runs(sw.chains[c], sw.omega_ball[c], args.absorb_blips);
    for (const sweep::ClassRun& r : runs) {
      out += fmt::format("{:<6} {:<28} {:<4} {:<5} {:<17} {:8.3f} .. {:<10.3f} {:<8} {:<6} {:<11} {}\n", c, params, r.leg,
                         dir_name(r.direction), sweep::to_string(r.cls), r.omega_from / pi, r.omega_to / pi, r.windows,
                         r.blips, std::isfinite(r.omega_ball_mean) ? fmt::format("{:.3f}", r.omega_ball_mean / pi) : "",
                         std::isfinite(r.omega_ball_slope) ? fmt::format("{:+.3f}", r.omega_ball_slope) : "");
      seq += fmt::format("{},{},run,{},{},{},{},{},{},{},{},{},,,\n", c, sw.params[c], r.leg, r.direction,
                         sweep::to_string(r.cls), num(r.omega_from), num(r.omega_to), r.windows, r.blips,
                         num(r.omega_ball_mean), num(r.omega_ball_slope));
    }
    matches.push_back(sweep::compare_with_paper(runs));
    for (const sweep::StepMatch& m : matches.back()) {
      const sweep::ClassRun* r = m.run >= 0 ? &runs[std::size_t(m.run)] : nullptr;
      seq += fmt::format("{},{},step,{},{},{},{},,,,{},{},{},{},{}\n", c, sw.params[c], r ? std::to_string(r->leg) : "",
                         r ? std::to_string(r->direction) : "", r ? std::string(sweep::to_string(r->cls)) : "",
                         num(m.omega), r ? num(r->omega_ball_mean) : "", r ? num(r->omega_ball_slope) : "",
                         sweep::to_string(m.step), sweep::to_string(m.status), csv_quoted(std::string(describe(m.step))));
    }
  }
  out += "\nagainst the paper's sequence (each step looked for after the last one found)\n";
  for (std::size_t c = 0; c < sw.chains.size(); ++c) {
    const std::string& variant = sw.variants[sw.variant[c]].name;
    out += fmt::format("chain {}{}\n", chain_name(sw, c), variant.empty() ? "" : " (" + variant + ")");
    for (const sweep::StepMatch& m : matches[c])
      out += fmt::format("  {:<9} {:<13} {:<13} {}\n", sweep::to_string(m.step), sweep::to_string(m.status),
                         m.run >= 0 ? fmt::format("at {:.3f}π", m.omega / pi) : "", sweep::describe(m.step));
  }
  return out;
}

bool write_text(const std::string& path, const std::string& text) { return write_csv(path, text); }

}  // namespace

namespace {

// What rank 0 reads and plans before the checks run.
struct Prepared {
  std::optional<HoldTime> hold;
  std::optional<sweep::ClassifierSettings> settings;
  SweepWindows sw;
  std::vector<std::optional<Onset>> onsets;
  std::optional<results::SweepReader> in;
  std::vector<Row> rows;
  ChainNames names;  // its start seeds here; the rest from sw
  Checks checks;     // with holds or --refine
};

// The options checked, the file read, its brackets found and their checks planned: 0, or the
// exit code once the error is printed.
int prepare(const ThresholdsArgs& args, Prepared& p) {
  if (!args.no_hold) {
    p.hold = parse_hold(args.hold);
    if (!p.hold) {
      std::fprintf(stderr,
                   "error: --hold %s: give the hold time in seconds (0 < T <= 1e5) or in drag times, e.g. 5tau\n",
                   args.hold.c_str());
      return kExitBadInput;
    }
  }
  if (!args.settings.empty()) {
    try {
      p.settings = sweep::parse_classifier_settings(args.settings);
    } catch (const std::invalid_argument& e) {
      std::fprintf(stderr, "error: --set %s (thresholds takes the sweep's configuration from the file; only the "
                   "classifier's settings can be changed)\n", e.what());
      return kExitBadInput;
    }
  }
  try {
    p.in.emplace(args.input);
    p.sw = read_sweep_windows(*p.in, p.settings);
    BottomBallSamples samples{*p.in, {}, {}};
    for (std::size_t c = 0; c < p.sw.chains.size(); ++c)
      p.onsets.push_back(flower_onset(samples, p.sw, c, args.onset_span));
    p.names.starts_ = start_seeds_of(*p.in, p.sw.chains.size());
  } catch (const results::SweepFileError& e) {
    std::fprintf(stderr, "error: %s\n", config::printable(e.what()).c_str());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s: cannot read a sweep file: %s\n", args.input.c_str(), config::printable(e.what()).c_str());
    return kExitBadInput;
  }
  for (std::size_t c = 0; c < p.sw.chains.size(); ++c)
    if (!is_bisection_chain(*p.in, c))  // a bisection's bracket is in /brackets, not in its windows
      for (sweep::Threshold t : sweep::kThresholds)
        p.rows.push_back({c, t, sweep::find_threshold(t, p.sw.chains[c]), {}, {}});
  if (thresholds_integrate(args))
    if (const std::string error = plan_checks(args, *p.in, p.settings, p.hold, p.sw, p.rows, p.checks); !error.empty()) {
      std::fprintf(stderr, "error: %s\n", config::printable(error).c_str());
      return kExitBadInput;
    }
  return 0;
}

// The planned checks run on the farm, their results in the rows and each hold judged; false
// when a stop request left some unrun.
bool run_planned_checks(const ThresholdsArgs& args, Prepared& p) {
  const Checks& ch = p.checks;
  const auto results = run_checks(ch.context, ch.src.plan, ch.src.settings, ch.planned, check_threads(args, ch.planned.size()));
  if (!results) return false;
  for (std::size_t i = 0; i < results->size(); ++i) place(p.rows[ch.to[i].first], ch.to[i].second, (*results)[i]);
  for (Row& r : p.rows)
    if (r.held) r.held->judgement = sweep::judge(r.held->pre, r.held->post);
  return true;
}

}  // namespace

int thresholds_command(const ThresholdsArgs& args) {
  // Under mpirun every rank runs this: rank 0 reads, plans and reports, the others take the
  // holds and refinements from the farm (with none, they have nothing to do). The job's exit
  // code is rank 0's: the others return 0 (commands.hpp).
  const bool farm = thresholds_integrate(args);
  int mpi = 0;
  MPI_Initialized(&mpi);
  if (mpi && parallel::comm_rank(MPI_COMM_WORLD) != 0) {
    if (farm) checks_worker();
    return 0;
  }
  Prepared p;
  if (const int code = prepare(args, p); code != 0) {
    if (farm) refuse_checks();
    return code;
  }
  if (farm && !run_planned_checks(args, p)) {
    std::fprintf(stderr, "interrupted (Ctrl-C, SIGTERM or SIGUSR1) before every hold and refinement had run: no "
                 "report written; run the command again\n");
    return kExitInterrupted;
  }
  const std::vector<Row>& rows = p.rows;
  const SweepWindows& sw = p.sw;
  const results::SweepReader* in = &*p.in;
  const auto& hold = p.hold;
  const auto& onsets = p.onsets;
  ChainNames& names = p.names;
  for (std::size_t c = 0; c < sw.chains.size(); ++c) {
    names.params_.push_back(sw.params[c]);
    names.groups_.push_back(sw.group[c]);
    names.variants_.push_back(sw.variants[sw.variant[c]].name);
    names.labels_.push_back(chain_name(sw, c) + (sw.variants[sw.variant[c]].name.empty() ? "" : " " + sw.variants[sw.variant[c]].name));
  }
  const std::string hold_text =
      hold ? fmt::format("Verdicts: each side held {} from the file's state and judged by its energy balance "
                         "(bifurcation: the new orbit persists; excursion: held past the change the old orbit "
                         "returns; time-limited transient: the old orbit was not sustained).",
                         hold->in_drag_times ? fmt::format("{:g} drag times m/c_D", hold->value)
                                             : fmt::format("{:g} s", hold->value))
           : "";
  if (!rows.empty() || !in->brackets()) std::fputs(report(args, sw, rows, onsets, false, hold_text).c_str(), stdout);
  if (in->brackets()) std::fputs(bisection_report(*in, names).c_str(), stdout);
  if (!args.markdown.empty() && !write_text(args.markdown, report(args, sw, rows, onsets, true, hold_text)))
    return kExitBadInput;
  if (!args.csv.empty()) {
    const std::string csv = csv_table(args, sw, rows, bool(hold));
    if (!write_csv(args.csv, in->brackets() ? with_bisection_rows(csv, *in, names) : csv)) return kExitBadInput;
  }
  if (args.sequence || !args.sequence_csv.empty()) {
    std::string seq;
    const std::string text = sequence_report(args, sw, seq);
    if (args.sequence) std::fputs(text.c_str(), stdout);
    if (!args.sequence_csv.empty() && !write_csv(args.sequence_csv, seq)) return kExitBadInput;
  }
  return 0;
}

}  // namespace ajx::app
