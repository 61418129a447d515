#include "numerics/integrate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace ajx::numerics {

void StepView::at(double t, Vec& out) const { s_.dense(f_, (t - t0_) / h_, out); }

void StepView::end(Vec& out) const {
  if (y1_)
    out = *y1_;
  else
    at(t1_, out);
}

std::string to_string(IntegrateStatus s) {
  switch (s) {
    case IntegrateStatus::Reached:
      return "reached";
    case IntegrateStatus::Event:
      return "event";
    case IntegrateStatus::StepUnderflow:
      return "step underflow";
    case IntegrateStatus::NonFinite:
      return "non-finite state";
    case IntegrateStatus::MaxSteps:
      return "max steps";
    case IntegrateStatus::Stopped:
      return "stopped";
  }
  return "unknown";
}

namespace {

// PI step-size control (Gustafsson; Hairer & Wanner, Solving ODEs II, IV.2, as in dopri5.f):
// after an accepted step, h_new = h * clamp(safety * err^-alpha * err_old^beta, facmin,
// facmax), alpha = 1/p - 0.75 beta, err_old = max(previous accepted err, 1e-4); facmax is 1
// right after a rejection. After a rejection, h_new = h * max(facmin, safety * err^-alpha).
constexpr double kSafety = 0.9;
constexpr double kFacMin = 0.2;
constexpr double kFacMax = 10.0;
constexpr double kBeta = 0.04;
constexpr double kErrOldMin = 1e-4;
// Guard samples of a step taken without the h_bound bound (conservative advancement) at most.
constexpr double kMaxCertifiedSamples = 1000.0;

// RMS of v_i / (atol + rtol |y_i|).
double scaled_rms(const Vec& v, const Vec& y, const Tolerances& tol) {
  double s = 0.0;
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    const double r = v[i] / (tol.atol + tol.rtol * std::abs(y[i]));
    s += r * r;
  }
  return std::sqrt(s / static_cast<double>(v.size()));
}

// Starting step of Hairer, Norsett & Wanner, Solving ODEs I, II.4 (HINIT of dopri5.f), in the
// RMS norm: h0 = 0.01 ||y0|| / ||f0||; one explicit Euler step gives a second-derivative
// estimate d2 = ||f(t0 + h0, y0 + h0 f0) - f0|| / h0; then
// h = min(100 h0, (0.01 / max(d2, ||f0||))^(1/p), h_max).
double initial_step(const System& f, Stepper& stepper, double t0, const Vec& y0, double dir,
                    const IntegrateOptions& opt) {
  const auto n = y0.size();
  Vec f0(n), y1(n), f1(n);
  f(t0, y0, f0);
  const double dnf = scaled_rms(f0, y0, opt.tol);
  const double dny = scaled_rms(y0, y0, opt.tol);
  double h = (dnf <= 1e-5 || dny <= 1e-5) ? 1e-6 : 0.01 * dny / dnf;
  h = std::min(h, opt.h_max);
  y1 = y0 + (dir * h) * f0;
  f(t0 + dir * h, y1, f1);
  stepper.count_rhs_evals(2);
  f1 -= f0;
  const double der2 = scaled_rms(f1, y0, opt.tol) / h;
  const double der12 = std::max(std::abs(der2), dnf);
  const double h1 =
      der12 <= 1e-15 ? std::max(1e-6, h * 1e-3) : std::pow(0.01 / der12, 1.0 / stepper.order());
  h = std::min({100.0 * h, h1, opt.h_max});
  // A non-finite derivative is left to the step loop (it rejects and shrinks).
  if (!(h > 0.0) || !std::isfinite(h)) h = std::min(1e-6, opt.h_max);
  return h;
}

// Sign-change test for one event over [ta, tb] along the integration, ga != 0:
// a root when g goes from ga to gb = 0 or to the opposite sign; "rising" is - to +.
bool crosses(double ga, double gb, int direction) {
  const bool rising = ga < 0.0 && gb >= 0.0;
  const bool falling = ga > 0.0 && gb <= 0.0;
  if (direction > 0) return rising;
  if (direction < 0) return falling;
  return rising || falling;
}

// Root of G on the bracket [ta, tb] (ga != 0, gb = 0 or of the other sign), by the Illinois
// variant of regula falsi (Dowell & Jarratt 1971) with a bisection fallback, until the
// bracket is narrower than tol or has no double inside. Returns the end on the far side of the
// crossing (where G has already changed sign, or G = 0), so that restarting from the returned
// state does not see the same crossing again.
template <class G>
double locate_root(G&& g, double ta, double ga, double tb, double gb, double tol) {
  if (gb == 0.0) return tb;
  int side = 0;  // which end was moved last: -1 the b end, +1 the a end
  for (int iter = 0; iter < 300; ++iter) {
    if (std::abs(tb - ta) <= tol) break;
    double tm = tb - gb * (tb - ta) / (gb - ga);
    const bool inside = (tm - ta) * (tb - tm) > 0.0;
    if (!inside || iter >= 100) tm = 0.5 * (ta + tb);  // safeguard; pure bisection late
    if (tm == ta || tm == tb) break;                   // no double left inside
    const double gm = g(tm);
    if (gm == 0.0) return tm;
    if ((gm < 0.0) == (gb < 0.0)) {  // root in [ta, tm]
      tb = tm;
      gb = gm;
      if (side == -1) ga *= 0.5;  // Illinois: the a end was kept twice
      side = -1;
    } else {  // root in [tm, tb]
      ta = tm;
      ga = gm;
      if (side == +1) gb *= 0.5;
      side = +1;
    }
  }
  return tb;
}

// One call of integrate(): the state its stages share (the step's ends, the events' brackets,
// the counters), so that each stage is a member function rather than a closure over a dozen
// locals. The stages, in the order a step meets them:
//   stepping           fixed_steps, adaptive_steps (with PiControl): attempt, accept or reject;
//   guard sampling     interior_samples, certify, cheap_sign_change: where in the step each
//                      event's g is looked at;
//   event location     open_brackets, earliest_root, bracket_root, stop_at_event: the first
//                      crossing in time order, located on the dense output;
//   post-step actions  finish_step: observer, projection, the next step's g0.
class Integration {
 public:
  Integration(const System& f, Stepper& stepper, double t0, Vec& y, double t_end, std::span<const Event> events,
              const StepObserver& observe, const PostStep& post_step, const IntegrateOptions& opt);
  Integration(const Integration&) = delete;  // g0_ ... point into g_small_
  Integration& operator=(const Integration&) = delete;

  IntegrateResult run() { return stepper_.adaptive() ? adaptive_steps() : fixed_steps(); }

 private:
  IntegrateResult fixed_steps();
  IntegrateResult adaptive_steps();
  double first_step();
  bool after_step(double t1, double hs);
  int interior_samples(double hs) const;
  int certify(double t1, int n);
  void open_brackets(double hs);
  bool cheap_sign_change(double t1, double hs, int n_samples);
  int earliest_root(double t1, double hs, int n, double& t_best);
  void bracket_root(std::size_t i, double ts, double hs, int& best, double& t_best);
  bool stop_at_event(int best, double t_best, double t1, double hs);
  bool finish_step(double t1, double hs);
  // g_i at tq inside the current step [t_, t_ + hs], on the dense output.
  double g_at(std::size_t i, double tq, double hs) {
    stepper_.dense(f_, (tq - t_) / hs, y_ev_);
    return events_[i].g(tq, y_ev_);
  }

  const System& f_;
  Stepper& stepper_;
  Vec& y_;  // the state at t_ (the step's start); at return, at res_.t
  const std::span<const Event> events_;
  const StepObserver& observe_;
  const PostStep& post_step_;
  const IntegrateOptions& opt_;
  const double t0_, t_end_;
  const double dir_;      // +1 forwards, -1 backwards
  const std::size_t m_;   // events
  Vec y_new_, y_ev_;      // the step's end; a state inside it
  IntegrateResult res_;
  double t_;              // start of the current step

  // Event bookkeeping: g at the start of the current step (g0) and at its end (g1).
  // Rule for g0 == 0 exactly (a start on the surface, or a restart at a located root): the
  // zero itself is never a crossing. The sign g takes just after the start is probed on the
  // dense output at ta = t + dir * delta (delta = max(event_tol, 1e-6 |h|), at most |h|/2);
  // only a sign change between ta and the step end counts. If g is still exactly 0 at ta the
  // event cannot fire in this step. A step end where g = 0 exactly after a nonzero start is
  // a root (at the step end). Two crossings between consecutive guard samples (the step's ends
  // and its interior samples, IntegrateOptions::event_samples) cancel and are not seen.
  // g values: on the stack for up to kSmall events (the usual case), else on the heap, once.
  // g0, g1: the step's ends; (ta_s, ga_s): each event's last sample with g != 0; gs: the current
  // one; clear: 1 for an event that cannot cross in this step (conservative advancement).
  static constexpr std::size_t kSmall = 16;
  std::array<double, 6 * kSmall> g_small_;
  std::vector<double> g_heap_;
  double *g0_, *g1_, *ga_s_, *ta_s_, *gs_, *clear_;

  const int samples_max_;
  // h_bound at the start state of the current step (adaptive methods with a bound): the interior
  // samples of a step are the fewest that keep them at most h_bound / (event_samples + 1) apart.
  double hb_start_ = std::numeric_limits<double>::infinity();
  // Conservative advancement (IntegrateOptions::event_samples): possible when every event bounds
  // its change over a step. near_: the last certified step had an event that could cross (or none
  // was certified yet), so h_bound bounds the steps.
  const bool can_certify_;
  bool near_ = true;
  Vec excursion_;
  bool cheap_detection_ = true;  // false once the stepper turned out to have no cheap interpolant
};

Integration::Integration(const System& f, Stepper& stepper, double t0, Vec& y, double t_end,
                         std::span<const Event> events, const StepObserver& observe, const PostStep& post_step,
                         const IntegrateOptions& opt)
    : f_(f), stepper_(stepper), y_(y), events_(events), observe_(observe), post_step_(post_step), opt_(opt),
      t0_(t0), t_end_(t_end), dir_(t_end > t0 ? 1.0 : -1.0), m_(events.size()), y_new_(y.size()),
      y_ev_(y.size()), t_(t0), g_heap_(m_ > kSmall ? 6 * m_ : 0),
      samples_max_(std::max(0, opt.event_samples)),
      can_certify_(samples_max_ > 0 && opt.h_bound && m_ > 0 &&
                   std::all_of(events.begin(), events.end(), [](const Event& e) { return bool(e.change_bound); })),
      excursion_(can_certify_ ? y.size() : 0) {
  res_.t = t0;
  g0_ = m_ > kSmall ? g_heap_.data() : g_small_.data();
  g1_ = g0_ + m_;
  ga_s_ = g1_ + m_;
  ta_s_ = ga_s_ + m_;
  gs_ = ta_s_ + m_;
  clear_ = gs_ + m_;
  for (std::size_t i = 0; i < m_; ++i) g0_[i] = events_[i].g(t0, y_);
}

// ---- stepping -----------------------------------------------------------------------------

// PI step-size control (Gustafsson; the constants above): the factor on |h| after an accepted
// step of error err, or after a rejected one.
struct PiControl {
  double alpha;  // 1/p - 0.75 beta
  double err_old = kErrOldMin;
  bool rejected_last = false;

  double accepted(double err, double h_abs) {
    double fac = kSafety * std::pow(err, -alpha) * std::pow(err_old, kBeta);
    fac = std::clamp(fac, kFacMin, rejected_last ? 1.0 : kFacMax);  // err = 0: facmax
    err_old = std::max(err, kErrOldMin);
    rejected_last = false;
    return h_abs * fac;
  }
  double rejected(double err, double h_abs) {
    rejected_last = true;
    return h_abs * std::max(kFacMin, kSafety * std::pow(err, -alpha));
  }
};

// Fixed step on the grid t0 + k h (no drift from repeated additions); the last step is
// shortened (or stretched by < 1e-9 h, to avoid a sliver step) to land on t_end.
IntegrateResult Integration::fixed_steps() {
  const double hf = opt_.h_init > 0.0 ? opt_.h_init : opt_.h_fixed;
  if (!(hf > 0.0)) throw std::invalid_argument("integrate: fixed step must be > 0");
  res_.h_next = hf;
  for (long k = 1;; ++k) {
    if (res_.steps >= opt_.max_steps) {
      res_.status = IntegrateStatus::MaxSteps;
      return res_;
    }
    double t1 = t0_ + dir_ * static_cast<double>(k) * hf;
    const bool last = dir_ * (t_end_ - t1) <= 1e-9 * hf;
    if (last) t1 = t_end_;
    if (t1 == t_) {
      res_.status = IntegrateStatus::StepUnderflow;
      return res_;
    }
    const double hs = t1 - t_;
    if (opt_.h_bound && samples_max_ > 0 && m_ > 0) hb_start_ = opt_.h_bound(t_, y_);  // for the samples only
    stepper_.attempt(f_, t_, y_, hs, y_new_, opt_.tol);
    if (!y_new_.allFinite()) {
      res_.status = IntegrateStatus::NonFinite;  // y, res.t: the last good state
      return res_;
    }
    stepper_.accept(f_);
    ++res_.steps;
    if (after_step(t1, hs)) return res_;
    t_ = t1;
    if (last) {
      res_.status = IntegrateStatus::Reached;
      return res_;
    }
  }
}

// The first adaptive step: h_init, or the starting-step estimate; within h_max and h_bound.
double Integration::first_step() {
  double h = opt_.h_init > 0.0 ? opt_.h_init : initial_step(f_, stepper_, t0_, y_, dir_, opt_);
  h = std::min(h, opt_.h_max);
  if (opt_.h_bound) {
    hb_start_ = opt_.h_bound(t0_, y_);
    h = std::min(h, hb_start_);
  }
  return h;
}

IntegrateResult Integration::adaptive_steps() {
  PiControl pi{1.0 / stepper_.order() - 0.75 * kBeta};
  double h = first_step();
  bool nonfinite_last = false;
  while (true) {
    if (res_.steps + res_.rejected >= opt_.max_steps) {
      res_.status = IntegrateStatus::MaxSteps;
      break;
    }
    if (h < opt_.h_min) {
      res_.status = nonfinite_last ? IntegrateStatus::NonFinite : IntegrateStatus::StepUnderflow;
      break;
    }
    // Land exactly on t_end, stretching the step by up to 1% rather than leaving a sliver.
    double hs = dir_ * h;
    const bool last = dir_ * (t_ + 1.01 * hs - t_end_) >= 0.0;
    if (last) hs = t_end_ - t_;
    const double t1 = last ? t_end_ : t_ + hs;
    if (t1 == t_) {  // h below the resolution of t: no progress possible
      res_.status = IntegrateStatus::StepUnderflow;
      break;
    }
    const double err = stepper_.attempt(f_, t_, y_, hs, y_new_, opt_.tol);
    if (!std::isfinite(err) || !y_new_.allFinite()) {
      // Treated as a failed step (an overflow from a too-large step can be cured by a
      // smaller one); if h underflows this way the status is NonFinite.
      ++res_.rejected;
      pi.rejected_last = true;
      nonfinite_last = true;
      h = std::abs(hs) * kFacMin;
      continue;
    }
    nonfinite_last = false;
    if (err > 1.0) {
      ++res_.rejected;
      h = pi.rejected(err, std::abs(hs));
      continue;
    }
    stepper_.accept(f_);
    ++res_.steps;
    double h_next = pi.accepted(err, std::abs(hs));
    if (last && std::abs(hs) < h) h_next = std::max(h_next, h);  // cut short only by t_end
    h_next = std::min(h_next, opt_.h_max);
    const double hb_end = opt_.h_bound ? opt_.h_bound(t1, y_new_) : hb_start_;
    res_.h_next = std::min(h_next, hb_end);  // a continuation starts near the guards
    if (after_step(t1, hs)) return res_;
    hb_start_ = hb_end;
    t_ = t1;
    h = near_ ? res_.h_next : h_next;  // far from every guard (certified): h_bound does not bound it
    if (last) {
      res_.status = IntegrateStatus::Reached;
      break;
    }
  }
  res_.t = t_;
  if (res_.h_next == 0.0) res_.h_next = h;
  return res_;
}

// Events, observer and post-step hook after an accepted step [t_, t1] of size hs whose end
// state is y_new_. Returns true when the integration ends here (res_ filled).
bool Integration::after_step(double t1, double hs) {
  if (m_ > 0) {
    int n = interior_samples(hs);
    for (std::size_t i = 0; i < m_; ++i) g1_[i] = events_[i].g(t1, y_new_);
    n = certify(t1, n);
    open_brackets(hs);
    // The samples first on the stepper's cheap interpolant, where it has one (DOP853's cubic
    // Hermite through both ends, no extra stage): if no event changes sign between them there,
    // the step's end alone is checked. Only a step where one does samples again on the dense
    // output and locates the crossing there.
    if (n > 0 && cheap_detection_ && !cheap_sign_change(t1, hs, n)) n = 0;
    double t_best = t1;
    const int best = earliest_root(t1, hs, n, t_best);
    if (best >= 0) return stop_at_event(best, t_best, t1, hs);
  }
  return finish_step(t1, hs);
}

// ---- guard sampling -------------------------------------------------------------------------

// Interior samples: |hs| (k + 1) / hb_start spacings of the bound's, less the step end; at most
// k while h_bound bounds the steps, as many as the spacing asks otherwise.
int Integration::interior_samples(double hs) const {
  int n = samples_max_;
  if (n > 0 && std::isfinite(hb_start_) && hb_start_ > 0.0)
    n = static_cast<int>(std::clamp(std::ceil(std::abs(hs) * (samples_max_ + 1) / hb_start_) - 1.0, 0.0,
                                    near_ ? double(samples_max_) : kMaxCertifiedSamples));
  return n;
}

// A step that needs samples (n of them) first asks which events can cross: |g0| above the bound
// on its change over the step keeps g0's sign on the whole interpolant (y_ still holds the
// start). Those are marked clear; when all are, the step's end alone is checked (0 samples).
int Integration::certify(double t1, int n) {
  std::fill(clear_, clear_ + m_, 0.0);
  if (!can_certify_ || !(n > 0) || !stepper_.dense_excursion(f_, excursion_)) return n;
  std::size_t n_clear = 0;
  for (std::size_t i = 0; i < m_; ++i)
    if (std::abs(g0_[i]) > events_[i].change_bound(t_, t1, y_, excursion_)) {
      clear_[i] = 1.0;
      ++n_clear;
    }
  near_ = n_clear < m_;
  return near_ ? n : 0;
}

// Whether any event changes sign between the n interior samples of the step [t_, t1] (size hs)
// and its ends on the stepper's cheap interpolant, each from its bracket start (ta_s, ga_s);
// the events certified not to cross (clear) are skipped. Uses gs as scratch.
bool Integration::cheap_sign_change(double t1, double hs, int n_samples) {
  std::copy(ga_s_, ga_s_ + m_, gs_);
  for (int j = 1; j <= n_samples + 1; ++j) {
    const double ts = j == n_samples + 1 ? t1 : t_ + hs * (static_cast<double>(j) / (n_samples + 1));
    if (j <= n_samples && !stepper_.cheap_interpolant(f_, (ts - t_) / hs, y_ev_)) {
      cheap_detection_ = false;  // the method has none: never ask again
      return true;
    }
    for (std::size_t i = 0; i < m_; ++i) {
      if (clear_[i] != 0.0 || std::isnan(gs_[i]) || dir_ * (ts - ta_s_[i]) <= 0.0) continue;
      const double g = j == n_samples + 1 ? g1_[i] : events_[i].g(ts, y_ev_);
      if (crosses(gs_[i], g, events_[i].direction)) return true;
      if (g != 0.0) gs_[i] = g;
    }
  }
  return false;
}

// ---- event location -------------------------------------------------------------------------

// Each event's bracket starts at (ta_s, ga_s): the step start, or the probe past a zero start
// (NaN: the event cannot fire in this step).
void Integration::open_brackets(double hs) {
  for (std::size_t i = 0; i < m_; ++i) {
    ta_s_[i] = t_;
    ga_s_[i] = g0_[i];
    if (g0_[i] == 0.0) {
      const double delta = std::min(0.5 * std::abs(hs), std::max(opt_.event_tol, 1e-6 * std::abs(hs)));
      ta_s_[i] = t_ + dir_ * delta;
      ga_s_[i] = g_at(i, ta_s_[i], hs);
      if (ga_s_[i] == 0.0) ga_s_[i] = std::numeric_limits<double>::quiet_NaN();
    }
  }
}

// The sub-intervals between consecutive samples (n interior ones, then the step's end), in time
// order; the first one in which any event crosses holds the earliest root seen at this sampling.
// Returns the event that fires first (-1: none) and its located time in t_best.
int Integration::earliest_root(double t1, double hs, int n, double& t_best) {
  int best = -1;
  for (int j = 1; j <= n + 1 && best < 0; ++j) {
    const double ts = j == n + 1 ? t1 : t_ + hs * (static_cast<double>(j) / (n + 1));
    if (j == n + 1) {
      std::copy(g1_, g1_ + m_, gs_);
    } else {
      stepper_.dense(f_, (ts - t_) / hs, y_ev_);
      for (std::size_t i = 0; i < m_; ++i) gs_[i] = clear_[i] != 0.0 ? ga_s_[i] : events_[i].g(ts, y_ev_);
    }
    for (std::size_t i = 0; i < m_; ++i) bracket_root(i, ts, hs, best, t_best);
    // The next bracket starts at this sample, unless g is exactly 0 there (its sign is kept).
    for (std::size_t i = 0; i < m_; ++i)
      if (!std::isnan(ga_s_[i]) && dir_ * (ts - ta_s_[i]) > 0.0 && gs_[i] != 0.0) {
        ta_s_[i] = ts;
        ga_s_[i] = gs_[i];
      }
  }
  return best;
}

// Event i over its bracket [ta_s, ts]: if it crosses (before t_best, when an earlier root is
// already known), its root located; kept in (best, t_best) when it is the earliest.
void Integration::bracket_root(std::size_t i, double ts, double hs, int& best, double& t_best) {
  const double ta = ta_s_[i], ga = ga_s_[i];
  if (std::isnan(ga) || dir_ * (ts - ta) <= 0.0) return;  // no sign, or before the probe
  if (!crosses(ga, gs_[i], events_[i].direction)) return;
  double tb = ts, gb = gs_[i];
  if (best >= 0) {
    // An earlier root is known: this event matters only if it crosses before t_best.
    if (dir_ * (t_best - ta) <= 0.0) return;
    const double gbest = g_at(i, t_best, hs);
    if (!crosses(ga, gbest, events_[i].direction)) return;
    tb = t_best;
    gb = gbest;
  }
  const double root = locate_root([&](double tq) { return g_at(i, tq, hs); }, ta, ga, tb, gb, opt_.event_tol);
  if (best < 0 || dir_ * (root - t_best) < 0.0) {
    best = static_cast<int>(i);
    t_best = root;
  }
}

// The step cut at the located root: y_ at t_best, the observer shown the truncated step (its
// return value cannot stop more).
bool Integration::stop_at_event(int best, double t_best, double t1, double hs) {
  if (t_best == t1) {
    y_ = y_new_;
  } else {
    stepper_.dense(f_, (t_best - t_) / hs, y_ev_);
    y_ = y_ev_;
  }
  res_.t = t_best;
  res_.status = IntegrateStatus::Event;
  res_.event_index = best;
  if (observe_) observe_(StepView(stepper_, f_, t_, t_best, hs, &y_));
  return true;
}

// ---- post-step actions ----------------------------------------------------------------------

// The observer runs before the projection; a stop still completes the step (post-step hook
// included) so that the returned state is a regular one. A projection resets the stepper and
// the next step's g0; otherwise g0 is this step's g1.
bool Integration::finish_step(double t1, double hs) {
  const bool stop = observe_ && !observe_(StepView(stepper_, f_, t_, t1, hs, &y_new_));
  y_ = y_new_;
  res_.t = t1;
  if (post_step_ && post_step_(t1, y_)) {
    stepper_.reset();
    for (std::size_t i = 0; i < m_; ++i) g0_[i] = events_[i].g(t1, y_);
  } else {
    std::swap(g0_, g1_);
  }
  if (stop) {
    res_.status = IntegrateStatus::Stopped;
    return true;
  }
  return false;
}

}  // namespace

IntegrateResult integrate(const System& f, Stepper& stepper, double t0, Vec& y, double t_end,
                          std::span<const Event> events, const StepObserver& observe,
                          const PostStep& post_step, const IntegrateOptions& opt) {
  if (!std::isfinite(t0) || !std::isfinite(t_end))
    throw std::invalid_argument("integrate: non-finite t0 or t_end");
  if (y.size() == 0) throw std::invalid_argument("integrate: empty state");

  IntegrateResult res;
  res.t = t0;
  // A new integration may come with a different f (mode switch): no stage is reused.
  stepper.reset();
  if (!y.allFinite()) {
    res.status = IntegrateStatus::NonFinite;
    return res;
  }
  if (t_end == t0) {
    res.h_next = opt.h_init > 0.0 ? opt.h_init : (stepper.adaptive() ? 0.0 : opt.h_fixed);
    return res;
  }
  return Integration(f, stepper, t0, y, t_end, events, observe, post_step, opt).run();
}

}  // namespace ajx::numerics
