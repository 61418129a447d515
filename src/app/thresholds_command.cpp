// astrojax thresholds: ω_rise, ω_fall, ω1 and ω2 of every chain of a sweep file, as brackets,
// next to the paper's measured values; with --refine F each bracket is re-run from the stored
// state before it, F times slower (sweep/refine.hpp), and the narrower bracket printed below;
// with --hold T both sides of each bracket are held for T and judged a bifurcation or a
// time-limited transient (sweep/hold_verdict.hpp); with --sequence each chain's orbit class
// sequence is printed against the paper's (sweep/class_sequence.hpp).
#include <atomic>
#include <charconv>
#include <cmath>
#include <functional>
#include <cstdio>
#include <fmt/format.h>
#include <fstream>
#include <numbers>
#include <optional>
#include <sstream>
#include <thread>
#include <vector>

#include "app/commands.hpp"
#include "app/sweep_file.hpp"
#include "config/config.hpp"
#include "io/hdf5_file.hpp"
#include "sweep/class_sequence.hpp"
#include "sweep/hold_verdict.hpp"
#include "sweep/plan.hpp"
#include "sweep/refine.hpp"
#include "sweep/thresholds.hpp"

namespace ajx::app {

namespace {

constexpr double pi = std::numbers::pi;

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);)
    if (!l.empty()) out.push_back(l);
  return out;
}

// What a refinement needs from the file: the sweep's plan rebuilt from the stored
// configuration, and for each chain the state to start from before a given time.
struct RefineSource {
  sweep::SweepPlan plan;
  sweep::ClassifierSettings settings;
  std::vector<std::int32_t> status;
  std::optional<SweepFile> file;

  // The last finished task's final state no later than t, else the chain's start state.
  physics::State state_before(std::size_t c, double t) const {
    const auto& spans = plan.spans[c];
    std::optional<std::size_t> best;
    for (std::size_t j = 0; j < spans.size() && spans[j].t_end <= t; ++j) {
      if (status[plan.first_task[c] + j] != 1) break;
      best = j;
    }
    return best ? file->state(plan.first_task[c] + *best) : plan.start_state(c);
  }
};

RefineSource open_refine_source(const std::string& path, std::size_t chains, std::size_t windows) {
  RefineSource src;
  io::File f = io::File::open_read(path);
  const io::Dataset config = f.open_dataset("config");
  const config::SweepConfig cfg = config::parse_sweep_config(
      config.read_string(), config.read_string_attribute("source"), lines(config.read_string_attribute("overrides")));
  src.plan = sweep::make_plan(cfg);
  if (src.plan.chains() != chains || src.plan.max_windows != windows)
    throw std::runtime_error(fmt::format("its configuration makes {} chains of up to {} windows, the file has {} of {}",
                                         src.plan.chains(), src.plan.max_windows, chains, windows));
  const io::Group wg = f.open_group("windows");
  if (wg.has_attribute("classifier_settings")) {
    const std::string used = wg.read_string_attribute("classifier_settings");
    if (used != "defaults") src.settings = sweep::parse_classifier_settings(lines(used));
  }
  src.status = f.read_int32s("tasks/status").data;
  src.file.emplace(std::move(f), chains, windows, 0, src.plan.n_tasks);
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

std::string parameters_of(const std::string& axes, const io::Array<double>& grid, std::size_t c) {
  std::string params;
  if (!axes.empty() && grid.data.size() > 0) {
    std::size_t a = 0;
    for (std::size_t start = 0; start <= axes.size(); ++a) {
      const std::size_t comma = std::min(axes.find(',', start), axes.size());
      params += fmt::format("{}{}={:g}", a ? " " : "", axes.substr(start, comma - start), grid(c, a));
      start = comma + 1;
    }
  }
  return params;
}

// Both sides of a bracket held, and the verdict.
struct HoldPair {
  sweep::HoldSide pre, post;
  sweep::Judgement judgement;
};

std::string side_line(const sweep::HoldSide& s) {
  if (!s.ok || s.final_class == sweep::OrbitClass::Failed)
    return fmt::format("hold {:.0f} s at {:.3f}π: failed: {}", s.hold, s.omega / pi, s.failure);
  return fmt::format("hold {:.0f} s at {:.3f}π: {} -> {}  P_motor {:.3e} W  P_drag {:.3e} W  dE/dt {:+.2e} W  "
                     "r = dE/dt / P_drag {:+.3f} (sustained if |r| <= {:.3f}): {}",
                     s.hold, s.omega / pi, sweep::to_string(s.reference), sweep::to_string(s.final_class), s.mean.motor,
                     s.mean.drag, s.mean.energy_rate, s.ratio, s.tolerance,
                     !s.determined ? "undetermined" : s.sustained ? "sustained" : "not sustained");
}

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

}  // namespace

int thresholds_command(const ThresholdsArgs& args) {
  std::optional<HoldTime> hold;
  if (!args.hold.empty()) {
    hold = parse_hold(args.hold);
    if (!hold) {
      std::fprintf(stderr,
                   "error: --hold %s: give the hold time in seconds (0 < T <= 1e5) or in drag times, e.g. 5tau\n",
                   args.hold.c_str());
      return kExitBadInput;
    }
  }
  std::vector<std::vector<sweep::ClassedWindow>> chains;
  std::vector<std::vector<double>> omega_ball;  // per chain, per window in `chains`
  const bool want_sequence = args.sequence || !args.sequence_csv.empty();
  std::string axes;
  io::Array<double> grid;
  std::size_t n_windows = 0;
  try {
    const io::File f = io::File::open_read(args.input);
    const auto cls = f.read_int32s("windows/class"), dir = f.read_int32s("windows/direction");
    const auto wb = f.read_doubles("windows/omega_m_begin"), we = f.read_doubles("windows/omega_m_end");
    io::Array<double> ob;
    if (want_sequence) ob = f.read_doubles("windows/omega_ball");
    const std::size_t C = cls.rows(), W = cls.cols();
    n_windows = W;
    for (std::size_t c = 0; c < C; ++c) {
      std::vector<sweep::ClassedWindow> w;
      std::vector<double> o;
      for (std::size_t k = 0; k < W; ++k)
        if (cls(c, k) >= 0 && std::isfinite(wb(c, k))) {
          w.push_back({wb(c, k), we(c, k), dir(c, k), static_cast<sweep::OrbitClass>(cls(c, k)), int(k)});
          if (want_sequence) o.push_back(ob(c, k));
        }
      chains.push_back(std::move(w));
      omega_ball.push_back(std::move(o));
    }
    const io::Group cg = f.open_group("chains");
    axes = cg.read_string_attribute("axes");
    if (cg.exists("grid_values")) grid = f.read_doubles("chains/grid_values");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s: cannot read a sweep file: %s\n", args.input.c_str(), e.what());
    return kExitBadInput;
  }

  // Every bracket found, in print order.
  struct Row {
    std::size_t chain;
    sweep::Threshold threshold;
    std::optional<sweep::Bracket> bracket;
    std::optional<sweep::Refinement> refined;
    std::optional<HoldPair> held;
  };
  std::vector<Row> rows;
  for (std::size_t c = 0; c < chains.size(); ++c)
    for (sweep::Threshold t : sweep::kThresholds) rows.push_back({c, t, sweep::find_threshold(t, chains[c]), {}, {}});

  if (args.refine > 0 || hold) {
    RefineSource src;
    try {
      src = open_refine_source(args.input, chains.size(), n_windows);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: %s: cannot rebuild the sweep to %s it: %s\n", args.input.c_str(),
                   args.refine > 0 ? "refine" : "hold", e.what());
      return kExitBadInput;
    }
    if (hold && hold->in_drag_times)
      for (std::size_t c = 0; c < chains.size(); ++c)
        if (!(src.plan.setups[c].model.p.drag > 0.0)) {
          std::fprintf(stderr, "error: --hold %s: chain %zu has no drag (c_D = 0), so no drag time: give seconds\n",
                       args.hold.c_str(), c);
          return kExitBadInput;
        }
    // The sweep's class of a chain's window, by its index.
    const auto class_of = [&](std::size_t c, int index) {
      for (const sweep::ClassedWindow& w : chains[c])
        if (w.index == index) return w.cls;
      return sweep::OrbitClass::Failed;
    };
    // Each refinement and each hold is an independent integration: spread them over threads.
    // Their start states are read from the file here, in this thread: a site's HDF5 need not be
    // built thread-safe (Debian's serial one is, its MPI one is not).
    std::vector<std::function<void()>> jobs;
    for (Row& r : rows) {
      if (!r.bracket) continue;
      const sweep::ChainSetup* setup = &src.plan.setups[r.chain];
      if (args.refine > 0) {
        const double t_begin = setup->protocol.windows[std::size_t(r.bracket->window_before)].t_begin;
        r.refined.emplace();
        try {
          jobs.push_back([&, setup, start = src.state_before(r.chain, t_begin)] {
            try {
              r.refined = sweep::refine_threshold(r.threshold, *setup, src.plan.points[r.chain].protocol, *r.bracket,
                                                  args.refine, start, src.settings);
            } catch (const std::exception& e) {
              r.refined->ok = false;
              r.refined->failure = e.what();
            }
          });
        } catch (const std::exception& e) {
          r.refined->ok = false;
          r.refined->failure = e.what();
        }
      }
      if (hold) {
        r.held.emplace();
        for (const bool pre : {true, false}) {
          // Hold at the middle of the bracket's window (ω_m there is the bracket's value), from
          // the last stored state before it, along the chain's own schedule.
          const int index = pre ? r.bracket->window_before : r.bracket->window_after;
          const sweep::Window& w = setup->protocol.windows[std::size_t(index)];
          const double t_cut = 0.5 * (w.t_begin + w.t_end);
          sweep::HoldSide& side = pre ? r.held->pre : r.held->post;
          try {
            jobs.push_back([&, setup, t_cut, window = w.t_end - w.t_begin, reference = class_of(r.chain, index),
                            start = src.state_before(r.chain, t_cut)] {
              try {
                side = sweep::hold_side(*setup, t_cut, hold->seconds(setup->model.p), window, start, reference,
                                        src.settings);
              } catch (const std::exception& e) {
                side.ok = false;
                side.failure = e.what();
              }
            });
          } catch (const std::exception& e) {
            side.ok = false;
            side.failure = e.what();
          }
        }
      }
    }
    std::atomic<std::size_t> next{0};
    const auto worker = [&] {
      for (std::size_t i; (i = next++) < jobs.size();) jobs[i]();
    };
    std::vector<std::thread> pool;
    for (int k = 0; k < std::max(1, args.jobs); ++k) pool.emplace_back(worker);
    for (auto& th : pool) th.join();
    for (Row& r : rows)
      if (r.held) r.held->judgement = sweep::judge(r.held->pre, r.held->post);
  }

  std::string csv = "chain,parameters,threshold,before_rad_s,after_rad_s,mid_rad_s,paper_rad_s,relative_difference";
  if (args.refine > 0) csv += ",refine_factor,refined_before_rad_s,refined_after_rad_s,refined_mid_rad_s,"
                              "refined_relative_difference,refine_note";
  if (hold) {
    csv += side_header("pre") + side_header("post") + ",verdict,verdict_reason";
    if (args.refine > 0) csv += ",rate_dependent";
  }
  csv += "\n";
  std::printf("%-6s %-28s %-11s %-22s %-10s %-10s %s\n", "chain", "parameters", "threshold", "bracket [π rad/s]",
              "mid [π]", "paper [π]", "relative difference");
  for (const Row& row : rows) {
    const std::size_t c = row.chain;
    const std::string params = parameters_of(axes, grid, c);
    const sweep::Threshold t = row.threshold;
    const double paper = sweep::paper_value(t);
    if (const auto& b = row.bracket) {
      const double rel = (b->mid() - paper) / paper;
      std::printf("%-6zu %-28s %-11s %8.3f .. %-10.3f %-10.3f %-10.2f %+.1f %%\n", c, params.c_str(),
                  std::string(sweep::to_string(t)).c_str(), b->before / pi, b->after / pi, b->mid() / pi, paper / pi,
                  100 * rel);
      csv += fmt::format("{},{},{},{:.9g},{:.9g},{:.9g},{:.9g},{:.6g}", c, params, sweep::to_string(t), b->before,
                         b->after, b->mid(), paper, rel);
    } else {
      std::printf("%-6zu %-28s %-11s %-22s %-10s %-10.2f\n", c, params.c_str(), std::string(sweep::to_string(t)).c_str(),
                  "not reached", "", paper / pi);
      csv += fmt::format("{},{},{},,,,{:.9g},", c, params, sweep::to_string(t), paper);
    }
    std::string rate_dependent;  // with --refine: "yes" when the slower ramp lost the change
    if (args.refine > 0) {
      const auto& r = row.refined;
      if (!r) {
        csv += fmt::format(",{},,,,,", args.refine);
      } else if (r->bracket) {
        const sweep::Bracket& b = *r->bracket;
        const double rel = (b.mid() - paper) / paper;
        std::printf("%-6s %-28s %-11s %8.3f .. %-10.3f %-10.3f %-10s %+.1f %%  (refined, %d× slower)\n", "", "", "",
                    b.before / pi, b.after / pi, b.mid() / pi, "", 100 * rel, r->factor);
        csv += fmt::format(",{},{:.9g},{:.9g},{:.9g},{:.6g},", r->factor, b.before, b.after, b.mid(), rel);
        rate_dependent = "no";
      } else {
        const std::string note =
            r->ok ? fmt::format("no change within the old bracket at {}x slower: the threshold depends on the ramp",
                                r->factor)
                  : "refinement failed: " + r->failure;
        std::printf("%-6s %-28s %-11s %s\n", "", "", "", note.c_str());
        csv += fmt::format(",{},,,,,\"{}\"", r->factor, note);
        if (r->ok) rate_dependent = "yes";
      }
    }
    if (hold) {
      if (const auto& h = row.held) {
        std::printf("%-6s %-28s %-11s %s\n", "", "", "", side_line(h->pre).c_str());
        std::printf("%-6s %-28s %-11s %s\n", "", "", "", side_line(h->post).c_str());
        std::string flag;
        if (rate_dependent == "no")
          flag = fmt::format("; the {}x slower ramp finds the change inside the bracket", args.refine);
        if (rate_dependent == "yes")
          flag = h->judgement.verdict == sweep::Verdict::Bifurcation
                     ? "; but rate-dependent: the slower ramp lost the change (conflict, look closer)"
                     : "; rate-dependent too: the slower ramp lost the change";
        std::printf("%-6s %-28s %-11s verdict: %s: %s%s\n", "", "", "",
                    std::string(sweep::to_string(h->judgement.verdict)).c_str(), h->judgement.reason.c_str(),
                    flag.c_str());
        csv += fmt::format(",{},{},{},{}", side_csv(h->pre), side_csv(h->post),
                           sweep::to_string(h->judgement.verdict), csv_quoted(h->judgement.reason));
      } else {
        csv += std::string(2 * kSideFields + 2, ',');  // two sides, verdict, reason: empty
      }
      if (args.refine > 0) csv += "," + rate_dependent;
    }
    csv += "\n";
  }
  if (!args.csv.empty() && !write_csv(args.csv, csv)) return kExitBadInput;

  if (want_sequence) {
    std::string seq = "chain,parameters,kind,leg,direction,class,omega_from_rad_s,omega_to_rad_s,windows,blips,"
                      "omega_ball_mean_rad_s,omega_ball_slope,step,status,step_description\n";
    const auto num = [](double v) { return std::isfinite(v) ? fmt::format("{:.9g}", v) : std::string(); };
    const auto dir_name = [](int d) { return d > 0 ? "up" : (d < 0 ? "down" : "held"); };
    if (args.sequence)
      std::printf("\nclass sequence%s\n"
                  "%-6s %-28s %-4s %-5s %-17s %-22s %-8s %-6s %-11s %s\n",
                  args.absorb_blips ? " (one not-settled window between two of one class is absorbed as a blip)" : "",
                  "chain", "parameters", "leg", "dir", "class", "ω_m [π rad/s]", "windows", "blips", "ω_ball [π]",
                  "dω_ball/dω_m");
    std::vector<std::vector<sweep::StepMatch>> matches;
    for (std::size_t c = 0; c < chains.size(); ++c) {
      const std::string params = parameters_of(axes, grid, c);
      const std::vector<sweep::ClassRun> runs = sweep::class_runs(chains[c], omega_ball[c], args.absorb_blips);
      for (const sweep::ClassRun& r : runs) {
        if (args.sequence)
          std::printf("%-6zu %-28s %-4d %-5s %-17s %8.3f .. %-10.3f %-8d %-6d %-11s %s\n", c, params.c_str(), r.leg,
                      dir_name(r.direction), std::string(sweep::to_string(r.cls)).c_str(), r.omega_from / pi,
                      r.omega_to / pi, r.windows, r.blips,
                      std::isfinite(r.omega_ball_mean) ? fmt::format("{:.3f}", r.omega_ball_mean / pi).c_str() : "",
                      std::isfinite(r.omega_ball_slope) ? fmt::format("{:+.3f}", r.omega_ball_slope).c_str() : "");
        seq += fmt::format("{},{},run,{},{},{},{},{},{},{},{},{},,,\n", c, params, r.leg, r.direction,
                           sweep::to_string(r.cls), num(r.omega_from), num(r.omega_to), r.windows, r.blips,
                           num(r.omega_ball_mean), num(r.omega_ball_slope));
      }
      matches.push_back(sweep::compare_with_paper(runs));
      for (const sweep::StepMatch& m : matches.back()) {
        const sweep::ClassRun* r = m.run >= 0 ? &runs[std::size_t(m.run)] : nullptr;
        seq += fmt::format("{},{},step,{},{},{},{},,,,{},{},{},{},{}\n", c, params, r ? std::to_string(r->leg) : "",
                           r ? std::to_string(r->direction) : "", r ? std::string(sweep::to_string(r->cls)) : "",
                           num(m.omega), r ? num(r->omega_ball_mean) : "", r ? num(r->omega_ball_slope) : "",
                           sweep::to_string(m.step), sweep::to_string(m.status), csv_quoted(std::string(describe(m.step))));
      }
    }
    if (args.sequence) {
      std::printf("\nagainst the paper's sequence (each step looked for after the last one found)\n");
      for (std::size_t c = 0; c < chains.size(); ++c) {
        std::printf("chain %zu %s\n", c, parameters_of(axes, grid, c).c_str());
        for (const sweep::StepMatch& m : matches[c]) {
          const std::string at = m.run >= 0 ? fmt::format("at {:.3f}π", m.omega / pi) : "";
          std::printf("  %-9s %-13s %-13s %s\n", std::string(sweep::to_string(m.step)).c_str(),
                      std::string(sweep::to_string(m.status)).c_str(), at.c_str(),
                      std::string(sweep::describe(m.step)).c_str());
        }
      }
    }
    if (!args.sequence_csv.empty() && !write_csv(args.sequence_csv, seq)) return kExitBadInput;
  }
  return 0;
}

}  // namespace ajx::app
