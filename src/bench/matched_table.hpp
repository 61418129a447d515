// The matched comparison's bookkeeping (astrojax_matched, docs/reports/matched-comparison.md):
// each (method, rtol) point's achieved error and its CPU times over interleaved rounds, the
// cheapest point of a method that reaches an error, and the ratios the targets are stated in.
// Knows nothing of solvers: the driver fills the points.
#pragma once
#include <string>
#include <vector>

namespace ajx::bench {

struct MatchedPoint {
  std::string scene;
  double horizon = 0.0;        // [s]
  std::string method, family;  // family: "guarantee" or "no guarantee"
  double rtol = 0.0;
  std::string status = "ok";
  long evals = 0;
  double error = 0.0;          // position error against the reference at the horizon [m]
  bool same_mode = true;       // the final contact mode agrees with the reference's
  std::vector<double> cpu;     // [s], one per round
  double cpu_min() const;
  double cpu_median() const;
  bool reaches(double target) const { return status == "ok" && same_mode && error <= target; }
};

// The point of `method` in `family` with the least minimum CPU among those reaching `target`,
// or nullptr.
const MatchedPoint* cheapest(const std::vector<MatchedPoint>& points, const std::string& method,
                             const std::string& family, double target);

// The project's method of a family (its name starts with "astrojax"), and whether a method is
// CVODE Adams (the 10x target's peer).
bool is_project(const std::string& method);
bool is_cvode_adams(const std::string& method);

// The ratios at one target error: the fastest peer's CPU over the project's in each family
// (>= 1: the project is at least as fast), CVODE Adams with its own root finding (the "no
// guarantee" family) over the project without the guarantee and over the default, and the guarantee's cost, default / no guarantee - 1. NaN where a
// side reaches no point.
struct MatchedRatios {
  double with_guarantee = 0.0, without_guarantee = 0.0;
  std::string fastest_with, fastest_without;
  double cvode_over_plain = 0.0, cvode_over_default = 0.0;
  double guarantee_cost = 0.0;
};
MatchedRatios ratios(const std::vector<MatchedPoint>& points, double target);

std::string matched_csv_header();
std::string matched_csv_line(const MatchedPoint& p, double floor);
// The printed tables: per target, each method's cheapest CPU [ms] with its error, then the ratios.
std::string matched_tables(const std::vector<MatchedPoint>& points, const std::vector<double>& targets);

// The ratios of every (scene, horizon) in the points at each target, as one Markdown table
// (the report's summary is this output).
std::string matched_summary(const std::vector<MatchedPoint>& points, const std::vector<double>& targets);

}  // namespace ajx::bench
