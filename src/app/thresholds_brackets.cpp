// astrojax thresholds on a sweep with [bisect] chains: the brackets of /brackets, one line (and
// one CSV row) per grid point and threshold, beside the ladder's brackets of the other chains.
#include "app/thresholds_brackets.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <numbers>
#include <sstream>

#include "config/text.hpp"
#include "sweep/bisection.hpp"
#include "sweep/orbit_classes.hpp"
#include "sweep/thresholds.hpp"

namespace ajx::app {

namespace {

constexpr double pi = std::numbers::pi;

std::string class_name(std::int32_t c) {
  return c < 0 ? std::string("-") : std::string(sweep::to_string(sweep::OrbitClass(c)));
}

// A bracket's two ends as the ladder's: before = the known side, after = past it.
struct Ends {
  double before = NAN, after = NAN;
  bool bracketed = false;
};
Ends ends(const results::BracketTable& t, std::size_t b) {
  Ends e{t.known_omega[b], t.other_omega[b], false};
  e.bracketed = t.status[b] == std::int32_t(sweep::BisectStatus::Converged) && std::isfinite(e.before) && std::isfinite(e.after);
  return e;
}

int probes_run(const results::BracketTable& t, std::size_t b) {
  int n = 0;
  for (std::size_t i = 0; i < t.probes.chain.size(); ++i)
    if (t.probes.chain[i] == t.chain[b] && t.probes.ran[i] == 1) ++n;
  return n;
}

std::string status_text(const results::BracketTable& t, std::size_t b) {
  const std::int32_t s = t.status[b];
  if (s < 0) return "not computed (the sweep was interrupted)";
  const auto st = sweep::BisectStatus(s);
  switch (st) {
    case sweep::BisectStatus::StartOffSide:
      return fmt::format("start not on the known side: {} at {:.3f}π", class_name(t.other_class[b]), t.other_omega[b] / pi);
    case sweep::BisectStatus::NoCrossing:
      return fmt::format("no crossing: still {} at {:.3f}π", class_name(t.known_class[b]), t.known_omega[b] / pi);
    default: return std::string(sweep::to_string(st));
  }
}

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

}  // namespace

bool is_bisection_chain(const results::SweepReader& in, std::size_t c) {
  if (!in.brackets()) return false;
  for (std::int64_t x : in.brackets()->chain)
    if (std::size_t(x) == c) return true;
  return false;
}

std::string bisection_report(const results::SweepReader& in, const ChainNames& names) {
  const results::BracketTable& t = *in.brackets();
  std::string out = "\nbisections (held levels; before = the threshold's known side, after = past it)\n";
  std::size_t w = 5;
  for (std::size_t b = 0; b < t.size(); ++b) w = std::max(w, names.label(std::size_t(t.chain[b])).size());
  const bool guided = !t.guide.empty();  // a column for the predictions the probes were put next to
  out += fmt::format("  {:<10} {:<{}} {:<22} {:>9} {:>9}  {:<36} {:<40} {:>6}{}\n", "threshold", "chain", w,
                     "bracket [π rad/s]", "width [π]", "paper [π]", "classes", "status", "probes",
                     guided ? "  guide [π]" : "");
  for (std::size_t b = 0; b < t.size(); ++b) {
    const auto c = std::size_t(t.chain[b]);
    const auto th = sweep::Threshold(t.threshold[b]);
    const Ends e = ends(t, b);
    const std::string bracket = e.bracketed ? fmt::format("{:.3f} → {:.3f}", e.before / pi, e.after / pi) : "none";
    const std::string width = e.bracketed ? fmt::format("{:.3f}", std::abs(e.after - e.before) / pi) : "";
    const std::string classes = fmt::format("{} → {}", class_name(t.known_class[b]), class_name(t.other_class[b]));
    const std::string guide = !guided ? "" : std::isnan(t.guide[b]) ? "  none" : fmt::format("  {:.3f}", t.guide[b] / pi);
    out += fmt::format("  {:<10} {:<{}} {:<22} {:>9} {:>9.2f}  {:<36} {:<40} {:>3}/{:<2}{}\n", sweep::to_string(th),
                       names.label(c), w, bracket, width, sweep::paper_value(th) / pi, classes, status_text(t, b),
                       probes_run(t, b), t.planned[b], guide);
  }
  return out;
}

std::string with_bisection_rows(const std::string& csv, const results::SweepReader& in, const ChainNames& names) {
  const results::BracketTable& t = *in.brackets();
  std::vector<std::string> lines = split_lines(csv);
  const std::size_t ladder_cols = std::size_t(std::count(lines.front().begin(), lines.front().end(), ',')) + 1;
  std::string axes_head;
  for (const std::string& a : in.axes()) axes_head += "," + config::printable(a);
  std::string out = lines.front() + ",group,variant" + axes_head +
                    ",method,width_rad_s,before_class,after_class,bisect_status,probes_run,start_seed\n";
  const auto axis_values = [&](std::size_t c) {
    std::string v;
    for (std::size_t a = 0; a < in.axes().size(); ++a) v += fmt::format(",{:.9g}", in.grid_values()(c, a));
    return v;
  };
  for (std::size_t i = 1; i < lines.size(); ++i) {  // the ladder's rows
    const std::size_t c = std::stoul(lines[i].substr(0, lines[i].find(',')));
    if (is_bisection_chain(in, c)) continue;
    out += lines[i] + fmt::format(",{},{}", names.group(c), names.variant(c)) + axis_values(c) + ",ladder,,,,,," + names.start(c) + "\n";
  }
  for (std::size_t b = 0; b < t.size(); ++b) {
    const auto c = std::size_t(t.chain[b]);
    const auto th = sweep::Threshold(t.threshold[b]);
    const Ends e = ends(t, b);
    const double paper = sweep::paper_value(th);
    std::string row = fmt::format("{},{},{}", c, names.params(c), sweep::to_string(th));
    if (e.bracketed) {
      const double mid = 0.5 * (e.before + e.after);
      row += fmt::format(",{:.9g},{:.9g},{:.9g},{:.9g},{:.6g}", e.before, e.after, mid, paper, (mid - paper) / paper);
    } else if (t.status[b] == std::int32_t(sweep::BisectStatus::NoCrossing)) {  // before: the last level, still known
      row += fmt::format(",{:.9g},,,{:.9g},", t.known_omega[b], paper);
    } else if (t.status[b] == std::int32_t(sweep::BisectStatus::StartOffSide)) {  // after: the start, already past
      row += fmt::format(",,{:.9g},,{:.9g},", t.other_omega[b], paper);
    } else {
      row += fmt::format(",,,,{:.9g},", paper);
    }
    row += std::string(ladder_cols - 8, ',');
    const std::int32_t s = t.status[b];
    row += fmt::format(",{},{}", names.group(c), names.variant(c)) + axis_values(c) +
           fmt::format(",bisection,{},{},{},{},{}", e.bracketed ? fmt::format("{:.9g}", std::abs(e.after - e.before)) : "",
                       class_name(t.known_class[b]), class_name(t.other_class[b]),
                       s < 0 ? std::string("not-computed") : fmt::format("\"{}\"", status_text(t, b)), probes_run(t, b));
    out += row + "," + names.start(c) + "\n";
  }
  return out;
}

}  // namespace ajx::app
