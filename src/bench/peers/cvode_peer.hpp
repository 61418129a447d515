// SUNDIALS on the hand-written model with its own root finding (the mode's guards, falling
// direction): CVODE Adams (fixed-point iteration, CVodeRootInit) and ARKODE's explicit
// ERKStep (ERKStepRootInit), the peers without the guarantee. With it
// (PeerOptions::guarantee), the solver also steps one step at a time with its maximum step
// set to (k+1)/Ω before each, and samples the guards on its own interpolant (GetDky) at the
// interior points a step needs; a crossing there is located by Illinois on the interpolant.
// At a root the solver returns the interpolated state there; the mode is switched, the state
// projected onto the new mode's constraints, and the solver re-initialised. Neither projects
// between events.
#pragma once
#include <arkode/arkode_erkstep.h>
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "bench/peers/hand_model.hpp"
#include "bench/peers/hybrid_peer.hpp"

namespace ajx::hand {

namespace detail {
struct CvodeUser {
  const Params* p;
  Contact* c;
  long* evals;
};
inline int cv_rhs(double t, N_Vector y, N_Vector ydot, void* u) {
  auto* user = static_cast<CvodeUser*>(u);
  ++*user->evals;
  rhs(*user->p, *user->c, t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
  return 0;
}
inline int cv_guards(double t, N_Vector y, double* g, void* u) {
  auto* user = static_cast<CvodeUser*>(u);
  guards(*user->p, *user->c, t, N_VGetArrayPointer(y), g);
  return 0;
}

// The calls the event loop makes, CVODE's or ERKStep's (same signatures but ReInit).
struct SolverApi {
  int (*root_init)(void*, int, CVRootFn);
  int (*set_root_direction)(void*, int*);
  int (*set_stop_time)(void*, double);
  int (*set_max_step)(void*, double);
  int (*evolve)(void*, double, N_Vector, double*, int);
  int (*get_dky)(void*, double, int, N_Vector);
  int (*get_root_info)(void*, int*);
  int (*get_num_steps)(void*, long*);
  int (*reinit)(void*, double, N_Vector);
  int normal, one_step, root_return;
};
inline const SolverApi cvode_api{CVodeRootInit, CVodeSetRootDirection, CVodeSetStopTime, CVodeSetMaxStep, CVode,
                                 CVodeGetDky, CVodeGetRootInfo, CVodeGetNumSteps,
                                 [](void* m, double t, N_Vector y) { return CVodeReInit(m, t, y); },
                                 CV_NORMAL, CV_ONE_STEP, CV_ROOT_RETURN};
inline const SolverApi erkstep_api{
    ERKStepRootInit, ERKStepSetRootDirection, ERKStepSetStopTime, ERKStepSetMaxStep, ERKStepEvolve,
    ERKStepGetDky, ERKStepGetRootInfo, ERKStepGetNumSteps,
    [](void* m, double t, N_Vector y) { return ERKStepReInit(m, cv_rhs, t, y); }, ARK_NORMAL, ARK_ONE_STEP,
    ARK_ROOT_RETURN};

}  // namespace detail

// The event loop on a created solver (mem, its state y, user data wired to c and the evals).
// Long for a reason: the loop of a hybrid integrator around SUNDIALS (evolve, sample, locate,
// switch, re-initialise), in one piece.
inline void sundials_events(const detail::SolverApi& api, void* mem, N_Vector y, const Params& p, Contact& c,
                            PeerRun& run, double t0, double t1, const PeerOptions& o,
                            const std::vector<double>& breakpoints) {
  double g[8];
  const auto arm = [&](double t) {  // the current mode's guards, all falling
    const int n = guards(p, c, t, N_VGetArrayPointer(y), g);
    api.root_init(mem, n, detail::cv_guards);
    std::vector<int> dir(n, -1);
    api.set_root_direction(mem, dir.data());
    return n;
  };
  int ng = arm(t0);
  double t = t0;
  N_Vector yk = N_VClone(y);
  // The guards on CVODE's interpolant at tk (valid over the last step).
  const auto guards_at = [&](double tk, double* gk) {
    api.get_dky(mem, tk, 0, yk);
    return guards(p, c, tk, N_VGetArrayPointer(yk), gk);
  };
  while (t < t1) {
    double t_stop = t1;
    for (double b : breakpoints)
      if (b > t + 1e-12 && b < t_stop) t_stop = b;
    api.set_stop_time(mem, t_stop);
    int flag, hit = -1;
    if (!o.guarantee) {
      flag = api.evolve(mem, t_stop, y, &t, api.normal);
    } else {  // one step at a time: h <= (k+1)/Ω, and the interior samples a step needs
      const double omega = guard_rate(p, t, N_VGetArrayPointer(y)), t_prev = t;
      api.set_max_step(mem, (o.samples + 1) / omega);
      flag = api.evolve(mem, t_stop, y, &t, api.one_step);
      const int n = std::clamp(int(std::ceil((t - t_prev) * omega)) - 1, 0, o.samples);
      double ga[8], gb[8];
      if (flag >= 0 && flag != api.root_return && n > 0) {
        guards_at(t_prev, ga);
        double ta = t_prev, tb = t;
        for (int k = 1; k <= n && hit < 0; ++k) {
          tb = t_prev + (t - t_prev) * k / (n + 1);
          guards_at(tb, gb);
          hit = detail::first_crossing(ga, gb, ng);
          if (hit < 0) std::copy(gb, gb + ng, ga), ta = tb;
        }
        if (hit >= 0) {  // Illinois on the interpolant, the far side kept
          double fa = ga[hit], fb = gb[hit];
          for (int it = 0, side = 0; it < 60 && tb - ta > o.event_tol; ++it) {
            double tm = tb - fb * (tb - ta) / (fb - fa);
            if (!(tm > ta && tm < tb)) tm = 0.5 * (ta + tb);
            double gm[8];
            guards_at(tm, gm);
            if (gm[hit] <= 0) tb = tm, fb = gm[hit], fa *= side == -1 ? 0.5 : 1.0, side = -1;
            else ta = tm, fa = gm[hit], fb *= side == +1 ? 0.5 : 1.0, side = +1;
          }
          api.get_dky(mem, tb, 0, y);
          t = tb;
        }
      }
    }
    if (flag < 0) {
      run.status = "SUNDIALS flag " + std::to_string(flag);
      break;
    }
    if (flag == api.root_return) {
      std::vector<int> found(ng, 0);
      api.get_root_info(mem, found.data());
      hit = int(std::find_if(found.begin(), found.end(), [](int f) { return f != 0; }) - found.begin());
    }
    if (hit >= 0) {
      double* yp = N_VGetArrayPointer(y);
      project(p, c, t, yp, o.projection_tol);
      if (++run.switches > o.max_events) { run.status = "too many events"; break; }
      if (!switch_mode(p, c, hit, t, yp)) { run.status = "slack string (not modelled)"; break; }
      project(p, c, t, yp, o.projection_tol);
    }
    if (t < t1 && (hit >= 0 || t >= t_stop)) {  // after an event or at a breakpoint of the drive: restart
      long steps = 0;
      api.get_num_steps(mem, &steps);
      run.steps += steps;
      api.reinit(mem, t, y);
      ng = arm(t);
    }
  }
  N_VDestroy(yk);
  long steps = 0;
  api.get_num_steps(mem, &steps);
  run.steps += steps;
  std::copy(N_VGetArrayPointer(y), N_VGetArrayPointer(y) + 12, run.y.begin());
  run.contact = c;
}

// One SUNDIALS solver's life: context, state, the solver made by `create`, the event loop, the
// clean-up. `create` returns the solver's memory (and any nonlinear solver to free, or null).
template <class Create, class Free>
PeerRun run_sundials(const detail::SolverApi& api, Create create, Free free_mem, const Params& p, Contact c,
                     const Y& y0, double t0, double t1, const PeerOptions& o, const std::vector<double>& breakpoints) {
  PeerRun run;
  run.y = y0;
  detail::CvodeUser user{&p, &c, &run.evals};
  SUNContext ctx = nullptr;
  SUNContext_Create(nullptr, &ctx);
  N_Vector y = N_VNew_Serial(12, ctx);
  std::copy(y0.begin(), y0.end(), N_VGetArrayPointer(y));
  SUNNonlinearSolver nls = nullptr;
  void* mem = create(ctx, y, &user, nls);
  sundials_events(api, mem, y, p, c, run, t0, t1, o, breakpoints);
  if (nls) SUNNonlinSolFree(nls);
  free_mem(&mem);
  N_VDestroy(y);
  SUNContext_Free(&ctx);
  return run;
}

// CVODE Adams with fixed-point iteration.
inline PeerRun run_cvode_adams(const Params& p, Contact c, const Y& y0, double t0, double t1, const PeerOptions& o,
                               const std::vector<double>& breakpoints) {
  const auto create = [&](SUNContext ctx, N_Vector y, void* user, SUNNonlinearSolver& nls) {
    void* mem = CVodeCreate(CV_ADAMS, ctx);
    CVodeInit(mem, detail::cv_rhs, t0, y);
    CVodeSStolerances(mem, o.rtol, 1e-3 * o.rtol);
    CVodeSetUserData(mem, user);
    CVodeSetMaxNumSteps(mem, 100'000'000);
    nls = SUNNonlinSol_FixedPoint(y, 0, ctx);
    CVodeSetNonlinearSolver(mem, nls);
    return mem;
  };
  return run_sundials(detail::cvode_api, create, CVodeFree, p, c, y0, t0, t1, o, breakpoints);
}

// ARKODE's explicit ERKStep with the Fehlberg 7(8) table.
inline PeerRun run_arkode_f78(const Params& p, Contact c, const Y& y0, double t0, double t1, const PeerOptions& o,
                              const std::vector<double>& breakpoints) {
  const auto create = [&](SUNContext ctx, N_Vector y, void* user, SUNNonlinearSolver&) {
    void* mem = ERKStepCreate(detail::cv_rhs, t0, y, ctx);
    ERKStepSetTableNum(mem, ARKODE_FEHLBERG_13_7_8);
    ERKStepSStolerances(mem, o.rtol, 1e-3 * o.rtol);
    ERKStepSetUserData(mem, user);
    ERKStepSetMaxNumSteps(mem, 100'000'000);
    return mem;
  };
  return run_sundials(detail::erkstep_api, create, ERKStepFree, p, c, y0, t0, t1, o, breakpoints);
}

}  // namespace ajx::hand
