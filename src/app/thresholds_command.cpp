// astrojax thresholds: ω_rise, ω_fall, ω1 and ω2 of every chain of a sweep file, as brackets,
// next to the paper's measured values; with --refine F each bracket is re-run from the stored
// state before it, F times slower (sweep/refine.hpp), and the narrower bracket printed below.
#include <atomic>
#include <cmath>
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

}  // namespace

int thresholds_command(const ThresholdsArgs& args) {
  std::vector<std::vector<sweep::ClassedWindow>> chains;
  std::string axes;
  io::Array<double> grid;
  std::size_t n_windows = 0;
  try {
    const io::File f = io::File::open_read(args.input);
    const auto cls = f.read_int32s("windows/class"), dir = f.read_int32s("windows/direction");
    const auto wb = f.read_doubles("windows/omega_m_begin"), we = f.read_doubles("windows/omega_m_end");
    const std::size_t C = cls.rows(), W = cls.cols();
    n_windows = W;
    for (std::size_t c = 0; c < C; ++c) {
      std::vector<sweep::ClassedWindow> w;
      for (std::size_t k = 0; k < W; ++k)
        if (cls(c, k) >= 0 && std::isfinite(wb(c, k)))
          w.push_back({wb(c, k), we(c, k), dir(c, k), static_cast<sweep::OrbitClass>(cls(c, k)), int(k)});
      chains.push_back(std::move(w));
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
  };
  std::vector<Row> rows;
  for (std::size_t c = 0; c < chains.size(); ++c)
    for (sweep::Threshold t : sweep::kThresholds) rows.push_back({c, t, sweep::find_threshold(t, chains[c]), {}});

  if (args.refine > 0) {
    RefineSource src;
    try {
      src = open_refine_source(args.input, chains.size(), n_windows);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: %s: cannot rebuild the sweep to refine it: %s\n", args.input.c_str(), e.what());
      return kExitBadInput;
    }
    // Each refinement is an independent integration: spread them over threads.
    std::atomic<std::size_t> next{0};
    std::atomic<long> failed{0};
    const auto worker = [&] {
      for (std::size_t i; (i = next++) < rows.size();) {
        Row& r = rows[i];
        if (!r.bracket) continue;
        const sweep::ChainSetup& setup = src.plan.setups[r.chain];
        const double t_begin = setup.protocol.windows[std::size_t(r.bracket->window_before)].t_begin;
        try {
          r.refined = sweep::refine_threshold(r.threshold, setup, src.plan.points[r.chain].protocol, *r.bracket,
                                              args.refine, src.state_before(r.chain, t_begin), src.settings);
        } catch (const std::exception& e) {
          sweep::Refinement bad;
          bad.ok = false;
          bad.failure = e.what();
          r.refined = bad;
          ++failed;
        }
      }
    };
    std::vector<std::thread> pool;
    for (int k = 0; k < std::max(1, args.jobs); ++k) pool.emplace_back(worker);
    for (auto& th : pool) th.join();
  }

  std::string csv = "chain,parameters,threshold,before_rad_s,after_rad_s,mid_rad_s,paper_rad_s,relative_difference";
  if (args.refine > 0) csv += ",refine_factor,refined_before_rad_s,refined_after_rad_s,refined_mid_rad_s,"
                              "refined_relative_difference,refine_note";
  csv += "\n";
  std::printf("%-6s %-28s %-11s %-22s %-10s %-10s %s\n", "chain", "parameters", "threshold", "bracket [π rad/s]",
              "mid [π]", "paper [π]", "relative difference");
  for (const Row& row : rows) {
    const std::size_t c = row.chain;
    std::string params;
    if (!axes.empty() && grid.data.size() > 0) {
      std::size_t a = 0;
      for (std::size_t start = 0; start <= axes.size(); ++a) {
        const std::size_t comma = std::min(axes.find(',', start), axes.size());
        params += fmt::format("{}{}={:g}", a ? " " : "", axes.substr(start, comma - start), grid(c, a));
        start = comma + 1;
      }
    }
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
      } else {
        const std::string note =
            r->ok ? fmt::format("no change within the old bracket at {}x slower: the threshold depends on the ramp",
                                r->factor)
                  : "refinement failed: " + r->failure;
        std::printf("%-6s %-28s %-11s %s\n", "", "", "", note.c_str());
        csv += fmt::format(",{},,,,,\"{}\"", r->factor, note);
      }
    }
    csv += "\n";
  }
  if (!args.csv.empty()) {
    std::ofstream out(args.csv);
    out << csv;
    if (!out) {
      std::fprintf(stderr, "error: cannot write %s\n", args.csv.c_str());
      return kExitBadInput;
    }
  }
  return 0;
}

}  // namespace ajx::app
