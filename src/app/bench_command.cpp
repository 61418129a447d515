// astrojax bench work-precision: each method over a range of tolerances (adaptive) or steps
// (fixed) on each scene; CPU time (median of repeats) against the achieved error at the
// horizon, with constraint drift and the energy-balance residual, as CSV.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>

#include "app/commands.hpp"
#include "bench/scene_file.hpp"
#include "bench/work_precision.hpp"
#include "config/config.hpp"
#include "numerics/stepper.hpp"

namespace ajx::app {

int bench_work_precision_command(const WorkPrecisionArgs& a) {
  std::vector<bench::Scene> scenes;
  try {
    if (!(a.horizon > 0.0 && a.horizon <= 1e4))
      throw config::ConfigError(fmt::format("--horizon {}: allowed (0, 1e4] s", a.horizon));
    if (a.repeats < 1) throw config::ConfigError(fmt::format("--repeats {}: allowed >= 1", a.repeats));
    for (const auto& m : a.methods) (void)numerics::make_stepper(m);
    for (double r : a.rtols)
      if (!(r >= 1e-15 && r < 1.0)) throw config::ConfigError(fmt::format("--rtols {}: allowed [1e-15, 1)", r));
    for (double h : a.steps)
      if (!(h > 0.0 && h <= 0.1)) throw config::ConfigError(fmt::format("--steps {}: allowed (0, 0.1] s", h));
    for (const auto& p : a.scenes) scenes.push_back(bench::load_scene(p, a.overrides, a.horizon));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  }
  const std::filesystem::path out(a.output);
  std::error_code ec;
  if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path(), ec);
  std::ofstream csv(a.output + ".part");
  if (!csv) {
    std::fprintf(stderr, "error: cannot write %s.part\n", a.output.c_str());
    return kExitBadInput;
  }
  csv << "# astrojax bench work-precision; reference: dop853 at rtol 1e-13, floor: |reference - dopri5 at rtol 1e-12|\n";
  csv << bench::csv_header() << "\n";
  for (const bench::Scene& scene : scenes) {
    const bench::Reference ref = bench::reference(scene);
    std::printf("%s: horizon %g s, reference %s, %ld mode switches, final mode %s, floor %.1e m, "
                "amplification of a 1e-9 kick %.1e%s\n",
                scene.name.c_str(), scene.horizon, ref.run.status.c_str(), ref.run.mode_switches,
                std::string(physics::to_string(ref.run.final.contact.mode)).c_str(), ref.floor, ref.amplification,
                ref.chaotic() ? " (chaotic: compare statistics)" : "");
    std::printf("  %-7s %9s %10s %10s %10s %10s %10s %6s\n", "method", "rtol|h", "cpu [s]", "err [m]",
                "drift [m]", "energy", "evals", "status");
    for (const auto& m : a.methods) {
      const bool adaptive = numerics::make_stepper(m)->adaptive();
      for (double param : adaptive ? a.rtols : a.steps) {
        bench::Setting set{m, adaptive ? param : 0.0, adaptive ? 0.0 : param};
        bench::Row row{scene.name, m, adaptive ? "rtol" : "step", param, {}, {}, 0.0};
        row.out = bench::run_point(scene, set, a.repeats, a.cpu_budget);
        row.err = bench::compare(row.out.final, ref.run.final);
        row.omega_ball_error = std::abs(row.out.omega_ball - ref.run.omega_ball);
        csv << bench::csv_line(row, ref) << "\n";
        csv.flush();
        std::printf("  %-7s %9.2e %10.3e %10.2e %10.2e %10.2e %10ld %s\n", m.c_str(), param, row.out.cpu_median,
                    row.err.position, row.out.max_drift, row.out.energy_residual, row.out.rhs_evals,
                    row.out.status.c_str());
        std::fflush(stdout);
      }
    }
  }
  csv.close();
  std::filesystem::rename(a.output + ".part", a.output, ec);
  if (ec) {
    std::fprintf(stderr, "error: cannot rename %s.part: %s\n", a.output.c_str(), ec.message().c_str());
    return 1;
  }
  std::printf("-> %s\n", a.output.c_str());
  return 0;
}

}  // namespace ajx::app
