// CVODE (Adams, fixed-point iteration) on the hand-written model with its own root finding
// (CVodeRootInit on the mode's guards, falling direction): the peer without the guarantee.
// With it (PeerOptions::guarantee), CVODE also steps one step at a time with its maximum step
// set to (k+1)/Ω before each, and samples the guards on its own interpolant (CVodeGetDky) at
// the interior points a step needs; a crossing there is located by Illinois on the interpolant.
// At a root CVODE returns the interpolated state there; the mode is switched, the state
// projected onto the new mode's constraints, and CVODE re-initialised. CVODE Adams has no
// projection of its own, so none between events (the drift is reported).
#pragma once
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
}  // namespace detail

// Long for a reason: CVODE's set-up, the event loop and the clean-up, in one piece.
inline PeerRun run_cvode_adams(const Params& p, Contact c, const Y& y0, double t0, double t1, const PeerOptions& o,
                               const std::vector<double>& breakpoints) {
  PeerRun run;
  run.y = y0;
  detail::CvodeUser user{&p, &c, &run.evals};
  SUNContext ctx = nullptr;
  SUNContext_Create(nullptr, &ctx);
  N_Vector y = N_VNew_Serial(12, ctx);
  std::copy(y0.begin(), y0.end(), N_VGetArrayPointer(y));
  void* mem = CVodeCreate(CV_ADAMS, ctx);
  CVodeInit(mem, detail::cv_rhs, t0, y);
  CVodeSStolerances(mem, o.rtol, 1e-3 * o.rtol);
  CVodeSetUserData(mem, &user);
  CVodeSetMaxNumSteps(mem, 100'000'000);
  SUNNonlinearSolver nls = SUNNonlinSol_FixedPoint(y, 0, ctx);
  CVodeSetNonlinearSolver(mem, nls);
  double g[8];
  const auto arm = [&](double t) {  // the current mode's guards, all falling
    const int n = guards(p, c, t, N_VGetArrayPointer(y), g);
    CVodeRootInit(mem, n, detail::cv_guards);
    std::vector<int> dir(n, -1);
    CVodeSetRootDirection(mem, dir.data());
    return n;
  };
  int ng = arm(t0);
  double t = t0;
  N_Vector yk = N_VClone(y);
  // The guards on CVODE's interpolant at tk (valid over the last step).
  const auto guards_at = [&](double tk, double* gk) {
    CVodeGetDky(mem, tk, 0, yk);
    return guards(p, c, tk, N_VGetArrayPointer(yk), gk);
  };
  while (t < t1) {
    double t_stop = t1;
    for (double b : breakpoints)
      if (b > t + 1e-12 && b < t_stop) t_stop = b;
    CVodeSetStopTime(mem, t_stop);
    int flag, hit = -1;
    if (!o.guarantee) {
      flag = CVode(mem, t_stop, y, &t, CV_NORMAL);
    } else {  // one step at a time: h <= (k+1)/Ω, and the interior samples a step needs
      const double omega = guard_rate(p, t, N_VGetArrayPointer(y)), t_prev = t;
      CVodeSetMaxStep(mem, (o.samples + 1) / omega);
      flag = CVode(mem, t_stop, y, &t, CV_ONE_STEP);
      const int n = std::clamp(int(std::ceil((t - t_prev) * omega)) - 1, 0, o.samples);
      double ga[8], gb[8];
      if (flag >= 0 && flag != CV_ROOT_RETURN && n > 0) {
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
          CVodeGetDky(mem, tb, 0, y);
          t = tb;
        }
      }
    }
    if (flag < 0) {
      run.status = "CVode flag " + std::to_string(flag);
      break;
    }
    if (flag == CV_ROOT_RETURN) {
      std::vector<int> found(ng, 0);
      CVodeGetRootInfo(mem, found.data());
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
      CVodeGetNumSteps(mem, &steps);
      run.steps += steps;
      CVodeReInit(mem, t, y);
      ng = arm(t);
    }
  }
  N_VDestroy(yk);
  long steps = 0;
  CVodeGetNumSteps(mem, &steps);
  run.steps += steps;
  std::copy(N_VGetArrayPointer(y), N_VGetArrayPointer(y) + 12, run.y.begin());
  run.contact = c;
  SUNNonlinSolFree(nls);
  CVodeFree(&mem);
  N_VDestroy(y);
  SUNContext_Free(&ctx);
  return run;
}

}  // namespace ajx::hand
