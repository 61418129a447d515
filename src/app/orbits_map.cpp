#include "app/orbits_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <functional>
#include <numbers>
#include <stdexcept>
#include <string>

#include "orbits/continuation.hpp"
#include "orbits/threshold_curves.hpp"
#include "physics/parameter_table.hpp"
#include "results/orbits_file.hpp"
#include "results/table.hpp"

namespace ajx::app {

namespace {

using namespace ajx::orbits;
constexpr double kPi = std::numbers::pi;

// The curves asked for: --curves, else every curve the model has (hopf with the clutch only).
std::vector<CurveKind> kinds_asked(const OrbitsArgs& args, const physics::Model& m) {
  std::vector<CurveKind> out;
  if (args.map_curves.empty()) {
    out = {CurveKind::Fold, CurveKind::ConeUp, CurveKind::ConeDown};
    if (m.layers.tie_clutch && m.p.drive_radius > 0) out.push_back(CurveKind::Hopf);
    return out;
  }
  for (const std::string& name : args.map_curves) out.push_back(curve_kind(name));
  return out;
}

// One row of the curves' table: a point of a curve, or a codimension-2 point on it.
struct MapRow {
  int curve = 0;
  CurveKind kind;
  double s = 0;
  std::string what;  // "curve" or the codimension-2 kind
  CurvePoint pt;
};

using MapColumn = results::ColumnSpec<MapRow>;
const std::vector<MapColumn>& map_columns() {
  static const std::vector<MapColumn> cols{
      {"curve_id", "1", [](const MapRow& r) { return double(r.curve); }},
      {"kind", "0 fold, 1 cone_up, 2 cone_down, 3 hopf", [](const MapRow& r) { return double(r.kind); }},
      {"s", "m", [](const MapRow& r) { return r.s; }},
      {"p", "the second parameter's unit", [](const MapRow& r) { return r.pt.p; }},
      {"omega_m", "rad/s", [](const MapRow& r) { return r.pt.omega_m; }},
      {"omega", "rad/s (the orbit's frame: omega_ball for hopf)", [](const MapRow& r) { return r.pt.omega; }},
      {"rho1", "m", [](const MapRow& r) { return r.pt.orbit.rho1; }},
      {"z1", "m", [](const MapRow& r) { return r.pt.orbit.z1; }},
      {"rho2", "m", [](const MapRow& r) { return r.pt.orbit.rho2; }},
      {"z2", "m", [](const MapRow& r) { return r.pt.orbit.z2; }},
      {"T1", "N", [](const MapRow& r) { return r.pt.orbit.T1; }},
      {"T2", "N", [](const MapRow& r) { return r.pt.orbit.T2; }},
      {"margin_up", "N", [](const MapRow& r) { return r.pt.orbit.margins.up; }},
      {"margin_down", "N", [](const MapRow& r) { return r.pt.orbit.margins.down; }},
      {"admissible", "1", [](const MapRow& r) { return double(r.pt.orbit.admissible); }},
      {"unstable", "1 (locked orbit; -1 for hopf)", [](const MapRow& r) { return r.kind == CurveKind::Hopf ? -1.0 : double(r.pt.unstable); }},
      {"frequency", "rad/s", [](const MapRow& r) { return r.pt.frequency; }},
      {"torque", "N m", [](const MapRow& r) { return r.pt.torque; }},
      {"sigma_min", "1", [](const MapRow& r) { return r.pt.sigma_min; }},
  };
  return cols;
}

void write_map_csv(const std::string& path, const std::string& parameter, const std::vector<MapRow>& rows) {
  results::TextColumns text{{"row", {}}, {"parameter", std::vector<std::string>(rows.size(), parameter)}};
  for (const MapRow& r : rows) text[0].second.push_back(r.what);
  results::write_csv(path, results::tabulate(map_columns(), rows), text);
}

// The parameter's symbol and unit, from the parameter table (s: the bead's position).
std::pair<std::string, std::string> parameter_label(const std::string& name) {
  if (name == "s") return {"s", "m"};
  if (const physics::ParameterInfo* p = physics::find_parameter(name)) return {std::string(p->symbol), std::string(p->unit)};
  if (const physics::ParameterAlias* a = physics::find_alias(name)) return {std::string(a->symbol), std::string(a->unit)};
  return {name, ""};
}

void write_map_h5(const OrbitsArgs& args, const config::OrbitsConfig& cfg, const std::vector<MapRow>& points,
                  const std::vector<MapRow>& meets, const std::vector<std::string>& stops) {
  const auto [symbol, unit] = parameter_label(args.map_parameter);
  results::CurvesOutput c{args.map_parameter, symbol, unit, {}, stops, results::tabulate(map_columns(), points),
                          results::tabulate(map_columns(), meets), {}};
  for (CurveKind k : {CurveKind::Fold, CurveKind::ConeUp, CurveKind::ConeDown, CurveKind::Hopf})
    c.kinds.emplace_back(to_string(k));  // by code, as the column `kind`
  for (const MapRow& r : meets) c.codim2_names.push_back(r.what);
  results::write_curves_file(args.output, args.command_line, cfg, c);
}

std::string omega_pi(double w) { return std::isfinite(w) ? fmt::format("{:.5f}π", w / kPi) : std::string("-"); }

// The curve on stdout: its ends, a few of its points, its codimension-2 points.
void print_curve(int id, const Curve& c, const std::string& P) {
  const auto [plo, phi] = std::minmax_element(c.points.begin(), c.points.end(),
                                              [](const CurvePoint& a, const CurvePoint& b) { return a.p < b.p; });
  std::printf("\ncurve %d: %s at s = %.4f m, %zu points, %s in [%g, %g]\n  %s\n", id,
              std::string(to_string(c.kind)).c_str(), c.s, c.points.size(), P.c_str(), plo->p, phi->p,
              c.stop_reason.c_str());
  std::printf("  %14s %13s %13s %8s %8s %9s %9s  %s\n", P.c_str(), "omega_m", "omega", "rho1", "rho2", "up [N]",
              "down [N]", c.kind == CurveKind::Hopf ? "Im l [rad/s]" : "locked orbit");
  const std::size_t n = c.points.size(), rows = std::min<std::size_t>(n, 9);
  for (std::size_t k = 0; k < rows; ++k) {
    const CurvePoint& q = c.points[rows > 1 ? k * (n - 1) / (rows - 1) : 0];
    const std::string last = c.kind == CurveKind::Hopf ? fmt::format("{:.4f}", q.frequency)
                                                       : std::string(q.unstable ? "unstable" : "stable") +
                                                             (q.orbit.admissible ? ", held" : ", not held");
    std::printf("  %14.6g %13s %13s %8.4f %8.4f %9.4f %9.4f  %s\n", q.p, omega_pi(q.omega_m).c_str(),
                omega_pi(q.omega).c_str(), q.orbit.rho1, q.orbit.rho2, q.orbit.margins.up, q.orbit.margins.down,
                last.c_str());
  }
  for (const Codim2Point& m : c.meets)
    std::printf("  codim-2: %-50s at %s = %.6g, omega_m = %s\n", m.kind.c_str(), P.c_str(), m.at.p,
                omega_pi(m.at.omega_m).c_str());
}

}  // namespace

void check_map_args(const OrbitsArgs& args, const config::OrbitsConfig& cfg) {
  if (args.map_parameter.empty()) {
    if (!args.map_curves.empty() || !args.curves_csv.empty())
      throw config::ConfigError("--curves and --curves-csv belong to --map PARAM");
    return;
  }
  const auto& allowed = second_parameters();
  if (std::find(allowed.begin(), allowed.end(), args.map_parameter) == allowed.end())
    throw config::ConfigError(fmt::format("--map '{}': not a continuation parameter; allowed: {}", args.map_parameter,
                                          fmt::join(allowed, ", ")));
  if (!args.parameter.empty() || args.lag || args.thresholds || !args.compare.empty())
    throw config::ConfigError("--map cannot be combined with --continue, --lag, --thresholds or --compare");
  if (cfg.orbits.s.empty()) throw config::ConfigError("--map: give the bead's stuck position with --s (repeatable)");
  for (const std::string& name : args.map_curves) {
    try {
      if (curve_kind(name) == CurveKind::Hopf && !cfg.model.layers.tie_clutch)
        throw config::ConfigError(fmt::format("{}: --curves hopf needs the slipping tie: key 'layers.tie' must be "
                                              "\"clutch\"",
                                              cfg.source_name));
    } catch (const std::invalid_argument& e) {
      throw config::ConfigError(std::string("--curves: ") + e.what());
    }
  }
  if (args.range.size() == 2 && args.map_parameter != "s") {
    const orbits::OrbitProblem probe{cfg.model, 1.0, Closure::Stuck, cfg.orbits.s.front()};
    const double v = parameter_value(probe, args.map_parameter);
    if (!(v >= args.range[0] && v <= args.range[1]))
      throw config::ConfigError(fmt::format("--range {} {}: must contain the model's {} = {}", args.range[0],
                                            args.range[1], args.map_parameter, v));
  }
}

int orbits_map(const config::OrbitsConfig& cfg, const std::vector<double>& omegas, const OrbitsArgs& args) {
  const physics::Model& m = cfg.model;
  const std::string& P = args.map_parameter;
  CurveOptions opt;
  if (args.range.size() == 2) {
    opt.p_lo = args.range[0];
    opt.p_hi = args.range[1];
  }
  if (!args.omega.empty()) opt.start_omega = omegas;  // else the defaults of CurveOptions
  std::printf("\ntwo-parameter continuation: the threshold curves in the plane (%s, omega_m), bead stuck at s\n",
              P.c_str());
  std::vector<MapRow> points, meets;
  std::vector<std::string> stops;
  int id = 0;
  for (double s : cfg.orbits.s) {
    const std::vector<CurveKind> kinds = kinds_asked(args, m);
    const std::vector<Curve> curves = threshold_curves(m, P, kinds, s, opt);
    for (CurveKind kind : kinds)
      if (std::none_of(curves.begin(), curves.end(), [&](const Curve& c) { return c.kind == kind; }))
        std::printf("\nno %s point at s = %.4f m for the model's %s (none on the branches continued in omega)\n",
                    std::string(to_string(kind)).c_str(), s, P.c_str());
    for (const Curve& c : curves) {
      ++id;
      print_curve(id, c, P);
      stops.push_back(fmt::format("curve {}: {}", id, c.stop_reason));
      for (const CurvePoint& q : c.points) points.push_back({id, c.kind, s, "curve", q});
      for (const Codim2Point& q : c.meets) meets.push_back({id, c.kind, s, q.kind, q.at});
    }
  }
  try {
    if (!args.curves_csv.empty()) {
      std::vector<MapRow> all = points;
      all.insert(all.end(), meets.begin(), meets.end());
      write_map_csv(args.curves_csv, P, all);
    }
    if (!args.output.empty()) write_map_h5(args, cfg, points, meets, stops);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace ajx::app
