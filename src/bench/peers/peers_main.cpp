// astrojax_peers: the peer solvers a user would pick instead of the project's integrators,
// driven through the same right-hand side (physics::rhs) on smooth scenes, i.e. scenes whose
// reference run stays in one contact mode. Built only with -DASTROJAX_PEERS=ON; the product
// never depends on it. Writes the CSV columns of `astrojax bench work-precision`, so that
// analysis/plot_work_precision.py draws both together.
//   Boost.Odeint: runge_kutta_dopri5, runge_kutta_fehlberg78, bulirsch_stoer (controlled);
//   SUNDIALS CVODE: Adams (fixed-point iteration) and BDF (Newton, dense LU, difference-
//     quotient Jacobian); ARKODE ERKStep with the Dormand-Prince 5(4) and Fehlberg 7(8) tables;
//   and, for a like-for-like comparison, the project's steppers through numerics::integrate
//   without events or projection ("ajx-*-plain").
// Every solver gets rtol and atol = 1e-3 rtol (each applies them in its own error norm); the
// achieved error is what the diagram shows. The drift and energy columns are measured at the
// horizon only (no solver here projects), not the maximum over steps.
// Usage: astrojax_peers sweeps/scenes/locked_circular.toml ... -o out/peers.csv
#include <CLI/CLI.hpp>
#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fmt/format.h>
#include <fstream>
#include <functional>
#include <vector>

#include <arkode/arkode_erkstep.h>
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include "bench/scene_file.hpp"
#include "bench/work_precision.hpp"
#include "numerics/integrate.hpp"
#include "physics/contact_modes.hpp"
#include "physics/energy.hpp"
#include "physics/rotating_axes.hpp"

namespace {

using namespace ajx;
using numerics::Vec;
using State = std::vector<double>;
namespace odeint = boost::numeric::odeint;

// The scene's RHS in its initial contact mode, counting evaluations; in the lab axes or (with
// --axes rotating) in the axes turning with the motor, the product's formulation.
struct Rhs {
  const bench::Scene& scene;
  bool rotating = false;
  long evals = 0;
  Vec y{physics::idx::dim}, dydt{physics::idx::dim};
  void operator()(double t, const double* in, double* out) {
    ++evals;
    y = Eigen::Map<const Eigen::VectorXd>(in, physics::idx::dim);
    if (rotating)
      physics::rhs_in_rotating_axes(scene.model, scene.schedule, scene.initial.contact, t, y, dydt);
    else
      physics::rhs(scene.model, scene.schedule, scene.initial.contact, t, y, dydt);
    Eigen::Map<Eigen::VectorXd>(out, physics::idx::dim) = dydt;
  }
};

// One solver: integrates y from t0 to t1 in place; returns "ok" or why it failed.
using Solver = std::function<std::string(Rhs& f, double t0, double t1, State& y, double rtol)>;

std::string odeint_run(Rhs& f, double t0, double t1, State& y, double rtol, int which) {
  const auto sys = [&f](const State& x, State& dxdt, double t) { f(t, x.data(), dxdt.data()); };
  const double atol = 1e-3 * rtol, dt = 1e-4;
  try {
    if (which == 0)
      odeint::integrate_adaptive(odeint::make_controlled<odeint::runge_kutta_dopri5<State>>(atol, rtol), sys, y,
                                 t0, t1, dt);
    else if (which == 1)
      odeint::integrate_adaptive(odeint::make_controlled<odeint::runge_kutta_fehlberg78<State>>(atol, rtol), sys,
                                 y, t0, t1, dt);
    else
      odeint::integrate_adaptive(odeint::bulirsch_stoer<State>(atol, rtol), sys, y, t0, t1, dt);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "ok";
}

int sundials_rhs(double t, N_Vector y, N_Vector ydot, void* user) {
  (*static_cast<Rhs*>(user))(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
  return 0;
}

// SUNDIALS objects owned for one run.
struct Sundials {
  SUNContext ctx = nullptr;
  N_Vector y = nullptr;
  SUNMatrix A = nullptr;
  SUNLinearSolver LS = nullptr;
  SUNNonlinearSolver NLS = nullptr;
  void* mem = nullptr;
  bool arkode = false;
  explicit Sundials(const State& y0) {
    SUNContext_Create(nullptr, &ctx);
    y = N_VNew_Serial(sunindextype(y0.size()), ctx);
    std::copy(y0.begin(), y0.end(), N_VGetArrayPointer(y));
  }
  ~Sundials() {
    if (mem) arkode ? ERKStepFree(&mem) : CVodeFree(&mem);
    if (NLS) SUNNonlinSolFree(NLS);
    if (LS) SUNLinSolFree(LS);
    if (A) SUNMatDestroy(A);
    if (y) N_VDestroy(y);
    if (ctx) SUNContext_Free(&ctx);
  }
  void copy_out(State& out) const {
    const double* p = N_VGetArrayPointer(y);
    std::copy(p, p + out.size(), out.begin());
  }
};

std::string cvode_run(Rhs& f, double t0, double t1, State& y, double rtol, bool bdf) {
  Sundials s(y);
  s.mem = CVodeCreate(bdf ? CV_BDF : CV_ADAMS, s.ctx);
  CVodeInit(s.mem, sundials_rhs, t0, s.y);
  CVodeSStolerances(s.mem, rtol, 1e-3 * rtol);
  CVodeSetUserData(s.mem, &f);
  CVodeSetMaxNumSteps(s.mem, 100'000'000);
  CVodeSetStopTime(s.mem, t1);
  if (bdf) {
    s.A = SUNDenseMatrix(sunindextype(y.size()), sunindextype(y.size()), s.ctx);
    s.LS = SUNLinSol_Dense(s.y, s.A, s.ctx);
    CVodeSetLinearSolver(s.mem, s.LS, s.A);
  } else {
    s.NLS = SUNNonlinSol_FixedPoint(s.y, 0, s.ctx);
    CVodeSetNonlinearSolver(s.mem, s.NLS);
  }
  double t = t0;
  const int flag = CVode(s.mem, t1, s.y, &t, CV_NORMAL);
  s.copy_out(y);
  return flag < 0 ? fmt::format("CVode flag {}", flag) : "ok";
}

std::string arkode_run(Rhs& f, double t0, double t1, State& y, double rtol, ARKODE_ERKTableID table) {
  Sundials s(y);
  s.arkode = true;
  s.mem = ERKStepCreate(sundials_rhs, t0, s.y, s.ctx);
  ERKStepSetTableNum(s.mem, table);
  ERKStepSStolerances(s.mem, rtol, 1e-3 * rtol);
  ERKStepSetUserData(s.mem, &f);
  ERKStepSetMaxNumSteps(s.mem, 100'000'000);
  ERKStepSetStopTime(s.mem, t1);
  double t = t0;
  const int flag = ERKStepEvolve(s.mem, t1, s.y, &t, ARK_NORMAL);
  s.copy_out(y);
  return flag < 0 ? fmt::format("ERKStepEvolve flag {}", flag) : "ok";
}

// The project's stepper with the project's driver, no events, no projection.
std::string plain_run(Rhs& f, double t0, double t1, State& y, double rtol, const char* method) {
  const numerics::System sys = [&f](double t, const Vec& x, Vec& dxdt) {
    dxdt.resize(x.size());
    f(t, x.data(), dxdt.data());
  };
  auto stepper = numerics::make_stepper(method);
  numerics::IntegrateOptions opt;
  opt.tol = {rtol, 1e-3 * rtol};
  Vec x = Eigen::Map<const Eigen::VectorXd>(y.data(), Eigen::Index(y.size()));
  const auto r = numerics::integrate(sys, *stepper, t0, x, t1, {}, {}, {}, opt);
  std::copy(x.data(), x.data() + x.size(), y.begin());
  return r.status == numerics::IntegrateStatus::Reached ? "ok" : numerics::to_string(r.status);
}

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

}  // namespace

// Long for a reason: a benchmark driver read top to bottom (options, then scenes x solvers x
// tolerances into one CSV), kept in one piece like the astrojax bench it mirrors.
int main(int argc, char** argv) {
  CLI::App app{"astrojax_peers: peer ODE solvers on the smooth work-precision scenes (same CSV as astrojax bench)"};
  std::vector<std::string> paths, overrides;
  std::string output = "out/work_precision_peers.csv";
  double horizon = 10.0, budget = 2.0;
  int repeats = 5;
  std::vector<double> rtols{1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12};
  app.add_option("scenes", paths, "Run files (sweeps/scenes/*.toml)")->required();
  app.add_option("-o,--output", output, "CSV output path")->capture_default_str();
  app.add_option("-s,--set", overrides, "Override a key in every scene");
  app.add_option("--horizon", horizon, "Error measured at this time [s]")->capture_default_str();
  app.add_option("--rtols", rtols, "Relative tolerances (atol = 1e-3 rtol)")->delimiter(',');
  app.add_option("--repeats", repeats, "Timed runs per point (median kept)")->capture_default_str();
  app.add_option("--budget", budget, "Stop repeating a point after this much CPU [s]")->capture_default_str();
  std::string axes = "lab";
  app.add_option("--axes", axes, "Axes of every solver's RHS: lab, or rotating (turning with the motor)")
      ->check(CLI::IsMember({"lab", "rotating"}))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  const std::vector<std::pair<std::string, Solver>> solvers = {
      {"odeint-dopri5", [](Rhs& f, double a, double b, State& y, double r) { return odeint_run(f, a, b, y, r, 0); }},
      {"odeint-fehlberg78", [](Rhs& f, double a, double b, State& y, double r) { return odeint_run(f, a, b, y, r, 1); }},
      {"odeint-bulirsch-stoer", [](Rhs& f, double a, double b, State& y, double r) { return odeint_run(f, a, b, y, r, 2); }},
      {"cvode-adams", [](Rhs& f, double a, double b, State& y, double r) { return cvode_run(f, a, b, y, r, false); }},
      {"cvode-bdf", [](Rhs& f, double a, double b, State& y, double r) { return cvode_run(f, a, b, y, r, true); }},
      {"arkode-erk-dp5", [](Rhs& f, double a, double b, State& y, double r) { return arkode_run(f, a, b, y, r, ARKODE_DORMAND_PRINCE_7_4_5); }},
      {"arkode-erk-f78", [](Rhs& f, double a, double b, State& y, double r) { return arkode_run(f, a, b, y, r, ARKODE_FEHLBERG_13_7_8); }},
      {"ajx-dopri5-plain", [](Rhs& f, double a, double b, State& y, double r) { return plain_run(f, a, b, y, r, "dopri5"); }},
      {"ajx-dop853-plain", [](Rhs& f, double a, double b, State& y, double r) { return plain_run(f, a, b, y, r, "dop853"); }},
  };

  std::vector<bench::Scene> scenes;
  try {
    for (const auto& p : paths) scenes.push_back(bench::load_scene(p, overrides, horizon));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  std::ofstream csv(output);
  csv << "# astrojax_peers; reference: dop853 at rtol 1e-13 (astrojax bench); drift and energy at the horizon only\n";
  csv << bench::csv_header() << "\n";
  for (const bench::Scene& scene : scenes) {
    const bench::Reference ref = bench::reference(scene);
    if (ref.run.mode_switches != 0 || ref.run.final.contact.mode != scene.initial.contact.mode) {
      std::printf("%s: skipped, not smooth (%ld mode switches in the reference): the peers integrate one contact mode\n",
                  scene.name.c_str(), ref.run.mode_switches);
      continue;
    }
    std::printf("%s: one contact mode (%s), floor %.1e m\n", scene.name.c_str(),
                std::string(physics::to_string(scene.initial.contact.mode)).c_str(), ref.floor);
    const double t0 = scene.initial.t, t1 = t0 + scene.horizon;
    const bool rotating = axes == "rotating";
    const auto axes_angle = [&](double t) {
      double phi, w, wd;
      scene.schedule.phase(t, phi, w, wd);
      return rotating ? phi : 0.0;
    };
    Vec y_start = scene.initial.y;
    physics::rotate_about_z(y_start, -axes_angle(t0));
    const State y0(y_start.data(), y_start.data() + y_start.size());
    for (const auto& [name, solve] : solvers) {
      for (double rtol : rtols) {
        bench::Row row{scene.name, rotating ? name + "/rotating" : name, "rtol", rtol, {}, {}, NAN, {}, true, NAN};
        std::vector<double> times;
        double spent = 0.0;
        State y;
        long evals = 0;
        for (int k = 0; k < repeats; ++k) {
          Rhs f{scene, rotating};
          y = y0;
          const double c0 = cpu_seconds();
          const std::string status = solve(f, t0, t1, y, rtol);
          const double c = cpu_seconds() - c0;
          times.push_back(c);
          spent += c;
          if (k == 0) {
            row.out.status = status;
            evals = f.evals;
          }
          if (spent > budget) break;
        }
        std::sort(times.begin(), times.end());
        const std::size_t n = times.size();
        row.out.repeats = int(n);
        row.out.cpu_median = n % 2 ? times[n / 2] : 0.5 * (times[n / 2 - 1] + times[n / 2]);
        row.out.cpu_min = times.front();
        row.out.rhs_evals = evals;
        row.out.final = scene.initial;
        row.out.final.t = t1;
        row.out.final.y = Eigen::Map<const Eigen::VectorXd>(y.data(), Eigen::Index(y.size()));
        physics::rotate_about_z(row.out.final.y, axes_angle(t1));
        const physics::TopKinematics top = scene.schedule.top(t1);
        row.out.max_drift = physics::constraint_drift(scene.model, scene.initial.contact, top, row.out.final.y).position;
        row.out.energy_residual = physics::energy_balance(scene.model.p, scene.initial, row.out.final).relative();
        row.err = bench::compare(row.out.final, ref.run.final);
        csv << bench::csv_line(row, ref) << "\n";
        std::printf("  %-22s %8.1e  cpu %.3e s  err %.2e m  drift %.1e m  energy %.1e  evals %ld  %s\n", name.c_str(),
                    rtol, row.out.cpu_median, row.err.position, row.out.max_drift, row.out.energy_residual, evals,
                    row.out.status.c_str());
        std::fflush(stdout);
      }
    }
  }
  std::printf("-> %s\n", output.c_str());
  return 0;
}
