#include "bench/constraint_study.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <ctime>

#include "numerics/integrate.hpp"
#include "physics/contact_modes.hpp"
#include "physics/energy.hpp"

namespace ajx::bench {

ConstraintRun run_constraint_variant(const Scene& scene, const ConstraintVariant& v, const Setting& s, int repeats) {
  using numerics::Vec;
  const physics::Model& m = scene.model;
  const physics::Contact c = scene.initial.contact;
  const Eigen::Matrix<double, 6, 1> inv_mass =
      (Eigen::Matrix<double, 6, 1>() << Eigen::Vector3d::Constant(1.0 / m.p.bead_mass),
       Eigen::Vector3d::Constant(1.0 / m.p.ball_mass))
          .finished();
  const numerics::System f = [&](double t, const Vec& y, Vec& dydt) {
    physics::rhs(m, scene.schedule, c, t, y, dydt);
    if (v.alpha <= 0.0) return;
    const physics::Constraints k = physics::constraints(m, c, scene.schedule.top(t), y);
    if (k.n == 0) return;
    // Fixed-capacity types (n <= 2): no heap allocation inside the RHS.
    using MatJ = Eigen::Matrix<double, Eigen::Dynamic, 6, 0, 2, 6>;
    using VecN = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 2, 1>;
    using MatA = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 2, 2>;
    const MatJ J = k.J.topRows(k.n);
    Eigen::Matrix<double, 6, 1> vel;
    vel << y.segment<3>(physics::idx::v1), y.segment<3>(physics::idx::v2);
    const VecN Cdot = J * vel - k.b.head(k.n);
    const MatA A = J * inv_mass.asDiagonal() * J.transpose();
    const VecN mu = A.ldlt().solve(VecN(-(2.0 * v.alpha * Cdot + v.alpha * v.alpha * k.C.head(k.n))));
    const Eigen::Matrix<double, 6, 1> da = inv_mass.asDiagonal() * (J.transpose() * mu);
    dydt.segment<3>(physics::idx::v1) += da.head<3>();
    dydt.segment<3>(physics::idx::v2) += da.tail<3>();
  };
  numerics::IntegrateOptions opt = scene.run.integ;
  if (s.rtol > 0.0) opt.tol = {s.rtol, 1e-3 * s.rtol};
  if (s.step > 0.0) opt.h_fixed = s.step;
  const double t0 = scene.initial.t, t1 = t0 + scene.horizon;
  ConstraintRun out;
  double max_drift = 0.0;
  const auto drift = [&](double t, const Vec& y) {
    return physics::constraint_drift(m, c, scene.schedule.top(t), y).position;
  };
  const numerics::PostStep project = [&](double t, Vec& y) {
    if (!v.project) return false;
    const physics::TopKinematics top = scene.schedule.top(t);
    const physics::Drift d = physics::constraint_drift(m, c, top, y);
    if (d.position <= scene.run.projection_tol && d.velocity <= scene.run.projection_tol) return false;
    physics::project_positions(m, c, top, y);
    physics::project_velocities(m, c, top, y);
    return true;
  };
  // One run with the drift observer (not timed), then the timed runs without it.
  const numerics::StepObserver observe = [&](const numerics::StepView& step) {
    Vec y;
    step.at(step.t1(), y);
    max_drift = std::max(max_drift, drift(step.t1(), y));
    return true;
  };
  {
    auto stepper = numerics::make_stepper(s.method);
    Vec y = scene.initial.y;
    const auto r = numerics::integrate(f, *stepper, t0, y, t1, {}, observe, project, opt);
    if (r.status != numerics::IntegrateStatus::Reached) out.status = numerics::to_string(r.status);
    out.steps = r.steps;
    out.rhs_evals = stepper->rhs_evals();
    out.final = scene.initial;
    out.final.t = t1;
    out.final.y = y;
  }
  std::vector<double> times;
  for (int k = 0; k < std::max(1, repeats); ++k) {
    auto stepper = numerics::make_stepper(s.method);
    Vec y = scene.initial.y;
    const double c0 = cpu_seconds();
    numerics::integrate(f, *stepper, t0, y, t1, {}, {}, project, opt);
    times.push_back(cpu_seconds() - c0);
  }
  std::sort(times.begin(), times.end());
  out.cpu = times[times.size() / 2];
  out.max_drift = max_drift;
  out.end_drift = drift(t1, out.final.y);
  out.energy_residual = physics::energy_balance(m.p, scene.initial, out.final).relative();
  return out;
}

}  // namespace ajx::bench
