// CVODE (Adams, fixed-point iteration) on the hand-written model with its own root finding
// (CVodeRootInit on the mode's guards, falling direction): the peer without the guarantee.
// At a root CVODE returns the interpolated state there; the mode is switched, the state
// projected onto the new mode's constraints, and CVODE re-initialised. CVODE Adams has no
// projection of its own, so none between events (the drift is reported).
#pragma once
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

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
  while (t < t1) {
    double t_stop = t1;
    for (double b : breakpoints)
      if (b > t + 1e-12 && b < t_stop) t_stop = b;
    CVodeSetStopTime(mem, t_stop);
    const int flag = CVode(mem, t_stop, y, &t, CV_NORMAL);
    if (flag < 0) {
      run.status = "CVode flag " + std::to_string(flag);
      break;
    }
    if (flag == CV_ROOT_RETURN) {
      std::vector<int> found(ng, 0);
      CVodeGetRootInfo(mem, found.data());
      const int hit = int(std::find_if(found.begin(), found.end(), [](int f) { return f != 0; }) - found.begin());
      double* yp = N_VGetArrayPointer(y);
      project(p, c, t, yp, o.projection_tol);
      if (++run.switches > o.max_events) { run.status = "too many events"; break; }
      if (!switch_mode(p, c, hit, t, yp)) { run.status = "slack string (not modelled)"; break; }
      project(p, c, t, yp, o.projection_tol);
    }
    if (t < t1) {  // after an event or at a breakpoint of the drive: restart
      long steps = 0;
      CVodeGetNumSteps(mem, &steps);
      run.steps += steps;
      CVodeReInit(mem, t, y);
      ng = arm(t);
    }
  }
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
