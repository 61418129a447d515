// astrojax orbits: the locked circular orbits at given ω_m (equilibria of the co-rotating
// frame), optionally continued in ω_m or a model parameter, and the thresholds predicted
// from the branches. Tables on stdout; CSV and HDF5 on request.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "app/orbits_map.hpp"
#include "results/orbits_file.hpp"
#include "results/table.hpp"
#include "results/sweep_reader.hpp"
#include "config/config.hpp"
#include "config/text.hpp"
#include "orbits/continuation.hpp"
#include "physics/parameter_table.hpp"
#include "orbits/lagging_orbit.hpp"
#include "orbits/orbit_families.hpp"
#include "orbits/orbit_stability.hpp"
#include "orbits/predicted_thresholds.hpp"
#include "sweep/thresholds.hpp"

namespace ajx::app {

namespace {

using namespace ajx::orbits;
constexpr double kPi = std::numbers::pi;

// One row of an output table: an orbit, its stability and where it came from.
struct Row {
  int id = 0;            // branch number (branch tables) or 0
  double lambda = 0.0;   // the continuation parameter's value (branch tables) or ω_m
  SteadyOrbit o;
  Stability st;
  int unstable = 0;
};

// The columns written to CSV and HDF5, with units.
using Column = results::ColumnSpec<Row>;
const std::vector<Column>& columns() {
  static const std::vector<Column> cols{
      {"branch_id", "1", [](const Row& r) { return double(r.id); }},
      {"lambda", "parameter", [](const Row& r) { return r.lambda; }},
      {"omega_m", "rad/s", [](const Row& r) { return r.o.omega; }},
      {"case", "0 stuck, 1 bottom_stop, 2 frictionless, 3 cone_up, 4 cone_down", [](const Row& r) { return double(r.o.closure); }},
      {"bead_side", "+1 on the top's side (x > 0), -1 opposite", [](const Row& r) { return r.o.p1.x() > 0 ? 1.0 : -1.0; }},
      {"ball_side", "+1 on the top's side (x > 0), -1 opposite", [](const Row& r) { return r.o.p2.x() > 0 ? 1.0 : -1.0; }},
      {"s", "m", [](const Row& r) { return r.o.s; }},
      {"x1", "m", [](const Row& r) { return r.o.p1.x(); }},
      {"y1", "m", [](const Row& r) { return r.o.p1.y(); }},
      {"z1", "m", [](const Row& r) { return r.o.p1.z(); }},
      {"x2", "m", [](const Row& r) { return r.o.p2.x(); }},
      {"y2", "m", [](const Row& r) { return r.o.p2.y(); }},
      {"z2", "m", [](const Row& r) { return r.o.p2.z(); }},
      {"rho1", "m", [](const Row& r) { return r.o.rho1; }},
      {"rho2", "m", [](const Row& r) { return r.o.rho2; }},
      {"phase1", "rad", [](const Row& r) { return r.o.phase1; }},
      {"phase2", "rad", [](const Row& r) { return r.o.phase2; }},
      {"T1", "N", [](const Row& r) { return r.o.T1; }},
      {"T2", "N", [](const Row& r) { return r.o.T2; }},
      {"contact", "N", [](const Row& r) { return r.o.contact; }},
      {"psi", "rad", [](const Row& r) { return r.o.psi; }},
      {"mu_required", "1", [](const Row& r) { return r.o.mu_required; }},
      {"margin_up", "N", [](const Row& r) { return r.o.margins.up; }},
      {"margin_down", "N", [](const Row& r) { return r.o.margins.down; }},
      {"admissible", "1", [](const Row& r) { return double(r.o.admissible); }},
      {"growth", "1/s", [](const Row& r) { return r.st.growth; }},
      {"frequency", "rad/s", [](const Row& r) { return r.st.frequency; }},
      {"unstable", "1", [](const Row& r) { return double(r.unstable); }},
      {"stable", "1", [](const Row& r) { return double(r.st.stable); }},
      {"residual", "1", [](const Row& r) { return r.o.residual; }},
  };
  return cols;
}

results::Table table_of(const std::vector<Row>& rows) { return results::tabulate(columns(), rows); }

Row make_row(const physics::Model& m, const SteadyOrbit& o, int id, double lambda) {
  Row r{id, lambda, o, stability({m, o.omega, o.closure, o.s}, unknowns(o)), 0};
  for (int i = 0; i < r.st.eigenvalues.size(); ++i) r.unstable += r.st.eigenvalues(i).real() > growth_noise(m, o.omega);
  return r;
}

std::string fmt_row(const Row& r) {
  return fmt::format("  {:<13}{:<7}{:>7.4f}{:>8.4f}{:>9.4f}{:>8.4f}{:>9.4f}{:>8.3f}{:>8.4f}{:>8.4f}{:>8.4f}{:>7.3f}{:>8.3f}"
                     "{:>9.4f}{:>9.4f}{:>9.4f}{:>8.3f}  {}{}",
                     to_string(r.o.closure), r.o.branch, r.o.s, r.o.rho1, r.o.z1, r.o.rho2, r.o.z2,
                     std::remainder(r.o.phase2 - r.o.phase1, 2 * kPi), r.o.T1, r.o.T2, r.o.contact, r.o.psi,
                     r.o.mu_required, r.o.margins.up, r.o.margins.down,
                     r.st.growth, r.st.frequency, r.o.admissible ? "admissible" : "-",
                     r.st.stable ? " stable" : " unstable");
}
const char* kHeader =
    "  case         side     s    rho1       z1    rho2       z2    dphi      T1      T2     N_c    psi     mu*"
    "   up [N] down [N]  Re l[1/s] Im l[rad/s]";

// "4.7pi" or "14.77": a value in rad/s.
double parse_omega(const std::string& text) {
  std::string t = text;
  double factor = 1.0;
  for (const char* suffix : {"pi", "π"}) {
    const std::string s(suffix);
    if (t.size() > s.size() && t.compare(t.size() - s.size(), s.size(), s) == 0) {
      t.resize(t.size() - s.size());
      factor = kPi;
    }
  }
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(t, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != t.size() || !(v * factor > 0.0) || v * factor > 2000.0)
    throw config::ConfigError(fmt::format("--omega '{}': expected a number in (0, 2000] rad/s, or a multiple of π "
                                          "written like 4.7pi",
                                          text));
  return v * factor;
}

// The stuck family summarised per side pattern: the intervals of s where it is admissible,
// and where it is also stable.
void print_family(const std::vector<Row>& stuck) {
  std::map<std::string, std::vector<const Row*>> by;
  for (const Row& r : stuck) by[r.o.branch].push_back(&r);
  for (const auto& [branch, rows] : by) {
    std::string adm, both;
    const auto intervals = [&](auto pred) {
      std::string out;
      std::optional<double> lo;
      double last = 0;
      std::map<double, bool> at;  // s → any orbit of this pattern satisfies pred
      for (const Row* r : rows) at[r->o.s] = at[r->o.s] || pred(*r);
      for (const auto& [s, ok] : at) {
        if (ok && !lo) lo = s;
        if (!ok && lo) {
          out += fmt::format(" [{:.4f}, {:.4f}]", *lo, last);
          lo.reset();
        }
        last = s;
      }
      if (lo) out += fmt::format(" [{:.4f}, {:.4f}]", *lo, last);
      return out.empty() ? std::string(" none") : out;
    };
    adm = intervals([](const Row& r) { return r.o.admissible; });
    both = intervals([](const Row& r) { return r.o.admissible && r.st.stable; });
    std::printf("    side %s: held by friction for s in%s m; held and stable for s in%s m\n", branch.c_str(),
                adm.c_str(), both.c_str());
  }
}

// The brackets of a sweep's chains whose model equals m (every parameter the file records in
// chains/model; older files lack some, and are matched on those they have), as `astrojax
// thresholds` finds them. Throws on a file that is not a sweep's.
struct SweepBrackets {
  std::vector<std::size_t> chains;  // the matching chains
  std::vector<std::string> lacking;  // parameters the file does not record
  std::map<std::string, std::vector<std::optional<sweep::Bracket>>> by_symbol;
};
SweepBrackets sweep_brackets(const std::string& path, const physics::Model& m) {
  const results::SweepReader in(path);
  const auto &cls = in.classes(), &dir = in.direction();
  const auto &wb = in.omega_m_begin(), &we = in.omega_m_end();
  const results::StoredModels& models = in.models();
  SweepBrackets out;
  out.lacking = models.lacking;
  for (std::size_t c = 0; c < cls.rows(); ++c) {
    bool same = true;
    for (const std::string& key : models.present) {
      const double mine = physics::parameter(m.p, key);
      same = same && std::abs(physics::parameter(models.chains[c], key) - mine) <= 1e-12 * std::abs(mine);
    }
    if (!same) continue;
    std::vector<sweep::ClassedWindow> w;
    for (std::size_t k = 0; k < cls.cols(); ++k)
      if (cls(c, k) >= 0 && std::isfinite(wb(c, k)))
        w.push_back({wb(c, k), we(c, k), dir(c, k), static_cast<sweep::OrbitClass>(cls(c, k))});
    out.chains.push_back(c);
    const auto rise = sweep::find_threshold(sweep::Threshold::Rise, w);
    out.by_symbol["omega_rise"].push_back(rise);
    out.by_symbol["omega_rise_cone"].push_back(rise);
    out.by_symbol["omega_fall"].push_back(sweep::find_threshold(sweep::Threshold::Fall, w));
    out.by_symbol["omega1"].push_back(sweep::find_threshold(sweep::Threshold::Omega1, w));
  }
  return out;
}


// --lag: the lagging orbits of the slipping tie (orbits/lagging_orbit.hpp) with the bead stuck
// at each s: those at each ω_m, then each held one's branch continued in ω_ball with its events.
std::string_view to_string(LagEventKind k) {
  switch (k) {
    case LagEventKind::StabilityLoss: return "loss";
    case LagEventKind::StabilityGain: return "gain";
    case LagEventKind::ConeExit: return "cone_exit";
    case LagEventKind::ConeEntry: return "cone_entry";
  }
  return "?";
}

// One lagging orbit as a table line.
std::string lag_line(const LagOrbit& L) {
  const std::string wm = std::isfinite(L.omega_m) ? fmt::format("{:>10.3f}π", L.omega_m / kPi) : fmt::format("{:>11}", "-");
  return fmt::format("{:<6}{:>10.5f}π{:>12.5e}{}{:>8.4f}{:>9.4f}{:>8.4f}{:>9.4f}{:>9.4f}{:>9.4f}{:>10.4f}{:>8.3f}  {}{}",
                     L.orbit.branch, L.orbit.omega / kPi, L.torque, wm, L.orbit.rho1, L.orbit.z1,
                     L.orbit.rho2, L.orbit.z2, L.orbit.margins.up, L.orbit.margins.down, L.st.growth, L.st.frequency,
                     L.orbit.admissible ? "held" : "slides", L.st.stable ? " stable" : " unstable");
}

// A row of the --lag CSV: the bead position, what the row is, the orbit.
struct LagCsvRow {
  double s;
  std::string kind;
  LagOrbit L;
};

// The branches through `starts` continued over ω_ball in [lo, hi], printed with their events
// and their held and stable runs; the events into rows.
void lag_branches(const physics::Model& m, double s, const std::vector<LagOrbit>& starts, double lo, double hi,
                  std::vector<LagCsvRow>& rows) {
  std::vector<LagBranch> done;
  for (const LagOrbit& start : starts) {
    // A start already on a branch continued (the sides meet at folds) adds nothing.
    if (std::any_of(done.begin(), done.end(),
                    [&](const LagBranch& b) { return on_branch(b.points, start.orbit, m.p.string_length); }))
      continue;
    const LagBranch& br = done.emplace_back(lag_branch(m, start.orbit, lo, hi));
    std::printf("  branch of side %s continued over omega_ball in [%.3fπ, %.3fπ] (%zu points), events as tau grows:\n",
                start.orbit.branch.c_str(), lo / kPi, hi / kPi, br.points.size());
    for (const LagEvent& e : br.events) {
      const std::string kind = std::string(to_string(e.kind)) + (e.complex_pair ? " (hopf)" : "");
      std::printf("    %-12s%s\n", kind.c_str(), lag_line(e.at).c_str());
      rows.push_back({s, kind, e.at});
    }
    // The runs of the branch where the lag is both held by friction and stable.
    std::optional<std::size_t> first;
    for (std::size_t i = 0; i <= br.points.size(); ++i) {
      const bool ok = i < br.points.size() && br.points[i].orbit.admissible && br.points[i].st.stable;
      if (ok && !first) first = i;
      if (!ok && first) {
        const LagOrbit &a = br.points[*first], &b = br.points[i - 1];
        std::printf("    held and stable (branch points): omega_ball %.4fπ .. %.4fπ, tau %.4e .. %.4e N m\n",
                    a.orbit.omega / kPi, b.orbit.omega / kPi, a.torque, b.torque);
        first.reset();
      }
    }
  }
}

int lag_report(const config::OrbitsConfig& cfg, const std::vector<double>& omegas, const OrbitsArgs& args) {
  const physics::Model& m = cfg.model;
  const physics::Parameters& p = m.p;
  const double lo = args.range.size() == 2 ? args.range[0] : 2.0 * kPi;
  const double hi = args.range.size() == 2 ? args.range[1] : 7.0 * kPi;
  std::printf("\nlagging orbits of the slipping tie: tau = tau_k + c_a (omega_m - omega_ball), tau_k %g N m, c_a %g N m s, "
              "I_a %g kg m^2;\n  positions in the frame turning with the tie at omega_ball, tie at (R, 0, 0); "
              "stable: all eigenvalues but the symmetry's Re l < 0\n",
              p.tie_kinetic_torque, p.tie_damping, p.tie_inertia);
  std::vector<LagCsvRow> rows;
  const char* header = "    side  omega_ball    tau [N m]   omega_m    rho1       z1    rho2       z2   up [N] down [N]  Re l[1/s] Im l";
  for (double s : cfg.orbits.s) {
    std::printf("\ns = %.4f m\n", s);
    std::vector<LagOrbit> starts;
    for (double w : omegas) {
      std::printf("  at omega_m = %.5fπ:\n%s\n", w / kPi, header);
      const std::vector<LagOrbit> lags = lag_orbits(m, s, w);
      if (lags.empty()) std::printf("    none with omega_ball in (%.3fπ, %.3fπ)\n", 0.1 * w / kPi, w / kPi);
      for (const LagOrbit& L : lags) {
        std::printf("%s\n", ("  " + lag_line(L)).c_str());
        rows.push_back({s, "lag", L});
        const bool new_side = std::none_of(starts.begin(), starts.end(),
                                           [&](const LagOrbit& q) { return q.orbit.branch == L.orbit.branch; });
        if (L.orbit.admissible && new_side) starts.push_back(L);
      }
    }
    // Also the held stuck orbits at the middle of the ω_ball range, so that a branch is found
    // whatever τ the clutch passes at the given ω_m.
    for (const SteadyOrbit& o : orbits_at({m, 0.5 * (lo + hi), Closure::Stuck, s}))
      if (o.admissible) starts.push_back({o, std::numeric_limits<double>::quiet_NaN(), tie_drive_torque(m, o), {}});
    lag_branches(m, s, starts, lo, hi, rows);
  }
  if (!args.csv.empty()) {
    std::ofstream out(args.csv);
    if (!out) {
      std::fprintf(stderr, "error: cannot write %s\n", args.csv.c_str());
      return 1;
    }
    out << "s,kind,side,omega_ball,torque,omega_m,rho1,z1,rho2,z2,margin_up,margin_down,admissible,growth,frequency,stable\n";
    for (const LagCsvRow& r : rows)
      out << fmt::format("{:.12g},{},{},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{},{:.12g},"
                         "{:.12g},{}\n",
                         r.s, r.kind, r.L.orbit.branch, r.L.orbit.omega, r.L.torque, r.L.omega_m, r.L.orbit.rho1,
                         r.L.orbit.z1, r.L.orbit.rho2, r.L.orbit.z2, r.L.orbit.margins.up, r.L.orbit.margins.down,
                         int(r.L.orbit.admissible), r.L.st.growth, r.L.st.frequency, int(r.L.st.stable));
  }
  return 0;
}

// ---- parse: the config file with the command line's choices -------------------------------

// The orbits config and the ω_m values to look at; throws config::ConfigError on bad input.
config::OrbitsConfig parse_orbits(const OrbitsArgs& args, std::vector<double>& omegas) {
  config::OrbitsConfig cfg = config::load_orbits_config(args.config_path, args.overrides);
  for (const auto& w : args.omega) omegas.push_back(parse_omega(w));
  if (omegas.empty()) omegas = cfg.orbits.omega;
  if (omegas.empty())
    throw config::ConfigError(fmt::format("{}: key 'orbits.omega': missing; give it there or with --omega",
                                          cfg.source_name));
  if (args.s_points > 0) cfg.orbits.s_points = args.s_points;
  if (!args.parameter.empty()) {
    const auto& names = continuation_parameters();
    if (std::find(names.begin(), names.end(), args.parameter) == names.end())
      throw config::ConfigError(fmt::format("--continue '{}': allowed: {}", args.parameter, fmt::join(names, ", ")));
    cfg.orbits.parameter = args.parameter;
  }
  if (args.range.size() == 2) {
    if (!(args.range[0] < args.range[1])) throw config::ConfigError("--range LO HI: expected LO < HI");
    cfg.orbits.range_lo = args.range[0];
    cfg.orbits.range_hi = args.range[1];
  }
  const physics::Parameters& p = cfg.model.p;
  for (double s : args.s) {
    if (!(s > p.top_stop && s <= p.string_length - p.contact_distance))
      throw config::ConfigError(fmt::format("--s {}: allowed ({}, {}] m (the stops)", s, p.top_stop,
                                            p.string_length - p.contact_distance));
    cfg.orbits.s.push_back(s);
  }
  if (args.lag && !cfg.model.layers.tie_clutch)
    throw config::ConfigError(fmt::format("{}: --lag needs the slipping tie: key 'layers.tie' must be \"clutch\"",
                                          cfg.source_name));
  if (args.lag && cfg.orbits.s.empty())
    throw config::ConfigError("--lag: give the bead's position with --s (repeatable)");
  if (args.lag && !(p.drive_radius > 0.0))
    throw config::ConfigError(fmt::format("{}: --lag needs key 'model.drive_radius' > 0", cfg.source_name));
  check_map_args(args, cfg);
  return cfg;
}

void print_model(const config::OrbitsConfig& cfg) {
  const physics::Model& m = cfg.model;
  const physics::Parameters& p = m.p;
  std::printf("# astrojax orbits %s: l %g m, m1 %g kg, m2 %g kg, c_D %g kg/s, R %g m, d %g m, s_min %g m, mu_s %g "
              "(%s, %s)\n",
              cfg.source_name.c_str(), p.string_length, p.bead_mass, p.ball_mass, p.drag, p.drive_radius,
              p.contact_distance, p.top_stop, p.mu_static, std::string(physics::to_string(m.layers.friction)).c_str(),
              std::string(physics::to_string(m.layers.friction_law)).c_str());
  std::printf("# positions in the frame turning with the motor, top at (R, 0, 0); side: bead/ball at x > 0 (+) or "
              "x < 0 (-); dphi: azimuth of the ball minus the bead's\n");
}

// ---- execute: the orbits, the branches, the predicted thresholds -----------------------------

// 1. The orbits at each ω_m, printed; the rows of the orbit table.
std::vector<Row> orbit_table(const config::OrbitsConfig& cfg, const std::vector<double>& omegas, bool all) {
  const physics::Model& m = cfg.model;
  std::vector<Row> table;
  for (double w : omegas) {
    const OrbitCatalogue cat = find_orbits(m, w, {cfg.orbits.s_points});
    std::printf("\nomega_m = %.6f rad/s (%.5fπ)\n", w, w / kPi);
    std::vector<Row> stuck;
    for (const auto& o : cat.stuck) stuck.push_back(make_row(m, o, 0, w));
    std::printf("  stuck family on %d bead positions from the top stop to the bottom stop:\n", cfg.orbits.s_points);
    print_family(stuck);
    std::vector<Row> shown;
    for (const auto* list : {&cat.bottom, &cat.frictionless, &cat.edges})
      for (const auto& o : *list) shown.push_back(make_row(m, o, 0, w));
    if (all) shown.insert(shown.end(), stuck.begin(), stuck.end());
    std::printf("%s\n", kHeader);
    for (const Row& r : shown) std::printf("%s\n", fmt_row(r).c_str());
    table.insert(table.end(), shown.begin(), shown.end());
    if (!all) table.insert(table.end(), stuck.begin(), stuck.end());
  }
  return table;
}

// The branches' points and events (with each event's kind and note).
struct Branches {
  std::vector<Row> points, events;
  std::vector<std::string> event_kind, event_note;
};

// 2. Continuation in cfg.orbits.parameter from the orbits at ω_m = w0, both directions, printed.
Branches continue_orbits(const config::OrbitsConfig& cfg, double w0) {
  const physics::Model& m = cfg.model;
  const physics::Parameters& p = m.p;
  Branches out;
  const std::string& P = cfg.orbits.parameter;
  const OrbitCatalogue cat = find_orbits(m, w0, {cfg.orbits.s_points});
  std::vector<SteadyOrbit> starts;
  if (P != "s") {
    starts = cat.bottom;
    starts.insert(starts.end(), cat.frictionless.begin(), cat.frictionless.end());
    starts.insert(starts.end(), cat.edges.begin(), cat.edges.end());
  }
  for (double s : cfg.orbits.s)
    for (const auto& o : orbits_at({m, w0, Closure::Stuck, s})) starts.push_back(o);
  ContinuationOptions copt;
  OrbitProblem probe{m, w0, Closure::Stuck, 0.5 * p.string_length};
  const double v0 = parameter_value(probe, P);
  copt.lambda_min = cfg.orbits.range_lo;
  copt.lambda_max = cfg.orbits.range_hi;
  if (!(copt.lambda_min < copt.lambda_max)) {
    if (P == "omega") copt.lambda_min = 0.5, copt.lambda_max = 20 * kPi;
    else if (P == "s") copt.lambda_min = p.top_stop, copt.lambda_max = p.string_length - p.contact_distance;
    else copt.lambda_min = 0.5 * v0, copt.lambda_max = 2.0 * v0;
  }
  std::printf("\ncontinuation in %s over [%g, %g] from %zu orbits at omega_m = %.6f rad/s, both directions\n",
              P.c_str(), copt.lambda_min, copt.lambda_max, starts.size(), w0);
  std::printf("  %-4s %-13s %-5s %-3s %-15s %14s %9s %9s %9s %10s  %s\n", "id", "case", "side", "dir", "event", P.c_str(),
              "s [m]", "rho1 [m]", "rho2 [m]", "Im l", "note");
  int id = 0;
  for (const auto& o : starts)
    for (int dir : {-1, +1}) {
      ++id;
      copt.direction = dir;
      OrbitProblem pb{m, w0, o.closure, o.s};
      const Branch b = continue_branch(pb, unknowns(o), P, copt);
      for (const auto& bp : b.points) {
        Row r{id, bp.lambda, bp.orbit, bp.stab, bp.unstable};
        out.points.push_back(r);
      }
      for (const auto& e : b.events) {
        std::printf("  %-4d %-13s %-5s %+-3d %-15s %14.6f %9.4f %9.4f %9.4f %10.4f  %s\n", id,
                    std::string(to_string(o.closure)).c_str(), o.branch.c_str(), dir,
                    std::string(to_string(e.kind)).c_str(), e.lambda, e.orbit.s, e.orbit.rho1, e.orbit.rho2,
                    e.frequency, e.note.c_str());
        Row r{id, e.lambda, e.orbit, {}, 0};
        r.st.frequency = e.frequency;
        out.events.push_back(r);
        out.event_kind.push_back(std::string(to_string(e.kind)));
        out.event_note.push_back(e.note);
      }
      std::printf("  %-4d %-13s %-5s %+-3d %-15s after %zu points\n", id, std::string(to_string(o.closure)).c_str(),
                  o.branch.c_str(), dir, b.stop_reason.c_str(), b.points.size());
    }
  return out;
}

// 3. The thresholds predicted from the branches, printed, and against the sweep args.compare.
// Returns the exit code: kExitBadInput when that sweep cannot be read.
int predict(const config::OrbitsConfig& cfg, const OrbitsArgs& args, std::optional<Predictions>& pred) {
  const physics::Model& m = cfg.model;
  PredictionOptions popt;
  popt.s_points = args.threshold_s_points;
  if (cfg.orbits.parameter == "omega" && cfg.orbits.range_lo < cfg.orbits.range_hi) {
    popt.omega_lo = cfg.orbits.range_lo;
    popt.omega_hi = cfg.orbits.range_hi;
  }
  pred = predict_thresholds(m, popt);
  std::printf("\nlocked intervals (stable, held by friction) of the branches, in omega_m:\n");
  for (const auto& iv : pred->intervals)
    std::printf("  s %.4f m side %s: [%.4fπ (%s), %.4fπ (%s)]\n", iv.s, iv.branch.c_str(), iv.omega_lo / kPi,
                iv.ends_lo.c_str(), iv.omega_hi / kPi, iv.ends_hi.c_str());
  std::printf("\npredicted thresholds (%d bead positions):\n  %-15s %12s %10s %10s  %s\n", popt.s_points, "symbol",
              "predicted", "", "paper", "mechanism");
  for (const auto& t : pred->thresholds)
    std::printf("  %-15s %12.5f %9.4fπ %9.2fπ  %s\n", t.symbol.c_str(), t.predicted, t.predicted / kPi,
                t.measured / kPi, t.mechanism.c_str());
  if (args.compare.empty()) return 0;
  SweepBrackets sb;
  try {
    sb = sweep_brackets(args.compare, m);
  } catch (const results::SweepFileError& e) {
    std::fprintf(stderr, "error: %s\n", config::printable(e.what()).c_str());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s: cannot read a sweep file: %s\n", args.compare.c_str(), config::printable(e.what()).c_str());
    return kExitBadInput;
  }
  std::printf("\nagainst the sweep %s (%zu chains with this model):\n", args.compare.c_str(), sb.chains.size());
  if (!sb.lacking.empty())
    std::printf("  (the file records %zu of the %zu model parameters, not %s; matched on those)\n",
                results::kModelColumns - sb.lacking.size(), results::kModelColumns, fmt::format("{}", fmt::join(sb.lacking, ", ")).c_str());
  for (const auto& t : pred->thresholds)
    for (std::size_t i = 0; i < sb.chains.size(); ++i) {
      const auto& b = sb.by_symbol[t.symbol][i];
      std::printf("  %-15s predicted %9.4fπ   chain %zu bracket %s\n", t.symbol.c_str(), t.predicted / kPi,
                  sb.chains[i],
                  b ? fmt::format("{:.3f}π .. {:.3f}π", b->before / kPi, b->after / kPi).c_str() : "not reached");
    }
  return 0;
}

// ---- report: the files asked for --------------------------------------------------------------

// CSV and HDF5 files; throws on a file that cannot be written.
void write_orbit_files(const OrbitsArgs& args, const config::OrbitsConfig& cfg, const std::vector<Row>& table,
                       const Branches& br, const std::optional<Predictions>& pred) {
  if (!args.csv.empty()) results::write_csv(args.csv, table_of(table));
  if (!args.branches_csv.empty()) results::write_csv(args.branches_csv, table_of(br.points));
  if (!args.events_csv.empty()) {
    std::ofstream out(args.events_csv);
    if (!out) throw std::runtime_error("cannot write " + args.events_csv);
    out << "branch_id,kind,lambda,s,rho1,rho2,z1,z2,frequency,note\n";
    for (std::size_t i = 0; i < br.events.size(); ++i) {
      const Row& r = br.events[i];
      out << fmt::format("{},{},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},\"{}\"\n", r.id,
                         br.event_kind[i], r.lambda, r.o.s, r.o.rho1, r.o.rho2, r.o.z1, r.o.z2, r.st.frequency,
                         br.event_note[i]);
    }
  }
  if (args.output.empty()) return;
  results::OrbitsOutput o{table_of(table), std::nullopt, std::nullopt};
  if (!br.points.empty())
    o.branches = results::OrbitsOutput::Branches{cfg.orbits.parameter, table_of(br.points), table_of(br.events),
                                                  br.event_kind};
  if (pred) {
    o.thresholds.emplace();
    for (const auto& t : pred->thresholds) o.thresholds->push_back({t.symbol, t.predicted, t.measured, t.mechanism});
  }
  results::write_orbits_file(args.output, args.command_line, cfg, o);
}

}  // namespace

int orbits_command(const OrbitsArgs& args) {
  config::OrbitsConfig cfg;
  std::vector<double> omegas;
  try {
    cfg = parse_orbits(args, omegas);
  } catch (const config::ConfigError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  }
  print_model(cfg);
  if (args.lag) return lag_report(cfg, omegas, args);
  if (!args.map_parameter.empty()) return orbits_map(cfg, omegas, args);

  const std::vector<Row> table = orbit_table(cfg, omegas, args.all);
  Branches br;
  if (!cfg.orbits.parameter.empty()) br = continue_orbits(cfg, omegas.front());
  std::optional<Predictions> pred;
  if (args.thresholds || !args.compare.empty())
    if (const int rc = predict(cfg, args, pred); rc != 0) return rc;

  try {
    write_orbit_files(args, cfg, table, br, pred);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace ajx::app
