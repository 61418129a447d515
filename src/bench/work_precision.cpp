#include "bench/work_precision.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <fmt/format.h>
#include <numbers>

#include "physics/contact_modes.hpp"
#include "physics/energy.hpp"
#include "sweep/orbit_classifier.hpp"

namespace ajx::bench {

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

namespace {
constexpr std::string_view kLabSuffix = "/lab";
constexpr std::string_view kAutoSuffix = "/auto";
}  // namespace

std::string_view stepper_name(std::string_view method) {
  for (std::string_view suffix : {kLabSuffix, kAutoSuffix})
    if (method.ends_with(suffix)) return method.substr(0, method.size() - suffix.size());
  return method;
}

sim::Axes axes_of(std::string_view method) {
  return method.ends_with(kLabSuffix)    ? sim::Axes::Lab
         : method.ends_with(kAutoSuffix) ? sim::Axes::Auto
                                         : sim::Axes::Rotating;
}

namespace {

sim::RunOptions options_for(const Scene& scene, const Setting& setting) {
  sim::RunOptions o = scene.run;
  o.method = std::string(stepper_name(setting.method));
  o.axes = axes_of(setting.method);
  if (setting.rtol > 0.0) o.integ.tol = {setting.rtol, 1e-3 * setting.rtol};
  if (setting.step > 0.0) o.integ.h_fixed = setting.step;
  return o;
}

}  // namespace

Outcome run_point(const Scene& scene, const Setting& setting, int repeats, double cpu_budget) {
  sim::Simulation simulation(scene.model, scene.schedule, options_for(scene, setting));
  const double t_end = scene.initial.t + scene.horizon;
  Outcome out;
  std::vector<double> times;
  double spent = 0.0;
  for (int k = 0; k < std::max(1, repeats); ++k) {
    physics::State s = scene.initial;
    const double c0 = cpu_seconds();
    const sim::RunSummary sum = simulation.run(s, t_end, 0.0);
    const double c = cpu_seconds() - c0;
    times.push_back(c);
    spent += c;
    if (k == 0) {
      out.status = sum.ok() ? "ok" : sum.failure;
      out.steps = sum.steps;
      out.rejected = sum.rejected;
      out.rhs_evals = sum.rhs_evals;
      out.mode_switches = sum.mode_switches;
      out.max_drift = sum.max_drift;
      out.energy_residual = sum.energy.relative();
      out.omega_ball = sum.omega_ball;
      out.final = s;
    }
    if (spent > cpu_budget) break;
  }
  std::sort(times.begin(), times.end());
  out.repeats = int(times.size());
  const std::size_t n = times.size();
  out.cpu_median = n % 2 ? times[n / 2] : 0.5 * (times[n / 2 - 1] + times[n / 2]);
  out.cpu_min = times.front();
  return out;
}

Errors compare(const physics::State& s, const physics::State& ref) {
  using namespace physics::idx;
  Errors e;
  e.position = std::max((s.y.segment<3>(r1) - ref.y.segment<3>(r1)).norm(),
                        (s.y.segment<3>(r2) - ref.y.segment<3>(r2)).norm());
  e.velocity = std::max((s.y.segment<3>(v1) - ref.y.segment<3>(v1)).norm(),
                        (s.y.segment<3>(v2) - ref.y.segment<3>(v2)).norm());
  e.same_mode = s.contact.mode == ref.contact.mode;
  if (!std::isfinite(e.position)) e.position = e.velocity = INFINITY;
  return e;
}

Reference reference(const Scene& scene) {
  Reference ref;
  // The reference in the lab axes, the check in the rotating ones: the floor also bounds the
  // difference of the two formulations.
  ref.run = run_point(scene, {"dop853/lab", 1e-13, 0.0}, 1, 0.0);
  const Outcome check = run_point(scene, {"dopri5", 1e-12, 0.0}, 1, 0.0);
  ref.floor = compare(check.final, ref.run.final).position;
  ref.sep = separation(scene);
  ref.amplification = ref.sep.amplification;
  return ref;
}

Separation separation(const Scene& scene, int samples) {
  // The kicked copy: δv = 1e-9 m/s on the bead, made consistent with the constraints; the
  // first of x, y, z whose kick survives the projection.
  constexpr double kick = 1e-9, saturation = 0.1;
  Scene kicked = scene;
  double d0 = 0.0;
  const physics::TopKinematics top = scene.schedule.top(scene.initial.t);
  for (int axis = 0; axis < 3 && !(d0 > 0.1 * kick); ++axis) {
    kicked.initial = scene.initial;
    kicked.initial.y(physics::idx::v1 + axis) += kick;
    physics::project_velocities(scene.model, kicked.initial.contact, top, kicked.initial.y);
    d0 = compare(kicked.initial, scene.initial).velocity;
  }
  const double dt = scene.horizon / samples;
  std::vector<double> v[2];
  for (int k = 0; k < 2; ++k) {
    sim::RunOptions o = options_for(k == 0 ? scene : kicked, {"dop853/lab", 1e-13, 0.0});
    sim::Simulation sim((k == 0 ? scene : kicked).model, scene.schedule, o);
    physics::State st = k == 0 ? scene.initial : kicked.initial;
    sim.run(st, scene.initial.t + scene.horizon, dt, [&](const sim::Sample& x) {
      for (int i = 0; i < 6; ++i) v[k].push_back(x.y(physics::idx::v1 + i));
    });
  }
  Separation sep;
  const double T = scene.horizon;
  sep.threshold = 3.0 * std::log(4.0) / (0.75 * T);
  const std::size_t n = std::min(v[0].size(), v[1].size()) / 6;
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = double(i) * dt;
    Eigen::Vector3d a1, a2;
    for (int c = 0; c < 3; ++c) {
      a1[c] = v[0][6 * i + c] - v[1][6 * i + c];
      a2[c] = v[0][6 * i + 3 + c] - v[1][6 * i + 3 + c];
    }
    const double d = std::max(a1.norm(), a2.norm());
    if (i + 1 == n) sep.amplification = d0 > 0.0 ? d / d0 : 0.0;
    if (t < 0.25 * T - 1e-12 || !(d > 0.0) || d >= saturation) continue;
    sx += t;
    sy += std::log(d);
    sxx += t * t;
    sxy += t * std::log(d);
    ++sep.fitted;
  }
  const double den = sep.fitted * sxx - sx * sx;
  sep.lyapunov = sep.fitted >= 2 && den > 0.0 ? (sep.fitted * sxy - sx * sy) / den : 0.0;
  return sep;
}

Statistics statistics(const Scene& scene, const Setting& setting) {
  sim::Simulation simulation(scene.model, scene.schedule, options_for(scene, setting));
  physics::State s = scene.initial;
  std::vector<double> t, w, r1, r2, L1, T1, T2;
  std::vector<int> mode;
  const sim::RunSummary sum = simulation.run(s, scene.initial.t + scene.horizon, 1.0 / 200.0, [&](const sim::Sample& x) {
    t.push_back(x.t);
    w.push_back(x.top.omega);
    for (int c = 0; c < 3; ++c) {
      r1.push_back(x.y(physics::idx::r1 + c));
      r2.push_back(x.y(physics::idx::r2 + c));
    }
    L1.push_back(x.dyn.g.L1);
    T1.push_back(x.dyn.T1);
    T2.push_back(x.dyn.T2);
    mode.push_back(int(x.contact.mode));
  });
  sweep::OrbitWindow win{t, w, r1, r2, L1, T1, T2, mode, !sum.ok(), sum.failure};
  const sweep::OrbitClassification c = sweep::classify_orbit(win, sweep::orbit_scales(scene.model.p));
  Statistics st;
  st.orbit_class = std::string(sweep::to_string(c.cls));
  double rho = 0.0;
  for (std::size_t i = 0; i < t.size(); ++i)
    rho += std::hypot(r1[3 * i], r1[3 * i + 1]) + std::hypot(r2[3 * i], r2[3 * i + 1]);
  st.mean_radius = t.empty() ? 0.0 : rho / (2.0 * double(t.size()));
  st.omega_ball = sum.omega_ball;
  return st;
}

std::string csv_header() {
  return "scene,method,param_kind,param,status,repeats,cpu_median_s,cpu_min_s,steps,rejected,rhs_evals,"
         "mode_switches,err_position_m,err_velocity_mps,same_final_mode,omega_ball_error,max_drift_m,"
         "energy_residual_rel,reference_floor_m,amplification,chaotic,lyapunov_per_s,orbit_class,same_class,"
         "mean_radius_error_m";
}

std::string csv_line(const Row& r, const Reference& ref) {
  const Outcome& o = r.out;
  return fmt::format("{},{},{},{:.6g},\"{}\",{},{:.6e},{:.6e},{},{},{},{},{:.6e},{:.6e},{},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{}",
                     r.scene, r.method, r.param_kind, r.param, o.status, o.repeats, o.cpu_median, o.cpu_min,
                     o.steps, o.rejected, o.rhs_evals, o.mode_switches, r.err.position, r.err.velocity,
                     r.err.same_mode ? 1 : 0, r.omega_ball_error, o.max_drift, o.energy_residual, ref.floor,
                     ref.amplification, ref.chaotic() ? 1 : 0) +
         fmt::format(",{:.6e},{},{},{:.6e}", ref.sep.lyapunov, r.orbit_class, r.same_class ? 1 : 0,
                     r.mean_radius_error);
}

}  // namespace ajx::bench

namespace ajx::bench {

Fall first_fall(const Scene& scene, const Setting& setting, double sample_dt) {
  sim::Simulation simulation(scene.model, scene.schedule, options_for(scene, setting));
  physics::State s = scene.initial;
  Fall fall;
  bool have_prev = false;
  double t_prev = 0.0, L2_prev = 0.0, L2dot_prev = 0.0;
  const double d = scene.model.p.contact_distance;
  simulation.run(s, scene.initial.t + scene.horizon, sample_dt, [&](const sim::Sample& x) {
    if (fall.found) return;
    if (x.contact.mode == physics::Mode::BottomStop) {
      if (!have_prev) return;  // resting from the start: not a fall
      fall.found = true;
      fall.t = L2dot_prev < 0.0 ? std::min(x.t, t_prev + (L2_prev - d) / (-L2dot_prev)) : x.t;
      double phi, w, wd;
      scene.schedule.phase(fall.t, phi, w, wd);
      fall.omega = w;
      return;
    }
    have_prev = true;
    t_prev = x.t;
    L2_prev = x.dyn.g.L2;
    L2dot_prev = x.dyn.g.L2_dot;
  });
  return fall;
}

Fall lock_loss(const Scene& scene, const Setting& setting, double sample_dt) {
  sim::Simulation simulation(scene.model, scene.schedule, options_for(scene, setting));
  physics::State s = scene.initial;
  Fall loss;
  bool have_prev = false;
  double t_prev = 0.0, lag_prev = 0.0, lag0 = 0.0, theta[2] = {0.0, 0.0};
  Eigen::Vector2d last[2];
  simulation.run(s, scene.initial.t + scene.horizon, sample_dt, [&](const sim::Sample& x) {
    if (loss.found) return;
    for (int b = 0; b < 2; ++b) {
      const Eigen::Vector2d now = x.y.segment<2>(b == 0 ? physics::idx::r1 : physics::idx::r2);
      if (have_prev) theta[b] += std::atan2(last[b].x() * now.y() - last[b].y() * now.x(), last[b].dot(now));
      last[b] = now;
    }
    const double lag = x.top.phi - 0.5 * (theta[0] + theta[1]);
    if (!have_prev) {
      lag0 = lag;
    } else if (lag - lag0 >= std::numbers::pi) {
      loss.found = true;
      const double f = (lag0 + std::numbers::pi - lag_prev) / (lag - lag_prev);
      loss.t = t_prev + f * (x.t - t_prev);
      double phi, w, wd;
      scene.schedule.phase(loss.t, phi, w, wd);
      loss.omega = w;
    }
    have_prev = true;
    t_prev = x.t;
    lag_prev = lag;
  });
  return loss;
}

}  // namespace ajx::bench
