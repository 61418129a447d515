#include "bench/matched_table.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

namespace ajx::bench {

double MatchedPoint::cpu_min() const {
  return cpu.empty() ? std::numeric_limits<double>::quiet_NaN() : *std::min_element(cpu.begin(), cpu.end());
}

double MatchedPoint::cpu_median() const {
  if (cpu.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::vector<double> c = cpu;
  std::sort(c.begin(), c.end());
  const std::size_t n = c.size();
  return n % 2 ? c[n / 2] : 0.5 * (c[n / 2 - 1] + c[n / 2]);
}

const MatchedPoint* cheapest(const std::vector<MatchedPoint>& points, const std::string& method,
                             const std::string& family, double target) {
  const MatchedPoint* best = nullptr;
  for (const MatchedPoint& p : points)
    if (p.method == method && p.family == family && p.reaches(target) && (!best || p.cpu_min() < best->cpu_min())) best = &p;
  return best;
}

bool is_project(const std::string& method) { return method.rfind("astrojax", 0) == 0; }
bool is_cvode_adams(const std::string& method) { return method.find("CVODE Adams") != std::string::npos; }

namespace {
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// The (method, family) pairs in the order of the points.
using Key = std::pair<std::string, std::string>;
std::vector<Key> method_names(const std::vector<MatchedPoint>& points) {
  std::vector<Key> names;
  for (const MatchedPoint& p : points)
    if (std::find(names.begin(), names.end(), Key{p.method, p.family}) == names.end())
      names.push_back({p.method, p.family});
  return names;
}

// The project's CPU and the fastest peer's (name, CPU) in a family at a target.
struct Family {
  double project = nan, peer = nan;
  std::string peer_name;
};
Family family(const std::vector<MatchedPoint>& points, const std::string& fam, double target) {
  Family f;
  for (const auto& [m, f_m] : method_names(points)) {
    const MatchedPoint* p = cheapest(points, m, f_m, target);
    if (!p || f_m != fam) continue;
    if (is_project(m)) f.project = p->cpu_min();
    else if (std::isnan(f.peer) || p->cpu_min() < f.peer) f.peer = p->cpu_min(), f.peer_name = m;
  }
  return f;
}
}  // namespace

MatchedRatios ratios(const std::vector<MatchedPoint>& points, double target) {
  MatchedRatios r;
  const Family with = family(points, "guarantee", target), without = family(points, "no guarantee", target);
  r.with_guarantee = with.peer / with.project;
  r.fastest_with = with.peer_name;
  r.without_guarantee = without.peer / without.project;
  r.fastest_without = without.peer_name;
  double cvode = nan;
  for (const auto& [m, f_m] : method_names(points))
    if (const MatchedPoint* p = cheapest(points, m, f_m, target); p && is_cvode_adams(m) && f_m == "no guarantee")
      cvode = p->cpu_min();
  r.cvode_over_plain = cvode / without.project;
  r.cvode_over_default = cvode / with.project;
  r.guarantee_cost = with.project / without.project - 1.0;
  return r;
}

std::string matched_csv_header() {
  return "scene,horizon_s,method,family,rtol,status,err_position_m,same_final_mode,evals,rounds,cpu_min_s,cpu_median_s,"
         "reference_floor_m";
}

std::string matched_csv_line(const MatchedPoint& p, double floor) {
  return fmt::format("{},{},\"{}\",{},{:.3g},\"{}\",{:.6e},{},{},{},{:.6e},{:.6e},{:.6e}", p.scene, p.horizon, p.method,
                     p.family, p.rtol, p.status, p.error, p.same_mode ? 1 : 0, p.evals, p.cpu.size(), p.cpu_min(),
                     p.cpu_median(), floor);
}

std::string matched_tables(const std::vector<MatchedPoint>& points, const std::vector<double>& targets) {
  if (points.empty()) return "";
  std::string out;
  for (double target : targets) {
    out += fmt::format("  {} at {:g} s, error <= {:.0e} m (min CPU over rounds):\n", points.front().scene,
                       points.front().horizon, target);
    for (const auto& [m, f_m] : method_names(points)) {
      const MatchedPoint* p = cheapest(points, m, f_m, target);
      if (p)
        out += fmt::format("    {:<14} {:<34} {:8.3f} ms  rtol {:.0e}  err {:.1e} m  evals {:>7}  {:4.0f} ns/eval\n",
                           f_m, m, 1e3 * p->cpu_min(), p->rtol, p->error, p->evals,
                           1e9 * p->cpu_min() / double(std::max(1L, p->evals)));
      else
        out += fmt::format("    {:<14} {:<34}  not reached\n", f_m, m);
    }
    const MatchedRatios r = ratios(points, target);
    out += fmt::format("    ratio fastest peer / astrojax, with the guarantee:    {:.2f} ({})\n", r.with_guarantee,
                       r.fastest_with);
    out += fmt::format("    ratio fastest peer / astrojax, without the guarantee: {:.2f} ({})\n",
                       r.without_guarantee, r.fastest_without);
    out += fmt::format("    ratio CVODE Adams / astrojax: {:.1f} (no guarantee), {:.1f} (default)\n",
                       r.cvode_over_plain, r.cvode_over_default);
    out += fmt::format("    cost of the guarantee (default / no guarantee - 1): {:+.0f} %\n", 100.0 * r.guarantee_cost);
  }
  return out;
}

std::string matched_summary(const std::vector<MatchedPoint>& points, const std::vector<double>& targets) {
  std::string out =
      "| scene | horizon | error | fastest peer / astrojax, with the guarantee | without the guarantee | "
      "CVODE Adams + roots / astrojax (without, default) | cost of the guarantee |\n|---|---|---|---|---|---|---|\n";
  std::vector<std::pair<std::string, double>> cases;
  for (const MatchedPoint& p : points)
    if (std::find(cases.begin(), cases.end(), std::pair{p.scene, p.horizon}) == cases.end())
      cases.push_back({p.scene, p.horizon});
  const auto ratio = [](double r, const std::string& who) {
    return std::isnan(r) ? std::string("not reached") : fmt::format("{:.2f} ({})", r, who);
  };
  for (const auto& [scene, horizon] : cases) {
    std::vector<MatchedPoint> sub;
    for (const MatchedPoint& p : points)
      if (p.scene == scene && p.horizon == horizon) sub.push_back(p);
    for (double target : targets) {
      const MatchedRatios r = ratios(sub, target);
      out += fmt::format("| {} | {:g} s | {:.0e} m | {} | {} | {:.1f}, {:.1f} | {:+.0f} % |\n", scene, horizon, target,
                         ratio(r.with_guarantee, r.fastest_with), ratio(r.without_guarantee, r.fastest_without),
                         r.cvode_over_plain, r.cvode_over_default, 100.0 * r.guarantee_cost);
    }
  }
  return out;
}

}  // namespace ajx::bench
