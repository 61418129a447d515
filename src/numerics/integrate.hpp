// The integration driver: step-size control, event location on the dense output, and
// observers, separate from the steppers (which only know their tableau).
#pragma once
#include <functional>
#include <span>
#include <string>

#include "numerics/stepper.hpp"

namespace ajx::numerics {

// A zero crossing of g(t, y) that ends the integration (a mode switch, a stop, ...).
// direction: +1 only rising (g goes - to +), -1 only falling, 0 either; rising and falling
// are meant along the integration (from the start of a step to its end, also backwards).
// A g that is exactly 0 at the start of the integration does not fire there: only a sign
// change after g has left zero counts. The located event time lies on the far side of the
// crossing (within event_tol), so restarting from the returned state does not see the same
// crossing again.
// change_bound (optional) certifies that a step cannot cross (conservative advancement): given
// e with e_i >= |y_i(t) - y0_i| on the step's interpolant over [t0, t1], it returns a bound on
// |g(t, y(t)) - g(t0, y0)| over the step. A guard with |g(t0, y0)| above it keeps its sign
// throughout the step, so the step needs no guard samples for it (IntegrateOptions::event_samples).
struct Event {
  std::function<double(double t, const Vec& y)> g;
  int direction = 0;
  std::function<double(double t0, double t1, const Vec& y0, const Vec& e)> change_bound = {};
};

// Interpolation over the last accepted step [t0, t1], handed to observers.
class StepView {
 public:
  StepView(Stepper& s, const System& f, double t0, double t1)
      : s_(s), f_(f), t0_(t0), t1_(t1), h_(t1 - t0) {}
  // A step of size h cut short at t1 (an event inside it): theta = (t - t0) / h. y1, when
  // given, is y(t1), which end() then hands out without touching the interpolant.
  StepView(Stepper& s, const System& f, double t0, double t1, double h, const Vec* y1 = nullptr)
      : s_(s), f_(f), t0_(t0), t1_(t1), h_(h), y1_(y1) {}
  double t0() const { return t0_; }
  double t1() const { return t1_; }
  // y(t) for t in [t0, t1] from the stepper's interpolant (DOP853 pays 3 extra stages for it,
  // once per step).
  void at(double t, Vec& out) const;
  // y(t1) (free when the driver passed it).
  void end(Vec& out) const;

 private:
  Stepper& s_;
  const System& f_;
  double t0_, t1_;
  double h_;  // size of the stepper's step starting at t0 (t1 - t0 unless cut by an event)
  const Vec* y1_ = nullptr;
};

struct IntegrateOptions {
  Tolerances tol;
  double h_init = 0.0;       // first step; 0 picks one from the tolerances (adaptive) or h_fixed
  double h_fixed = 5e-4;     // step of fixed-step methods [s] (the paper's 1/2000 s)
  double h_max = 0.05;       // [s]
  double h_min = 1e-12;      // below this an adaptive step is a failure [s]
  long max_steps = 200'000'000;
  double event_tol = 1e-13;  // event time located to this absolute precision [s]
  // Adaptive methods: a further bound on the next step from the accepted state (t, y), e.g. the
  // time scale of the events' guards (sim/step_bound.hpp); absent: h_max alone.
  std::function<double(double t, const Vec& y)> h_bound;
  // Guard samples inside each accepted step: up to this many equally spaced interior points
  // where the events' g are evaluated, so that a crossing that goes and comes back between the
  // step's ends is still seen if a sample falls past it. They are taken on the stepper's cheap
  // interpolant where it has one (Stepper::cheap_interpolant; DOP853's cubic Hermite, error
  // ≤ h⁴ max|y⁽⁴⁾|/384), and again on the dense output, which confirms and locates, only in a
  // step where those show a sign change. With h_bound,
  // a step uses the fewest samples that keep them at most h_bound(t, y) / (event_samples + 1)
  // apart (h_bound at the step's start state; also for fixed-step methods, whose steps it does
  // not bound): a step that is already that short pays for none. Without h_bound, every step
  // uses all of them. 0: the step ends alone.
  // Conservative advancement: when every event has a change_bound and the stepper an excursion
  // bound (Stepper::dense_excursion), a step that would need samples first asks each event
  // whether it can cross; those that cannot are not sampled. After a step in which no event
  // could cross, the next step is not bounded by h_bound (it is far from every guard); a step
  // so taken that turns out to need samples gets as many as keep them h_bound / (event_samples
  // + 1) apart, and the bound applies again from then on.
  int event_samples = 0;
};

enum class IntegrateStatus { Reached, Event, StepUnderflow, NonFinite, MaxSteps, Stopped };
std::string to_string(IntegrateStatus s);

struct IntegrateResult {
  IntegrateStatus status = IntegrateStatus::Reached;
  double t = 0.0;          // time reached (t_end, or the event time)
  int event_index = -1;    // which event fired, when status == Event
  long steps = 0;          // accepted steps
  long rejected = 0;       // rejected attempts
  double h_next = 0.0;     // suggested next step, to continue without a cold start
};

// Called after every accepted step (before projection); return false to stop.
using StepObserver = std::function<bool(const StepView& step)>;
// Called after every accepted step that raised no event; may change y in place (projection
// onto a constraint manifold). Return true when y was changed (the stepper is then reset).
using PostStep = std::function<bool(double t, Vec& y)>;

// Integrate dy/dt = f(t, y) from (t0, y) towards t_end. On return y holds the state at
// result.t. If an event fires inside a step, the step is cut at the located root (to
// event_tol) and y is the interpolated state there; events are checked only after an
// accepted step, against the sign of g at the step's start, at the step's end and at its
// interior samples (event_samples), the first sign change in time order being located. Every call starts with
// stepper.reset() (f may differ from the previous call's: no stage is carried over); pass
// h_init = result.h_next to continue without a cold-start step-size search.
IntegrateResult integrate(const System& f, Stepper& stepper, double t0, Vec& y, double t_end,
                          std::span<const Event> events, const StepObserver& observe,
                          const PostStep& post_step, const IntegrateOptions& opt);

}  // namespace ajx::numerics
