// astrojax thresholds: ω_rise, ω_fall, ω1 and ω2 of every chain of a sweep file, as brackets,
// next to the paper's measured values.
#include <cmath>
#include <cstdio>
#include <fmt/format.h>
#include <fstream>
#include <numbers>
#include <vector>

#include "app/commands.hpp"
#include "io/hdf5_file.hpp"
#include "sweep/thresholds.hpp"

namespace ajx::app {

int thresholds_command(const ThresholdsArgs& args) {
  constexpr double pi = std::numbers::pi;
  std::vector<std::vector<sweep::ClassedWindow>> chains;
  std::string axes;
  io::Array<double> grid;
  try {
    const io::File f = io::File::open_read(args.input);
    const auto cls = f.read_int32s("windows/class"), dir = f.read_int32s("windows/direction");
    const auto wb = f.read_doubles("windows/omega_m_begin"), we = f.read_doubles("windows/omega_m_end");
    const std::size_t C = cls.rows(), W = cls.cols();
    for (std::size_t c = 0; c < C; ++c) {
      std::vector<sweep::ClassedWindow> w;
      for (std::size_t k = 0; k < W; ++k)
        if (cls(c, k) >= 0 && std::isfinite(wb(c, k)))
          w.push_back({wb(c, k), we(c, k), dir(c, k), static_cast<sweep::OrbitClass>(cls(c, k))});
      chains.push_back(std::move(w));
    }
    const io::Group cg = f.open_group("chains");
    axes = cg.read_string_attribute("axes");
    if (cg.exists("grid_values")) grid = f.read_doubles("chains/grid_values");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s: cannot read a sweep file: %s\n", args.input.c_str(), e.what());
    return kExitBadInput;
  }

  std::string csv = "chain,parameters,threshold,before_rad_s,after_rad_s,mid_rad_s,paper_rad_s,relative_difference\n";
  std::printf("%-6s %-28s %-11s %-22s %-10s %-10s %s\n", "chain", "parameters", "threshold", "bracket [π rad/s]",
              "mid [π]", "paper [π]", "relative difference");
  for (std::size_t c = 0; c < chains.size(); ++c) {
    std::string params;
    if (!axes.empty() && grid.data.size() > 0) {
      std::size_t a = 0;
      for (std::size_t start = 0; start <= axes.size(); ++a) {
        const std::size_t comma = std::min(axes.find(',', start), axes.size());
        params += fmt::format("{}{}={:g}", a ? " " : "", axes.substr(start, comma - start), grid(c, a));
        start = comma + 1;
      }
    }
    for (sweep::Threshold t : sweep::kThresholds) {
      const auto b = sweep::find_threshold(t, chains[c]);
      const double paper = sweep::paper_value(t);
      if (b) {
        const double rel = (b->mid() - paper) / paper;
        std::printf("%-6zu %-28s %-11s %8.3f .. %-10.3f %-10.3f %-10.2f %+.1f %%\n", c, params.c_str(),
                    std::string(sweep::to_string(t)).c_str(), b->before / pi, b->after / pi, b->mid() / pi, paper / pi,
                    100 * rel);
        csv += fmt::format("{},{},{},{:.9g},{:.9g},{:.9g},{:.9g},{:.6g}\n", c, params, sweep::to_string(t), b->before,
                           b->after, b->mid(), paper, rel);
      } else {
        std::printf("%-6zu %-28s %-11s %-22s %-10s %-10.2f\n", c, params.c_str(), std::string(sweep::to_string(t)).c_str(),
                    "not reached", "", paper / pi);
        csv += fmt::format("{},{},{},,,,{:.9g},\n", c, params, sweep::to_string(t), paper);
      }
    }
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
