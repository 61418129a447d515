#include "bench/stability.hpp"

#include <cmath>

namespace ajx::bench {

Scene held_at(const Scene& base, double omega) {
  Scene s = base;
  s.schedule = physics::MotorSchedule(base.model.p.drive_radius, {{omega, omega, base.horizon + 1.0}});
  // The initial state is kept; a preset state at rest does not depend on the schedule's ω.
  return s;
}

bool acceptable(const Outcome& o, const Errors& e, const StabilityCriteria& c) {
  return o.status == "ok" && e.same_mode && std::isfinite(e.position) &&
         std::abs(o.energy_residual) <= c.energy_tol;
}

double largest_stable_step(const Scene& scene, const std::string& method, const Reference& ref,
                           const StabilityCriteria& c, double h_max, double h_min, std::vector<StabilityRow>& rows) {
  int run_of_passes = 0;
  double candidate = 0.0;
  for (int k = 0;; ++k) {
    const double h = h_max * std::pow(2.0, -0.5 * k);
    if (h < h_min) break;
    StabilityRow r{scene.schedule.segments().front().omega_begin, method, h, {}, {}, false};
    r.out = run_point(scene, {method, 0.0, h}, 1, 0.0);
    r.err = compare(r.out.final, ref.run.final);
    r.pass = acceptable(r.out, r.err, c);
    rows.push_back(r);
    if (!r.pass) {
      run_of_passes = 0;
      continue;
    }
    if (run_of_passes++ == 0) candidate = h;
    if (run_of_passes == 3) return candidate;
  }
  return run_of_passes > 0 ? candidate : 0.0;
}

}  // namespace ajx::bench
