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

}  // namespace

// Long (about 250 lines) for a reason: the one step loop of every run, whose event brackets (on
// the stack), dense output and counters are shared by its step-acceptance, event-location and
// observer parts; split into functions they would pass a dozen references through the hot path.
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
  const double dir = t_end > t0 ? 1.0 : -1.0;
  const auto n = y.size();
  Vec y_new(n), y_ev(n);

  // Event bookkeeping: g at the start of the current step (g0) and at its end (g1).
  // Rule for g0 == 0 exactly (a start on the surface, or a restart at a located root): the
  // zero itself is never a crossing. The sign g takes just after the start is probed on the
  // dense output at ta = t + dir * delta (delta = max(event_tol, 1e-6 |h|), at most |h|/2);
  // only a sign change between ta and the step end counts. If g is still exactly 0 at ta the
  // event cannot fire in this step. A step end where g = 0 exactly after a nonzero start is
  // a root (at the step end). Two crossings between consecutive guard samples (the step's ends
  // and its interior samples, IntegrateOptions::event_samples) cancel and are not seen.
  const std::size_t m = events.size();
  // g values: on the stack for up to kSmall events (the usual case), else on the heap, once.
  // g0, g1: the step's ends; (ta_s, ga_s): each event's last sample with g != 0; gs: the current
  // one; clear: 1 for an event that cannot cross in this step (conservative advancement).
  constexpr std::size_t kSmall = 16;
  std::array<double, 6 * kSmall> g_small;
  std::vector<double> g_heap(m > kSmall ? 6 * m : 0);
  double* g0 = m > kSmall ? g_heap.data() : g_small.data();
  double* g1 = g0 + m;
  double* ga_s = g1 + m;
  double* ta_s = ga_s + m;
  double* gs = ta_s + m;
  double* clear = gs + m;
  for (std::size_t i = 0; i < m; ++i) g0[i] = events[i].g(t0, y);

  double t = t0;
  const int samples_max = std::max(0, opt.event_samples);
  // h_bound at the start state of the current step (adaptive methods with a bound): the interior
  // samples of a step are the fewest that keep them at most h_bound / (event_samples + 1) apart.
  double hb_start = std::numeric_limits<double>::infinity();
  // Conservative advancement (IntegrateOptions::event_samples): possible when every event bounds
  // its change over a step. near: the last certified step had an event that could cross (or none
  // was certified yet), so h_bound bounds the steps.
  const bool can_certify = samples_max > 0 && opt.h_bound && m > 0 &&
                           std::all_of(events.begin(), events.end(), [](const Event& e) { return bool(e.change_bound); });
  bool near = true;
  Vec excursion(can_certify ? n : 0);

  // Whether any event changes sign between the n interior samples of the step [t, t1] (size hs)
  // and its ends on the stepper's cheap interpolant, each from its bracket start (ta_s, ga_s);
  // the events certified not to cross (clear) are skipped. Uses gs as scratch.
  bool cheap_detection = true;
  auto sign_change_seen = [&](double t_step, double t1, double hs, int n_samples) {
    std::copy(ga_s, ga_s + m, gs);
    for (int j = 1; j <= n_samples + 1; ++j) {
      const double ts = j == n_samples + 1 ? t1 : t_step + hs * (static_cast<double>(j) / (n_samples + 1));
      if (j <= n_samples && !stepper.cheap_interpolant(f, (ts - t_step) / hs, y_ev)) {
        cheap_detection = false;  // the method has none: never ask again
        return true;
      }
      for (std::size_t i = 0; i < m; ++i) {
        if (clear[i] != 0.0 || std::isnan(gs[i]) || dir * (ts - ta_s[i]) <= 0.0) continue;
        const double g = j == n_samples + 1 ? g1[i] : events[i].g(ts, y_ev);
        if (crosses(gs[i], g, events[i].direction)) return true;
        if (g != 0.0) gs[i] = g;
      }
    }
    return false;
  };

  // Events, observer and post-step hook after an accepted step [t, t1] of size hs whose end
  // state is y_new. Returns true when the integration ends here (res filled).
  auto after_step = [&](double t1, double hs) -> bool {
    if (m > 0) {
      auto g_at = [&](std::size_t i, double tq) {
        stepper.dense(f, (tq - t) / hs, y_ev);
        return events[i].g(tq, y_ev);
      };
      // Interior samples: |hs| (k + 1) / hb_start spacings of the bound's, less the step end; at
      // most k while h_bound bounds the steps, as many as the spacing asks otherwise.
      int n = samples_max;
      if (n > 0 && std::isfinite(hb_start) && hb_start > 0.0)
        n = static_cast<int>(std::clamp(std::ceil(std::abs(hs) * (samples_max + 1) / hb_start) - 1.0, 0.0,
                                        near ? double(samples_max) : kMaxCertifiedSamples));
      for (std::size_t i = 0; i < m; ++i) g1[i] = events[i].g(t1, y_new);
      // A step that needs samples first asks which events can cross: |g0| above the bound on its
      // change over the step keeps g0's sign on the whole interpolant (y still holds the start).
      std::fill(clear, clear + m, 0.0);
      if (can_certify && n > 0 && stepper.dense_excursion(f, excursion)) {
        std::size_t n_clear = 0;
        for (std::size_t i = 0; i < m; ++i)
          if (std::abs(g0[i]) > events[i].change_bound(t, t1, y, excursion)) {
            clear[i] = 1.0;
            ++n_clear;
          }
        near = n_clear < m;
        if (!near) n = 0;  // no event can cross: the step's end alone
      }
      // Each event's bracket starts at (ta_s, ga_s): the step start, or the probe past a zero
      // start (NaN: the event cannot fire in this step).
      for (std::size_t i = 0; i < m; ++i) {
        ta_s[i] = t;
        ga_s[i] = g0[i];
        if (g0[i] == 0.0) {
          const double delta =
              std::min(0.5 * std::abs(hs), std::max(opt.event_tol, 1e-6 * std::abs(hs)));
          ta_s[i] = t + dir * delta;
          ga_s[i] = g_at(i, ta_s[i]);
          if (ga_s[i] == 0.0) ga_s[i] = std::numeric_limits<double>::quiet_NaN();
        }
      }
      // The samples first on the stepper's cheap interpolant, where it has one (DOP853's cubic
      // Hermite through both ends, no extra stage): if no event changes sign between them there,
      // the step's end alone is checked. Only a step where one does samples again on the dense
      // output and locates the crossing there.
      if (n > 0 && cheap_detection && !sign_change_seen(t, t1, hs, n)) n = 0;
      int best = -1;
      double t_best = t1;
      // Sub-intervals between consecutive samples, in time order; the first one in which any
      // event crosses holds the earliest root seen at this sampling.
      for (int j = 1; j <= n + 1 && best < 0; ++j) {
        const double ts = j == n + 1 ? t1 : t + hs * (static_cast<double>(j) / (n + 1));
        if (j == n + 1) {
          std::copy(g1, g1 + m, gs);
        } else {
          stepper.dense(f, (ts - t) / hs, y_ev);
          for (std::size_t i = 0; i < m; ++i) gs[i] = clear[i] != 0.0 ? ga_s[i] : events[i].g(ts, y_ev);
        }
        for (std::size_t i = 0; i < m; ++i) {
          const double ta = ta_s[i], ga = ga_s[i];
          if (std::isnan(ga) || dir * (ts - ta) <= 0.0) continue;  // no sign, or before the probe
          if (!crosses(ga, gs[i], events[i].direction)) continue;
          double tb = ts, gb = gs[i];
          if (best >= 0) {
            // An earlier root is known: this event matters only if it crosses before t_best.
            if (dir * (t_best - ta) <= 0.0) continue;
            const double gbest = g_at(i, t_best);
            if (!crosses(ga, gbest, events[i].direction)) continue;
            tb = t_best;
            gb = gbest;
          }
          const double root =
              locate_root([&](double tq) { return g_at(i, tq); }, ta, ga, tb, gb, opt.event_tol);
          if (best < 0 || dir * (root - t_best) < 0.0) {
            best = static_cast<int>(i);
            t_best = root;
          }
        }
        // The next bracket starts at this sample, unless g is exactly 0 there (its sign is kept).
        for (std::size_t i = 0; i < m; ++i)
          if (!std::isnan(ga_s[i]) && dir * (ts - ta_s[i]) > 0.0 && gs[i] != 0.0) {
            ta_s[i] = ts;
            ga_s[i] = gs[i];
          }
      }
      if (best >= 0) {
        if (t_best == t1) {
          y = y_new;
        } else {
          stepper.dense(f, (t_best - t) / hs, y_ev);
          y = y_ev;
        }
        res.t = t_best;
        res.status = IntegrateStatus::Event;
        res.event_index = best;
        // The observer sees the truncated step; its return value cannot stop more.
        if (observe) observe(StepView(stepper, f, t, t_best, hs, &y));
        return true;
      }
    }
    // The observer runs before the projection; a stop still completes the step (post-step
    // hook included) so that the returned state is a regular one.
    const bool stop = observe && !observe(StepView(stepper, f, t, t1, hs, &y_new));
    y = y_new;
    res.t = t1;
    if (post_step && post_step(t1, y)) {
      stepper.reset();
      for (std::size_t i = 0; i < m; ++i) g0[i] = events[i].g(t1, y);
    } else {
      std::swap(g0, g1);
    }
    if (stop) {
      res.status = IntegrateStatus::Stopped;
      return true;
    }
    return false;
  };

  if (!stepper.adaptive()) {
    // Fixed step on the grid t0 + k h (no drift from repeated additions); the last step is
    // shortened (or stretched by < 1e-9 h, to avoid a sliver step) to land on t_end.
    const double hf = opt.h_init > 0.0 ? opt.h_init : opt.h_fixed;
    if (!(hf > 0.0)) throw std::invalid_argument("integrate: fixed step must be > 0");
    res.h_next = hf;
    for (long k = 1;; ++k) {
      if (res.steps >= opt.max_steps) {
        res.status = IntegrateStatus::MaxSteps;
        return res;
      }
      double t1 = t0 + dir * static_cast<double>(k) * hf;
      const bool last = dir * (t_end - t1) <= 1e-9 * hf;
      if (last) t1 = t_end;
      if (t1 == t) {
        res.status = IntegrateStatus::StepUnderflow;
        return res;
      }
      const double hs = t1 - t;
      if (opt.h_bound && samples_max > 0 && m > 0) hb_start = opt.h_bound(t, y);  // for the samples only
      stepper.attempt(f, t, y, hs, y_new, opt.tol);
      if (!y_new.allFinite()) {
        res.status = IntegrateStatus::NonFinite;  // y, res.t: the last good state
        return res;
      }
      stepper.accept(f);
      ++res.steps;
      if (after_step(t1, hs)) return res;
      t = t1;
      if (last) {
        res.status = IntegrateStatus::Reached;
        return res;
      }
    }
  }

  const double alpha = 1.0 / stepper.order() - 0.75 * kBeta;
  double h = opt.h_init > 0.0 ? opt.h_init : initial_step(f, stepper, t0, y, dir, opt);
  h = std::min(h, opt.h_max);
  if (opt.h_bound) {
    hb_start = opt.h_bound(t0, y);
    h = std::min(h, hb_start);
  }
  double err_old = kErrOldMin;
  bool rejected_last = false;
  bool nonfinite_last = false;
  while (true) {
    if (res.steps + res.rejected >= opt.max_steps) {
      res.status = IntegrateStatus::MaxSteps;
      break;
    }
    if (h < opt.h_min) {
      res.status = nonfinite_last ? IntegrateStatus::NonFinite : IntegrateStatus::StepUnderflow;
      break;
    }
    // Land exactly on t_end, stretching the step by up to 1% rather than leaving a sliver.
    double hs = dir * h;
    bool last = false;
    if (dir * (t + 1.01 * hs - t_end) >= 0.0) {
      hs = t_end - t;
      last = true;
    }
    const double t1 = last ? t_end : t + hs;
    if (t1 == t) {  // h below the resolution of t: no progress possible
      res.status = IntegrateStatus::StepUnderflow;
      break;
    }
    const double err = stepper.attempt(f, t, y, hs, y_new, opt.tol);
    if (!std::isfinite(err) || !y_new.allFinite()) {
      // Treated as a failed step (an overflow from a too-large step can be cured by a
      // smaller one); if h underflows this way the status is NonFinite.
      ++res.rejected;
      rejected_last = true;
      nonfinite_last = true;
      h = std::abs(hs) * kFacMin;
      continue;
    }
    nonfinite_last = false;
    if (err <= 1.0) {
      stepper.accept(f);
      ++res.steps;
      double fac = kSafety * std::pow(err, -alpha) * std::pow(err_old, kBeta);
      fac = std::clamp(fac, kFacMin, rejected_last ? 1.0 : kFacMax);  // err = 0: facmax
      err_old = std::max(err, kErrOldMin);
      rejected_last = false;
      double h_next = std::abs(hs) * fac;
      if (last && std::abs(hs) < h) h_next = std::max(h_next, h);  // cut short only by t_end
      h_next = std::min(h_next, opt.h_max);
      const double hb_end = opt.h_bound ? opt.h_bound(t1, y_new) : hb_start;
      res.h_next = std::min(h_next, hb_end);  // a continuation starts near the guards
      if (after_step(t1, hs)) return res;
      hb_start = hb_end;
      t = t1;
      h = near ? res.h_next : h_next;  // far from every guard (certified): h_bound does not bound it
      if (last) {
        res.status = IntegrateStatus::Reached;
        break;
      }
    } else {
      ++res.rejected;
      rejected_last = true;
      h = std::abs(hs) * std::max(kFacMin, kSafety * std::pow(err, -alpha));
    }
  }
  res.t = t;
  if (res.h_next == 0.0) res.h_next = h;
  return res;
}

}  // namespace ajx::numerics
