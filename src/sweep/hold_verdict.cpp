#include "sweep/hold_verdict.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <fmt/format.h>
#include <optional>
#include <stdexcept>

#include "physics/drive.hpp"
#include "sweep/refine.hpp"

namespace ajx::sweep {

double drag_time(const physics::Parameters& p) {
  return p.drag > 0.0 ? std::max(p.bead_mass, p.ball_mass) / p.drag : std::numeric_limits<double>::infinity();
}

double sustain_tolerance(const physics::Parameters& p, double hold) {
  // An orbit with (dE/dt)/P_drag = r e-folds in no less than m_min/(2 c_D |r|): longer than T.
  return p.drag > 0.0 ? std::min(p.bead_mass, p.ball_mass) / (2.0 * p.drag * hold)
                      : std::numeric_limits<double>::infinity();
}

ChainSetup held_chain(const ChainSetup& chain, double t_cut, int n_windows, double window) {
  if (n_windows < 1 || !(window > 0.0)) throw std::invalid_argument("hold: needs at least one window of positive length");
  if (!(t_cut >= 0.0) || t_cut > chain.protocol.duration)
    throw std::invalid_argument(fmt::format("hold: t = {} s is outside the chain's schedule [0, {}] s", t_cut,
                                            chain.protocol.duration));
  double phi = 0.0, omega = 0.0, omega_dot = 0.0;
  if (!chain.protocol.schedule.empty())
    chain.motor().phase(t_cut, phi, omega, omega_dot);
  ChainSetup out = chain;
  out.protocol.schedule = schedule_until(chain.protocol.schedule, t_cut, omega);
  const double hold = n_windows * window;
  out.protocol.schedule.push_back({omega, omega, hold});
  out.protocol.windows.clear();
  for (int k = 0; k < n_windows; ++k)
    out.protocol.windows.push_back({t_cut + k * window, t_cut + (k + 1) * window, omega, omega, 0, 0});
  out.protocol.windows.back().t_end = t_cut + hold;
  out.protocol.duration = t_cut + hold;
  return out;
}

HoldSide hold_side(const ChainSetup& chain, double t_cut, double hold, double window, const physics::State& start,
                   OrbitClass reference, const ClassifierSettings& settings) {
  if (start.t > t_cut) throw std::invalid_argument("hold: the start state is later than the hold");
  // At least four windows, so that the measured half has two to estimate the scatter from.
  const int n = std::max(4, int(std::ceil(hold / window - 1e-9)));
  const ChainSetup held = held_chain(chain, t_cut, n, window);
  const TaskOutput out = run_task(held, TaskSpan{start.t, held.protocol.duration, 0, n}, start);
  const std::vector<OrbitClassification> classes = classify_windows(held, out, settings);

  HoldSide s;
  s.omega = held.protocol.windows.front().omega_begin;
  s.t_cut = t_cut;
  s.hold = n * window;
  s.reference = reference;
  s.ok = out.ok;
  s.failure = out.failure;
  s.simulated = out.simulated;
  for (std::size_t k = 0; k < classes.size(); ++k) {
    s.classes.push_back(classes[k].cls);
    s.powers.push_back(window_powers(out.windows[k]));
    if (std::isnan(s.first_change) && classes[k].cls != reference)
      s.first_change = held.protocol.windows[k].t_begin - t_cut;
  }
  s.final_class = s.classes.empty() ? OrbitClass::Failed : s.classes.back();
  if (!s.ok || s.final_class == OrbitClass::Failed) return s;

  // The measured stretch: the last half of the windows, from the first one's first sample to
  // the last one's last sample (the ledgers are cumulative, so gaps between windows count).
  s.measured = n / 2;
  const WindowRecord &a = out.windows[std::size_t(n - s.measured)], &b = out.windows.back();
  const double dt = b.last.t - a.first.t;
  s.mean = {(b.last.motor_work - a.first.motor_work) / dt, (b.last.drag_loss - a.first.drag_loss) / dt,
            (b.last.other_loss - a.first.other_loss) / dt, (b.last.energy - a.first.energy) / dt,
            (b.last.string_work - a.first.string_work) / dt, (b.last.clutch_loss - a.first.clutch_loss) / dt};
  const double r_tol = sustain_tolerance(chain.model.p, s.hold);
  if (!(chain.model.p.drag > 0.0)) {
    // Without drag nothing decays: the classes alone decide.
    s.tolerance = r_tol;
    s.sustained = s.determined = true;
    return s;
  }
  if (s.mean.drag > 0.0) s.ratio = s.mean.energy_rate / s.mean.drag;
  // Standard error of the per-window ratios r_k = (dE/dt)_k / P_drag,k.
  std::vector<double> r;
  for (std::size_t k = std::size_t(n - s.measured); k < s.powers.size(); ++k)
    if (s.powers[k].drag > 0.0) r.push_back(s.powers[k].energy_rate / s.powers[k].drag);
  s.ratio_error = 0.0;
  if (r.size() >= 2) {
    double mean = 0.0, var = 0.0;
    for (double x : r) mean += x / double(r.size());
    for (double x : r) var += (x - mean) * (x - mean) / double(r.size() - 1);
    s.ratio_error = std::sqrt(var / double(r.size()));
  }
  s.tolerance = std::max(r_tol, 2.0 * s.ratio_error);
  s.determined = 2.0 * s.ratio_error < 0.5;
  // Balls at rest (P_drag = 0) are sustained only if E does not change either.
  s.sustained = std::abs(s.mean.energy_rate) <= s.tolerance * s.mean.drag;
  return s;
}

std::string_view to_string(Verdict v) {
  switch (v) {
    case Verdict::Bifurcation: return "bifurcation";
    case Verdict::Excursion: return "excursion";
    case Verdict::TimeLimited: return "time-limited transient";
    case Verdict::Undecided: return "undecided";
  }
  return "?";
}

Judgement judge(const HoldSide& pre, const HoldSide& post) {
  constexpr double pi = std::numbers::pi;
  const auto name = [](OrbitClass c) { return std::string(to_string(c)); };
  for (const HoldSide* s : {&pre, &post})
    if (!s->ok || s->final_class == OrbitClass::Failed)
      return {Verdict::Undecided, fmt::format("the hold at {:.3f}pi failed: {}", s->omega / pi, s->failure)};
  if (pre.final_class == pre.reference && !pre.determined)
    return {Verdict::Undecided,
            fmt::format("held at {:.3f}pi the energy account of the {} orbit scatters too much between windows "
                        "(r = {:+.2f} +- {:.2f}) to tell sustained from decaying: hold longer",
                        pre.omega / pi, name(pre.reference), pre.ratio, pre.ratio_error)};
  if (pre.final_class != pre.reference)
    return {Verdict::TimeLimited,
            fmt::format("held at {:.3f}pi the {} orbit becomes {} (first change after {:.0f} s)", pre.omega / pi,
                        name(pre.reference), name(pre.final_class), pre.first_change)};
  if (!pre.sustained)
    return {Verdict::TimeLimited,
            fmt::format("held at {:.3f}pi the {} orbit is not sustained: dE/dt = {:+.3f} P_drag (|r| > {:.3f})",
                        pre.omega / pi, name(pre.reference), pre.ratio, pre.tolerance)};
  if (post.final_class == pre.reference) {
    // Did the held orbit after the change show another class first, and when was it back?
    double back = HoldSide::nan;
    std::optional<OrbitClass> away;
    for (std::size_t k = 0; k < post.classes.size(); ++k) {
      if (!away && post.classes[k] != pre.reference) away = post.classes[k];
      if (std::isnan(back) && away && post.classes[k] == pre.reference)
        back = double(k) * post.hold / double(post.classes.size());
    }
    const std::string after =
        away ? fmt::format("is {} and back to {} after {:.0f} s", name(*away), name(pre.reference), back)
             : fmt::format("is back to {} when the hold starts (the sweep saw {} there)", name(pre.reference),
                           name(post.reference));
    return {Verdict::Excursion,
            fmt::format("held at {:.3f}pi the {} orbit is sustained (dE/dt = {:+.1e} P_drag); at {:.3f}pi the orbit "
                        "{} (P_drag {:.2e} W, before {:.2e} W): the change does not persist",
                        pre.omega / pi, name(pre.reference), pre.ratio, post.omega / pi, after, post.mean.drag,
                        pre.mean.drag)};
  }
  return {Verdict::Bifurcation,
          fmt::format("held at {:.3f}pi the {} orbit is sustained (dE/dt = {:+.1e} P_drag); at {:.3f}pi it ends {}",
                      pre.omega / pi, name(pre.reference), pre.ratio, post.omega / pi, name(post.final_class))};
}

}  // namespace ajx::sweep
