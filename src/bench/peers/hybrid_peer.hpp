// The hand-written peer's driver: a Boost.Odeint controlled stepper on hand::rhs, with the
// hybrid part a user would add by hand: projection after every step, the mode's guards checked
// for a sign change, the crossing located, the mode switched, and the stepper restarted.
//  - without the guarantee (samples = 0, no bound): the guards at step ends only;
//  - with it: steps capped at (k+1)/Ω (hand::guard_rate at the step's start) and the guards
//    also sampled at the ⌈hΩ⌉ − 1 (≤ k) equally spaced interior points a step needs, as the
//    project does.
// Odeint's controlled steppers give no dense output for rkf78, so every peer samples a cubic
// Hermite interpolant of the step (its end derivatives evaluated only for steps that sample).
// A sign change seen there is confirmed on the true trajectory (a re-integration from the
// step's start; a false alarm of the interpolant falls back to the step-end check) and refined
// by Illinois iterations whose points are such re-integrations (one step each), to event_tol;
// the run continues from the far side of the crossing.
#pragma once
#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "bench/peers/hand_model.hpp"

namespace ajx::hand {

struct PeerOptions {
  double rtol = 1e-6;        // atol = 1e-3 rtol
  bool guarantee = false;    // the step cap and the interior samples
  int samples = 3;           // k, with the guarantee
  double projection_tol = 1e-12;
  double event_tol = 1e-13;  // [s]
  long max_events = 10000;
};

struct PeerRun {
  std::string status = "ok";
  Contact contact;
  Y y{};
  long evals = 0, steps = 0, rejected = 0, switches = 0;
};

namespace detail {

// Cubic Hermite interpolant on [t0, t0 + h] from the end values and derivatives.
inline Y hermite(const Y& y0, const Y& f0, const Y& y1, const Y& f1, double h, double theta) {
  const double t2 = theta * theta, t3 = t2 * theta;
  const double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + theta, h01 = -2 * t3 + 3 * t2, h11 = t3 - t2;
  Y y;
  for (int i = 0; i < 12; ++i) y[i] = h00 * y0[i] + h10 * h * f0[i] + h01 * y1[i] + h11 * h * f1[i];
  return y;
}

// Index of the first guard (direction: falling) that went from > 0 to <= 0 between a and b, or -1.
inline int first_crossing(const double* ga, const double* gb, int n) {
  for (int i = 0; i < n; ++i)
    if (ga[i] > 0 && gb[i] <= 0) return i;
  return -1;
}

}  // namespace detail

// Runs the scene from (t0, y0) in mode c to t1, stopping at the drive's breakpoints.
// Long for a reason: the step loop of a hybrid integrator (step, project, sample, locate,
// switch), kept in one piece as a peer would write it.
template <class Controlled>
PeerRun run_peer(const Params& p, Contact c, const Y& y0, double t0, double t1, Controlled ctl,
                 const PeerOptions& o, const std::vector<double>& breakpoints) {
  namespace odeint = boost::numeric::odeint;
  PeerRun run;
  run.y = y0;
  auto sys = [&](const Y& x, Y& dx, double t) {
    ++run.evals;
    rhs(p, c, t, x.data(), dx.data());
  };
  // The true state a time tau after (ta, ya): re-integrated with the same controller.
  auto reach = [&](double ta, const Y& ya, double tau, double h_hint) {
    Y x = ya;
    Controlled fresh = ctl;
    odeint::integrate_adaptive(fresh, sys, x, ta, ta + tau, std::min(tau, h_hint));
    return x;
  };
  double t = t0, dt = 1e-3;
  double g_start[8], g_end[8];
  int ng = guards(p, c, t, run.y.data(), g_start);
  while (t < t1) {
    double t_stop = t1;
    for (double b : breakpoints)
      if (b > t + 1e-12 && b < t_stop) t_stop = b;
    const double omega = o.guarantee ? guard_rate(p, t, run.y.data()) : 0.0;
    double h = std::min(dt, t_stop - t);
    if (o.guarantee) h = std::min(h, (o.samples + 1) / omega);
    Y x = run.y;
    double tt = t, hh = h;
    if (ctl.try_step(sys, x, tt, hh) == odeint::fail) {
      ++run.rejected;
      dt = hh;
      if (hh < 1e-14) return run.status = "step size underflow", run;
      continue;
    }
    ++run.steps;
    const double taken = tt - t;
    dt = std::abs(tt - t_stop) < 1e-12 ? std::max(dt, hh) : hh;
    if (std::abs(tt - t_stop) < 1e-12) tt = t_stop;
    project(p, c, tt, x.data(), o.projection_tol);
    ng = guards(p, c, tt, x.data(), g_end);
    // The samples: the fewest that keep them 1/Ω apart, at most k.
    const int n = o.guarantee ? std::clamp(int(std::ceil(taken * omega)) - 1, 0, o.samples) : 0;
    int hit = detail::first_crossing(g_start, g_end, ng);
    double ta = t, tb = tt, ga = 0, gb = 0;
    Y f0{}, f1{};
    const auto derivatives = [&] {
      sys(run.y, f0, t);
      sys(x, f1, tt);
    };
    if (n > 0 || hit >= 0) {
      if (n > 0) derivatives();
      double g_prev[8];
      std::copy(g_start, g_start + ng, g_prev);
      double t_prev = t;
      for (int k = 1; k <= n + 1; ++k) {
        const double tk = t + taken * k / (n + 1);
        double gk[8];
        if (k == n + 1) std::copy(g_end, g_end + ng, gk);
        else guards(p, c, tk, detail::hermite(run.y, f0, x, f1, taken, double(k) / (n + 1)).data(), gk);
        const int i = detail::first_crossing(g_prev, gk, ng);
        if (i >= 0) {
          hit = i, ta = t_prev, tb = tk, ga = g_prev[i], gb = gk[i];
          break;
        }
        std::copy(gk, gk + ng, g_prev);
        t_prev = tk;
        if (k == n + 1) hit = -1;
      }
    }
    Y x_far = x;
    if (hit >= 0 && tb != tt) {  // a crossing seen on the interpolant: confirm it on the trajectory
      const Y xb = reach(t, run.y, tb - t, taken);
      double gv[8];
      guards(p, c, tb, xb.data(), gv);
      if (gv[hit] <= 0) {
        gb = gv[hit], x_far = xb;
      } else {  // a false alarm of the interpolant: only a sign change at the step's end counts
        hit = detail::first_crossing(g_start, g_end, ng);
        if (hit >= 0) ta = t, tb = tt, ga = g_start[hit], gb = g_end[hit];
      }
    }
    if (hit < 0) {
      run.y = x;
      t = tt;
      std::copy(g_end, g_end + ng, g_start);
      continue;
    }
    // Locate: Illinois on the true guard, the far side kept.
    const double h_hint = taken;
    int side = 0;
    for (int it = 0; it < 12 && tb - ta > o.event_tol; ++it) {
      double tm = tb - gb * (tb - ta) / (gb - ga);
      if (!(tm > ta && tm < tb)) tm = 0.5 * (ta + tb);
      const Y xm = reach(t, run.y, tm - t, h_hint);
      double gm[8];
      guards(p, c, tm, xm.data(), gm);
      if (gm[hit] <= 0) {
        tb = tm, gb = gm[hit], x_far = xm;
        if (side == -1) ga *= 0.5;
        side = -1;
      } else {
        ta = tm, ga = gm[hit];
        if (side == +1) gb *= 0.5;
        side = +1;
      }
    }
    t = tb;
    run.y = x_far;
    project(p, c, t, run.y.data(), o.projection_tol);
    if (++run.switches > o.max_events) return run.status = "too many events", run;
    if (!switch_mode(p, c, hit, t, run.y.data())) return run.status = "slack string (not modelled)", run;
    project(p, c, t, run.y.data(), o.projection_tol);
    ng = guards(p, c, t, run.y.data(), g_start);
  }
  run.contact = c;
  return run;
}

}  // namespace ajx::hand
