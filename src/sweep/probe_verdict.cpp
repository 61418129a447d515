#include "sweep/probe_verdict.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

namespace ajx::sweep {

ProbeVerdict::ProbeVerdict(Threshold threshold, const physics::Model& model, const ClassifierSettings& settings,
                           double t_hold)
    : may_fall_(threshold == Threshold::Fall || threshold == Threshold::Omega1),
      may_lock_(may_fall_),
      l_(model.p.string_length),
      d_(model.p.contact_distance),
      on_ball_tol_(settings.on_ball_tol),
      t_hold_(t_hold) {}

void ProbeVerdict::add(const sim::Sample& s) {
  // The classifier's on-ball test (sweep/orbit_classifier.cpp): the mode, or L2 = l − L1 within tol·d of d.
  if (s.contact.mode == physics::Mode::BottomStop || std::abs(l_ - s.dyn.g.L1 - d_) <= on_ball_tol_ * d_) {
    if (std::isnan(on_since_)) on_since_ = s.t;
    last_on_ = s.t;
  } else {
    on_since_ = std::numeric_limits<double>::quiet_NaN();
  }
  stuck_ = stuck_ && s.contact.mode == physics::Mode::Stuck && !s.contact.tie.slip;
  // x = Rz(−ψ)(r1, r2), ψ the top's azimuth.
  const double c = std::cos(s.top.phi), sn = std::sin(s.top.phi);
  Vec6 x;
  for (int b = 0; b < 2; ++b) {
    const int i = b == 0 ? physics::idx::r1 : physics::idx::r2;
    x(3 * b) = c * s.y(i) + sn * s.y(i + 1);
    x(3 * b + 1) = -sn * s.y(i) + c * s.y(i + 1);
    x(3 * b + 2) = s.y(i + 2);
  }
  if (n_++ == 0) {
    t_first_ = s.t;
    lo_ = hi_ = x;
  } else {
    lo_ = lo_.cwiseMin(x);
    hi_ = hi_.cwiseMax(x);
  }
}

std::optional<OrbitClassification> ProbeVerdict::close_block(double t_begin, double t_end) {
  std::optional<OrbitClassification> out;
  const bool whole = t_end - t_begin >= kBlock * (1.0 - 1e-9) && n_ > 0;
  if (may_fall_ && !std::isnan(on_since_) && last_on_ - on_since_ >= kBlock - 1e-6) {
    out.emplace();
    out->cls = OrbitClass::Fallen;
    out->confidence = 1.0;
    out->reason = fmt::format("decided at t = {:.1f} s: the bead on the bottom ball at every sample since {:.1f} s",
                              t_end, on_since_);
  }
  const bool held = whole && may_lock_ && stuck_ && t_first_ >= t_hold_;
  if (!out && held) {
    const Vec6 centre = 0.5 * (lo_ + hi_);
    const double spread = 0.5 * (hi_ - lo_).norm();  // a_j
    if (stuck_blocks_ >= 1) {
      const double shift = (centre - centre_prev_).norm();  // s_j
      if (stuck_blocks_ >= 2 && spread <= spread_prev_) {
        const double q = shift_prev_ > 0.0 ? shift / shift_prev_ : (shift > 0.0 ? 1.0 : 0.0);
        const double D = q < 1.0 ? spread + shift * q / (1.0 - q) : std::numeric_limits<double>::infinity();
        if (D <= kLockTolerance * l_) {
          out.emplace();
          out->cls = OrbitClass::LockedCircular;
          out->confidence = 1.0;
          out->reason = fmt::format("decided at t = {:.1f} s: stuck, held and converging to a fixed point of the "
                                    "turning frame, {:.2g} m from it", t_end, D);
        }
      }
      shift_prev_ = shift;
    }
    spread_prev_ = spread;
    centre_prev_ = centre;
    ++stuck_blocks_;
  } else if (!held) {
    stuck_blocks_ = 0;
  }
  n_ = 0;
  stuck_ = true;
  return out;
}

double ProbeVerdict::fall_due() const {
  return may_fall_ && !std::isnan(on_since_) ? on_since_ + kBlock + 0.5 * kSampleStep
                                             : std::numeric_limits<double>::infinity();
}

ProbePath run_probe_path(const ChainSetup& chain, physics::State start, Threshold threshold,
                         const ClassifierSettings& settings, const sim::SampleObserver& on_sample,
                         const std::function<void(double, double, long)>& on_block) {
  const Window& win = chain.protocol.windows.front();
  const TaskSpan span{start.t, win.t_end, 0, 1};
  ProbeVerdict verdict(threshold, chain.model, settings, win.t_settle);
  ProbePath p;
  if (!verdict.active()) {
    p.out = run_task(chain, span, std::move(start));
    return p;
  }
  const physics::MotorSchedule schedule = chain.motor();
  sim::RunOptions run = chain.run;
  run.run_statistics = false;
  sim::Simulation simulation(chain.model, schedule, run);
  const auto watch = [&](const sim::Sample& s) {
    verdict.add(s);
    if (on_sample) on_sample(s);
  };
  physics::State s = std::move(start);
  const double t0 = s.t;
  // Blocks on the grid t0 + k B up to the window's start, or up to B after a landing (then back
  // on the grid); the window itself in one run.
  for (int k = 1; s.t < win.t_begin;) {
    while (t0 + k * ProbeVerdict::kBlock <= s.t + 1e-9) ++k;
    const double t_begin = s.t;
    const double t_end = std::min({t0 + k * ProbeVerdict::kBlock, verdict.fall_due(), win.t_begin});
    const sim::RunSummary r = simulation.run(s, t_end, ProbeVerdict::kSampleStep, watch, 0.0);
    add_counts(p.out, r);
    if (on_block) on_block(t_begin, t_end, r.steps);
    if (!r.ok()) {
      p.out.ok = false;
      p.out.failure = r.failure;
      p.out.final_state = s;
      p.out.simulated = s.t - t0;
      p.out.windows.push_back({0, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}});
      return p;
    }
    if (auto c = verdict.close_block(t_begin, t_end)) {
      p.decided = std::move(c);
      p.decided_at = s.t;
      p.out.final_state = s;
      p.out.simulated = s.t - t0;
      p.out.windows.push_back({0, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}});
      return p;
    }
  }
  TaskOutput w = run_task(chain, TaskSpan{s.t, win.t_end, 0, 1}, s);
  for (auto [into, from] : {std::pair{&w.steps, p.out.steps}, {&w.rhs_evals, p.out.rhs_evals},
                            {&w.impacts, p.out.impacts}, {&w.sticks, p.out.sticks}, {&w.slack_phases, p.out.slack_phases}})
    *into += from;
  w.skipped += p.out.skipped;
  w.simulated += s.t - t0;
  p.out = std::move(w);
  return p;
}

}  // namespace ajx::sweep
