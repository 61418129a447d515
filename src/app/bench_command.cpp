// astrojax bench work-precision: each method over a range of tolerances (adaptive) or steps
// (fixed) on each scene; CPU time (median of repeats) against the achieved error at the
// horizon, with constraint drift and the energy-balance residual, as CSV.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <numbers>
#include <optional>

#include "app/commands.hpp"
#include "bench/scene_file.hpp"
#include "bench/constraint_study.hpp"
#include "bench/friction_study.hpp"
#include "bench/stability.hpp"
#include "bench/work_precision.hpp"
#include "config/config.hpp"
#include "numerics/stepper.hpp"

namespace ajx::app {

namespace {

// A benchmark's CSV: written to "<path>.part" as the rows come, renamed to <path> when complete,
// so a killed benchmark never leaves a truncated file under the final name.
class CsvOutput {
 public:
  explicit CsvOutput(const std::string& path) : path_(path) {
    const std::filesystem::path out(path);
    std::error_code ec;
    if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path(), ec);
    stream_.open(path + ".part");
  }

  std::ofstream& stream() { return stream_; }
  // Closes and renames; prints where the table went. Returns the exit code.
  int commit() {
    stream_.close();
    std::error_code ec;
    std::filesystem::rename(path_ + ".part", path_, ec);
    if (!stream_ || ec) {
      std::fprintf(stderr, "error: cannot write %s: %s\n", path_.c_str(), ec ? ec.message().c_str() : "write failed");
      return 1;
    }
    std::printf("-> %s\n", path_.c_str());
    return 0;
  }

 private:
  std::string path_;
  std::ofstream stream_;
};

void require_horizon(double horizon) {
  if (!(horizon > 0.0 && horizon <= 1e4))
    throw config::ConfigError(fmt::format("--horizon {}: allowed (0, 1e4] s", horizon));
}

// The CSV of a benchmark, or none (with the error on stderr) when it cannot be written.
std::optional<CsvOutput> open_csv(const std::string& path) {
  std::optional<CsvOutput> table(std::in_place, path);
  if (table->stream()) return table;
  std::fprintf(stderr, "error: cannot write %s.part\n", path.c_str());
  return std::nullopt;
}

}  // namespace

int bench_work_precision_command(const WorkPrecisionArgs& a) {
  std::vector<bench::Scene> scenes;
  try {
    require_horizon(a.horizon);
    if (a.repeats < 1) throw config::ConfigError(fmt::format("--repeats {}: allowed >= 1", a.repeats));
    for (const auto& m : a.methods) (void)numerics::make_stepper(bench::stepper_name(m));
    for (double r : a.rtols)
      if (!(r >= 1e-15 && r < 1.0)) throw config::ConfigError(fmt::format("--rtols {}: allowed [1e-15, 1)", r));
    for (double h : a.steps)
      if (!(h > 0.0 && h <= 0.1)) throw config::ConfigError(fmt::format("--steps {}: allowed (0, 0.1] s", h));
    for (const auto& p : a.scenes) scenes.push_back(bench::load_scene(p, a.overrides, a.horizon));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  }
  std::optional<CsvOutput> table = open_csv(a.output);
  if (!table) return kExitBadInput;
  std::ofstream& csv = table->stream();
  csv << "# astrojax bench work-precision; reference: dop853 at rtol 1e-13, floor: |reference - dopri5 at rtol 1e-12|\n";
  csv << bench::csv_header() << "\n";
  for (const bench::Scene& scene : scenes) {
    const bench::Reference ref = bench::reference(scene);
    std::printf("%s: horizon %g s, reference %s, %ld mode switches, final mode %s, floor %.1e m, "
                "amplification of a 1e-9 kick %.1e, Lyapunov exponent %.2f /s (chaos above %.2f)%s\n",
                scene.name.c_str(), scene.horizon, ref.run.status.c_str(), ref.run.mode_switches,
                std::string(physics::to_string(ref.run.final.contact.mode)).c_str(), ref.floor, ref.amplification,
                ref.sep.lyapunov, ref.sep.threshold, ref.chaotic() ? " (chaotic: compare statistics)" : "");
    // A chaotic scene is measured by statistics over the horizon, against the reference's.
    bench::Statistics ref_stats;
    if (ref.chaotic()) {
      ref_stats = bench::statistics(scene, {"dop853/lab", 1e-13, 0.0});
      std::printf("  reference statistics: class %s, mean radius %.6f m, omega_ball %.6f rad/s\n",
                  ref_stats.orbit_class.c_str(), ref_stats.mean_radius, ref_stats.omega_ball);
    }
    std::printf("  %-7s %9s %10s %10s %10s %10s %10s %6s\n", "method", "rtol|h", "cpu [s]", "err [m]",
                "drift [m]", "energy", "evals", "status");
    for (const auto& m : a.methods) {
      const bool adaptive = numerics::make_stepper(bench::stepper_name(m))->adaptive();
      for (double param : adaptive ? a.rtols : a.steps) {
        bench::Setting set{m, adaptive ? param : 0.0, adaptive ? 0.0 : param};
        bench::Row row{scene.name, m, adaptive ? "rtol" : "step", param, {}, {}, 0.0, {}, true, NAN};
        row.out = bench::run_point(scene, set, a.repeats, a.cpu_budget);
        row.err = bench::compare(row.out.final, ref.run.final);
        row.omega_ball_error = std::abs(row.out.omega_ball - ref.run.omega_ball);
        if (ref.chaotic()) {
          const bench::Statistics st = bench::statistics(scene, set);
          row.orbit_class = st.orbit_class;
          row.same_class = st.orbit_class == ref_stats.orbit_class;
          row.mean_radius_error = std::abs(st.mean_radius - ref_stats.mean_radius);
          row.omega_ball_error = std::abs(st.omega_ball - ref_stats.omega_ball);
        }
        csv << bench::csv_line(row, ref) << "\n";
        csv.flush();
        std::printf("  %-7s %9.2e %10.3e %10.2e %10.2e %10.2e %10ld %s\n", m.c_str(), param, row.out.cpu_median,
                    row.err.position, row.out.max_drift, row.out.energy_residual, row.out.rhs_evals,
                    row.out.status.c_str());
        std::fflush(stdout);
      }
    }
  }
  return table->commit();
}

int bench_stability_command(const StabilityArgs& a) {
  bench::Scene base;
  try {
    require_horizon(a.horizon);
    for (const auto& m : a.methods)
      if (numerics::make_stepper(bench::stepper_name(m))->adaptive())
        throw config::ConfigError(fmt::format("--methods {}: allowed the fixed-step methods euler, rk4, radau_iia", m));
    for (double w : a.omegas_pi)
      if (!(w >= 0.0 && w * std::numbers::pi <= 2000.0))
        throw config::ConfigError(fmt::format("--omegas-pi {}: allowed [0, 2000/π]", w));
    if (!(a.h_min > 0.0 && a.h_min < a.h_max && a.h_max <= 0.1))
      throw config::ConfigError(fmt::format("--h-min {} --h-max {}: allowed 0 < h_min < h_max <= 0.1 s", a.h_min, a.h_max));
    base = bench::load_scene(a.scene, a.overrides, a.horizon);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  }
  std::optional<CsvOutput> table = open_csv(a.output);
  if (!table) return kExitBadInput;
  std::ofstream& csv = table->stream();
  const bench::StabilityCriteria crit{a.energy_tol};
  csv << fmt::format("# astrojax bench stability {}: hold at omega from the scene's initial state for {} s; pass = "
                     "finished, final mode of the reference (dop853 rtol 1e-13), |energy residual| <= {}\n",
                     a.scene, a.horizon, crit.energy_tol);
  csv << "omega,omega_over_pi,method,step,pass,largest_stable,status,final_mode_ok,err_position_m,max_drift_m,"
         "energy_residual_rel,cpu_s\n";
  std::printf("%-10s %-9s %16s   explicit Euler at the paper's step 1/2000 s: %s\n", "ω_m/π", "method", "largest stable h",
              "energy residual, drift, error, final mode");
  for (double wpi : a.omegas_pi) {
    const double omega = wpi * std::numbers::pi;
    const bench::Scene scene = bench::held_at(base, omega);
    const bench::Reference ref = bench::reference(scene);
    for (const auto& m : a.methods) {
      std::vector<bench::StabilityRow> rows;
      const double h = bench::largest_stable_step(scene, m, ref, crit, a.h_max, a.h_min, rows);
      std::string paper;
      if (m == "euler") {
        bench::StabilityRow r{omega, m, 5e-4, bench::run_point(scene, {m, 0.0, 5e-4}, 1, 0.0), {}, false};
        r.err = bench::compare(r.out.final, ref.run.final);
        r.pass = bench::acceptable(r.out, r.err, crit);
        paper = fmt::format("{:+.2e}, {:.1e} m, {:.1e} m, {}{}", r.out.energy_residual, r.out.max_drift,
                            r.err.position, physics::to_string(r.out.final.contact.mode),
                            r.err.same_mode ? "" : " (wrong)");
        rows.push_back(r);
      }
      for (const auto& r : rows)
        csv << fmt::format("{:.17g},{:.6g},{},{:.6g},{},{:.6g},\"{}\",{},{:.6e},{:.6e},{:.6e},{:.6e}\n", omega, wpi, m,
                           r.step, r.pass ? 1 : 0, h, r.out.status, r.err.same_mode ? 1 : 0, r.err.position,
                           r.out.max_drift, r.out.energy_residual, r.out.cpu_median);
      csv.flush();
      std::printf("%-10.4g %-9s %16.3e   %s\n", wpi, m.c_str(), h, paper.c_str());
      std::fflush(stdout);
    }
  }
  return table->commit();
}

int bench_friction_command(const FrictionArgs& a) {
  bench::Scene base;
  try {
    require_horizon(a.horizon);
    for (double e : a.eps)
      if (!(e > 0.0 && e <= 1000.0)) throw config::ConfigError(fmt::format("--eps {}: allowed (0, 1000] m/s", e));
    if (!(a.rtol >= 1e-15 && a.rtol < 1.0))
      throw config::ConfigError(fmt::format("--rtol {}: allowed [1e-15, 1)", a.rtol));
    for (double h : a.rk4_steps)
      if (!(h > 0.0 && h <= 0.1)) throw config::ConfigError(fmt::format("--rk4-steps {}: allowed (0, 0.1] s", h));
    for (double h : a.radau_steps)
      if (!(h > 0.0 && h <= 0.1)) throw config::ConfigError(fmt::format("--radau-steps {}: allowed (0, 0.1] s", h));
    if (a.max_steps < 1) throw config::ConfigError(fmt::format("--max-steps {}: allowed >= 1", a.max_steps));
    for (const auto& law : a.laws)
      if (law != "regularised" && law != "stribeck")
        throw config::ConfigError(fmt::format("--laws {}: allowed regularised, stribeck", law));
    base = bench::load_scene(a.scene, a.overrides, a.horizon);
    if (base.model.layers.friction != physics::Friction::StickSlip)
      throw config::ConfigError(fmt::format("{}: key 'layers.friction': allowed \"stick_slip\" (the event-driven "
                                            "model the regularised one is compared with)", a.scene));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  }
  base.run.integ.max_steps = a.max_steps;
  std::optional<CsvOutput> table = open_csv(a.output);
  if (!table) return kExitBadInput;
  std::ofstream& csv = table->stream();
  csv << fmt::format("# astrojax bench friction {}: horizon {} s; eps = 0 is the event-driven stick-slip model; "
                     "references: dop853 at rtol 1e-13 (event-driven), 1e-11 (regularised, per law and eps); "
                     "stribeck_speed {} m/s\n",
                     a.scene, a.horizon, base.model.layers.stribeck_speed);
  csv << "eps,model,method,param_kind,param,status,cpu_s,steps,rhs_evals,err_model_m,err_stick_slip_m,err_kinetic_m,"
         "creep_stick_slip_L1_m,creep_kinetic_L1_m,energy_residual_rel\n";
  const bench::Reference exact = bench::reference(base);
  const bench::Scene kin = bench::kinetic(base);
  const bench::Reference exact_kin = bench::reference(kin);
  const double L1_exact = bench::bead_position(base, exact.run.final);
  const double L1_kin = bench::bead_position(kin, exact_kin.run.final);
  std::printf("event-driven references: stick-slip %ld mode switches, final mode %s, L1 = %.9f m; kinetic %ld, %s, "
              "L1 = %.9f m\n",
              exact.run.mode_switches, std::string(physics::to_string(exact.run.final.contact.mode)).c_str(), L1_exact,
              exact_kin.run.mode_switches, std::string(physics::to_string(exact_kin.run.final.contact.mode)).c_str(),
              L1_kin);
  std::printf("%-8s %-11s %-10s %8s %10s %9s %10s %10s %10s %10s %10s  %s\n", "ε [m/s]", "model", "method", "rtol|h",
              "cpu [s]", "evals", "err model", "err s-s", "err kin", "creep s-s", "creep kin", "status");
  const auto measure = [&](const bench::Scene& scene, const bench::Outcome& ref, double eps, const char* model,
                           double creep_ss, double creep_kin, const std::string& method, bool adaptive, double param) {
    bench::FrictionRow r{eps, method, adaptive ? "rtol" : "step", param, {}, 0.0, 0.0, 0.0, creep_ss, creep_kin};
    r.out = bench::run_point(scene, {method, adaptive ? param : 0.0, adaptive ? 0.0 : param}, a.repeats, 2.0);
    r.err_model = bench::compare(r.out.final, ref.final).position;
    r.err_stick_slip = bench::compare(r.out.final, exact.run.final).position;
    r.err_kinetic = bench::compare(r.out.final, exact_kin.run.final).position;
    csv << fmt::format("{:.6g},{},{},{},{:.6g},\"{}\",{:.6e},{},{},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e}\n", r.eps,
                       model, r.method, r.param_kind, r.param, r.out.status, r.out.cpu_median, r.out.steps,
                       r.out.rhs_evals, r.err_model, r.err_stick_slip, r.err_kinetic, r.creep_stick_slip,
                       r.creep_kinetic, r.out.energy_residual);
    csv.flush();
    std::printf("%-8.0e %-11s %-10s %8.1e %10.3e %9ld %10.2e %10.2e %10.2e %10.2e %10.2e  %s\n", r.eps, model,
                r.method.c_str(), r.param, r.out.cpu_median, r.out.rhs_evals, r.err_model, r.err_stick_slip,
                r.err_kinetic, r.creep_stick_slip, r.creep_kinetic, r.out.status.c_str());
    std::fflush(stdout);
  };
  for (const char* m : {"dopri5", "dop853"}) measure(base, exact.run, 0.0, "stick_slip", 0.0, NAN, m, true, a.rtol);
  for (const char* m : {"dopri5", "dop853"}) measure(kin, exact_kin.run, 0.0, "kinetic", NAN, 0.0, m, true, a.rtol);
  for (const auto& law_name : a.laws) {
    const bool stribeck = law_name == "stribeck";
    const physics::Friction law = stribeck ? physics::Friction::Stribeck : physics::Friction::Regularised;
    const char* model = law_name.c_str();
    for (double eps : a.eps) {
      if (stribeck && eps >= base.model.layers.stribeck_speed) {  // no peak near μ_s (the config refuses it)
        std::printf("%-8.0e %-11s skipped: ε >= layers.stribeck_speed = %g m/s\n", eps, model,
                    base.model.layers.stribeck_speed);
        continue;
      }
      const bench::Scene scene = bench::regularised(base, eps, law);
      const bench::Outcome ref = bench::run_point(scene, {"dop853", 1e-11, 0.0}, 1, 0.0);
      const double L1 = ref.status == "ok" ? bench::bead_position(scene, ref.final) : NAN;
      const double c_ss = std::abs(L1 - L1_exact), c_kin = std::abs(L1 - L1_kin);
      for (const char* m : {"dopri5", "dop853"}) measure(scene, ref, eps, model, c_ss, c_kin, m, true, a.rtol);
      for (double h : a.rk4_steps) measure(scene, ref, eps, model, c_ss, c_kin, "rk4", false, h);
      for (double h : a.radau_steps) measure(scene, ref, eps, model, c_ss, c_kin, "radau_iia", false, h);
    }
  }
  return table->commit();
}

int bench_constraints_command(const ConstraintsArgs& a) {
  bench::Scene scene;
  std::vector<bench::Setting> settings;
  try {
    require_horizon(a.horizon);
    for (double al : a.alphas)
      if (!(al > 0.0 && al <= 1e6)) throw config::ConfigError(fmt::format("--alphas {}: allowed (0, 1e6] 1/s", al));
    for (const auto& s : a.settings) {  // method@rtol or method@step
      const auto at = s.find('@');
      if (at == std::string::npos) throw config::ConfigError(fmt::format("--runs {}: allowed method@value", s));
      const std::string m = s.substr(0, at);
      const double x = std::stod(s.substr(at + 1));
      const bool adaptive = numerics::make_stepper(m)->adaptive();
      if (adaptive ? !(x >= 1e-15 && x < 1.0) : !(x > 0.0 && x <= 0.1))
        throw config::ConfigError(fmt::format("--runs {}: allowed rtol in [1e-15, 1) or step in (0, 0.1] s", s));
      settings.push_back({m, adaptive ? x : 0.0, adaptive ? 0.0 : x});
    }
    scene = bench::load_scene(a.scene, a.overrides, a.horizon);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  }
  const bench::Reference ref = bench::reference(scene);
  if (ref.run.mode_switches != 0) {
    std::fprintf(stderr, "error: %s: the reference switches modes %ld times; allowed: a scene in one contact mode\n",
                 a.scene.c_str(), ref.run.mode_switches);
    return kExitBadInput;
  }
  std::optional<CsvOutput> table = open_csv(a.output);
  if (!table) return kExitBadInput;
  std::ofstream& csv = table->stream();
  csv << fmt::format("# astrojax bench constraints {}: horizon {} s, mode {}; reference dop853 at rtol 1e-13\n", a.scene,
                     a.horizon, physics::to_string(scene.initial.contact.mode));
  csv << "variant,alpha,method,param,status,cpu_s,steps,rhs_evals,max_drift_m,end_drift_m,err_position_m,"
         "energy_residual_rel\n";
  std::vector<bench::ConstraintVariant> variants{{"none", 0.0, false}};
  for (double al : a.alphas) variants.push_back({"baumgarte", al, false});
  variants.push_back({"projection", 0.0, true});
  std::printf("%-11s %8s %-8s %8s %10s %11s %11s %11s %11s  %s\n", "variant", "α [1/s]", "method", "rtol|h", "cpu [s]",
              "max drift", "end drift", "error [m]", "energy", "status");
  for (const auto& s : settings)
    for (const auto& v : variants) {
      const bench::ConstraintRun r = bench::run_constraint_variant(scene, v, s, a.repeats);
      const double err = bench::compare(r.final, ref.run.final).position;
      const double param = s.rtol > 0.0 ? s.rtol : s.step;
      csv << fmt::format("{},{:.6g},{},{:.6g},\"{}\",{:.6e},{},{},{:.6e},{:.6e},{:.6e},{:.6e}\n", v.name, v.alpha,
                         s.method, param, r.status, r.cpu, r.steps, r.rhs_evals, r.max_drift, r.end_drift, err,
                         r.energy_residual);
      csv.flush();
      std::printf("%-11s %8.3g %-8s %8.1e %10.3e %11.2e %11.2e %11.2e %11.2e  %s\n", v.name.c_str(), v.alpha,
                  s.method.c_str(), param, r.cpu, r.max_drift, r.end_drift, err, r.energy_residual, r.status.c_str());
      std::fflush(stdout);
    }
  return table->commit();
}

int bench_threshold_command(const WorkPrecisionArgs& a, double sample_dt) {
  std::vector<bench::Scene> scenes;
  try {
    require_horizon(a.horizon);
    if (!(sample_dt > 0.0 && sample_dt <= 0.1))
      throw config::ConfigError(fmt::format("--sample {}: allowed (0, 0.1] s", sample_dt));
    for (const auto& m : a.methods) (void)numerics::make_stepper(bench::stepper_name(m));
    for (const auto& p : a.scenes) scenes.push_back(bench::load_scene(p, a.overrides, a.horizon));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  }
  // The threshold a scene measures follows its ramp: down, ω_fall (the first landing on the
  // bottom ball); up, ω1 (the loss of the lock). All scenes of one table measure the same one.
  const auto ramps_up = [](const bench::Scene& scene) {
    double phi, w0, w1, wd;
    scene.schedule.phase(scene.initial.t, phi, w0, wd);
    scene.schedule.phase(scene.initial.t + scene.horizon, phi, w1, wd);
    return w1 > w0;
  };
  const bool up = !scenes.empty() && ramps_up(scenes.front());
  for (const bench::Scene& scene : scenes)
    if (ramps_up(scene) != up) {
      std::fprintf(stderr, "error: %s: ramps %s while %s ramps %s; allowed: scenes that all ramp the same way\n",
                   scene.name.c_str(), up ? "down" : "up", scenes.front().name.c_str(), up ? "up" : "down");
      return kExitBadInput;
    }
  const auto measure = [&](const bench::Scene& scene, const bench::Setting& set) {
    return up ? bench::lock_loss(scene, set, sample_dt) : bench::first_fall(scene, set, sample_dt);
  };
  const char* name = up ? "omega_1" : "omega_fall";
  const char* symbol = up ? "ω1" : "ω_fall";
  // The references first: a scene where the event never comes is bad input, found before any file.
  std::vector<std::pair<bench::Fall, bench::Fall>> refs;
  for (const bench::Scene& scene : scenes) {
    refs.emplace_back(measure(scene, {"dop853/lab", 1e-13, 0.0}), measure(scene, {"dopri5", 1e-12, 0.0}));
    if (!refs.back().first.found) {
      std::fprintf(stderr, "error: %s: %s within %g s\n", scene.name.c_str(),
                   up ? "the balls never fall half a turn behind the motor" : "the bead never lands on the bottom ball",
                   scene.horizon);
      return kExitBadInput;
    }
  }
  std::optional<CsvOutput> table = open_csv(a.output);
  if (!table) return kExitBadInput;
  std::ofstream& csv = table->stream();
  csv << fmt::format("# astrojax bench threshold: omega_m at {}; reference dop853 at rtol 1e-13, floor |reference - "
                     "dopri5 at rtol 1e-12|\n",
                     up ? "the loss of the lock (the balls half a turn behind the motor)"
                        : "the bead's first landing on the bottom ball");
  const std::string tcol = up ? "t_1_s" : "t_fall_s", terr = up ? "t_1_error_s" : "t_fall_error_s";
  csv << fmt::format("scene,method,param_kind,param,status,repeats,cpu_median_s,rhs_evals,found,{},{},{}_error,{},"
                     "omega_floor\n",
                     tcol, name, name, terr);
  for (std::size_t k = 0; k < scenes.size(); ++k) {
    const bench::Scene& scene = scenes[k];
    const auto& [ref, chk] = refs[k];
    const double floor = chk.found ? std::abs(chk.omega - ref.omega) : NAN;
    std::printf("%s: reference %s = %.9f rad/s (%.6fπ) at t = %.6f s, floor %.1e rad/s\n", scene.name.c_str(),
                symbol, ref.omega, ref.omega / std::numbers::pi, ref.t, floor);
    for (const auto& m : a.methods) {
      const bool adaptive = numerics::make_stepper(bench::stepper_name(m))->adaptive();
      for (double param : adaptive ? a.rtols : a.steps) {
        const bench::Setting set{m, adaptive ? param : 0.0, adaptive ? 0.0 : param};
        const bench::Outcome o = bench::run_point(scene, set, a.repeats, a.cpu_budget);
        const bench::Fall f = measure(scene, set);
        const double ew = f.found ? std::abs(f.omega - ref.omega) : INFINITY;
        const double et = f.found ? std::abs(f.t - ref.t) : INFINITY;
        csv << fmt::format("{},{},{},{:.6g},\"{}\",{},{:.6e},{},{},{:.9f},{:.12g},{:.6e},{:.6e},{:.6e}\n", scene.name, m,
                           adaptive ? "rtol" : "step", param, o.status, o.repeats, o.cpu_median, o.rhs_evals,
                           f.found ? 1 : 0, f.t, f.omega, ew, et, floor);
        csv.flush();
        std::printf("  %-7s %9.2e  cpu %.3e s  %s %.6fπ  |Δ%s| %.2e rad/s  |Δt| %.2e s  %s\n", m.c_str(), param,
                    o.cpu_median, symbol, f.omega / std::numbers::pi, symbol, ew, et, o.status.c_str());
        std::fflush(stdout);
      }
    }
  }
  return table->commit();
}

}  // namespace ajx::app
