#include "orbits/predicted_thresholds.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numbers>

#include "orbits/corotating_frame.hpp"
#include "orbits/orbit_families.hpp"

namespace ajx::orbits {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One branch through a start point as a single sequence in arclength: the backward half
// reversed, then the forward half. Events are kept with the index of the segment they lie in.
struct Walk {
  std::vector<const BranchPoint*> points;
  std::vector<std::pair<int, const BranchEvent*>> events;  // (segment i: between points i, i+1)
};

Walk join(const Branch& back, const Branch& fwd) {
  Walk w;
  const int nb = int(back.points.size());
  for (int i = nb - 1; i >= 0; --i) w.points.push_back(&back.points[i]);
  for (const auto& e : back.events) w.events.push_back({nb - 2 - e.after_point, &e});
  for (std::size_t i = 1; i < fwd.points.size(); ++i) w.points.push_back(&fwd.points[i]);
  for (const auto& e : fwd.events) w.events.push_back({nb - 1 + e.after_point, &e});
  return w;
}

// Held by friction, and (unless only the cone is asked for) linearly stable.
bool locked(const BranchPoint& p, bool need_stable) { return p.orbit.admissible && (!need_stable || p.unstable == 0); }

// Where a run of locked points ends inside segment i: the event there that breaks it.
std::pair<double, std::string> boundary(const Walk& w, int i, bool at_end, bool need_stable) {
  for (const auto& [seg, e] : w.events) {
    const bool stability = e->kind == EventKind::Hopf || e->kind == EventKind::StabilityLoss ||
                           e->kind == EventKind::StabilityGain;
    if (seg == i && e->kind != EventKind::BranchPoint && (need_stable || !stability))
      return {e->lambda, std::string(to_string(e->kind))};
  }
  const BranchPoint& p = *w.points[at_end ? i : i + 1];
  return {p.lambda, "range"};
}

void collect(const Walk& w, double s, bool need_stable, std::vector<LockedInterval>& out) {
  const int n = int(w.points.size());
  int i = 0;
  while (i < n) {
    if (!locked(*w.points[i], need_stable)) {
      ++i;
      continue;
    }
    int j = i;
    while (j + 1 < n && locked(*w.points[j + 1], need_stable)) ++j;
    LockedInterval iv;
    iv.s = s;
    iv.branch = w.points[i]->orbit.branch;
    auto a = i > 0 ? boundary(w, i - 1, false, need_stable)
                   : std::pair<double, std::string>{w.points[i]->lambda, "range"};
    auto b = j + 1 < n ? boundary(w, j, true, need_stable)
                       : std::pair<double, std::string>{w.points[j]->lambda, "range"};
    if (a.first > b.first) std::swap(a, b);
    iv.omega_lo = a.first;
    iv.ends_lo = a.second;
    iv.omega_hi = b.first;
    iv.ends_hi = b.second;
    out.push_back(iv);
    i = j + 1;
  }
}

// Whether X at ω lies on a branch already traced (interpolated between its points).
bool traced(const std::vector<Walk>& walks, double omega, const Vec9& X, double l) {
  for (const auto& w : walks)
    for (std::size_t i = 0; i + 1 < w.points.size(); ++i) {
      const BranchPoint &p = *w.points[i], &q = *w.points[i + 1];
      if ((p.lambda - omega) * (q.lambda - omega) > 0 || p.lambda == q.lambda) continue;
      const double t = (omega - p.lambda) / (q.lambda - p.lambda);
      const Vec9 Xi = (1 - t) * unknowns(p.orbit) + t * unknowns(q.orbit);
      if ((Xi - X).head<6>().norm() < 1e-3 * l) return true;
    }
  return false;
}

}  // namespace

namespace {
// Every branch of one closure through the orbits found at the start frequencies, continued in
// ω_m both ways; the intervals where it is admissible and stable.
void trace_family(const physics::Model& m, Closure closure, double s, const std::vector<double>& starts,
                  ContinuationOptions copt, std::vector<LockedInterval>& out,
                  std::vector<LockedInterval>* held_only = nullptr) {
  std::vector<Branch> halves;
  std::vector<Walk> walks;
  halves.reserve(2 * starts.size() * 8);
  for (double w0 : starts) {
    const OrbitProblem pb{m, w0, closure, s};
    for (const SteadyOrbit& o : orbits_at(pb)) {
      if (traced(walks, w0, unknowns(o), m.p.string_length)) continue;
      if (halves.size() + 2 > halves.capacity()) break;  // Walk keeps pointers into halves
      copt.direction = -1;
      halves.push_back(continue_branch(pb, unknowns(o), "omega", copt));
      copt.direction = +1;
      halves.push_back(continue_branch(pb, unknowns(o), "omega", copt));
      walks.push_back(join(halves[halves.size() - 2], halves.back()));
      const double sw = closure == Closure::BottomStop ? m.p.string_length - m.p.contact_distance : s;
      collect(walks.back(), sw, true, out);
      if (held_only) collect(walks.back(), sw, false, *held_only);
    }
  }
}
}  // namespace

Predictions predict_thresholds(const physics::Model& m, const PredictionOptions& opt) {
  const physics::Parameters& p = m.p;
  const double l = p.string_length;
  const double s_lo = m.layers.top_stop ? p.top_stop : 1e-3 * l;
  const double s_hi = m.layers.bottom_stop ? l - p.contact_distance : (1 - 1e-3) * l;
  const double w_hi = opt.omega_hi > 0 ? opt.omega_hi : 20 * kPi;
  const std::vector<double> starts =
      opt.start_omega.empty() ? std::vector<double>{3 * kPi, 5 * kPi, 8 * kPi, 12 * kPi} : opt.start_omega;
  ContinuationOptions copt;
  copt.lambda_min = opt.omega_lo;
  copt.lambda_max = w_hi;
  Predictions out;
  const int n = std::max(opt.s_points, 2);
  for (int k = 0; k < n; ++k)  // interior points: the bottom stop has its own rule
    trace_family(m, Closure::Stuck, s_lo + (s_hi - s_lo) * (k + 0.5) / n, starts, copt, out.intervals);
  // ω1 and ω_fall: the ends of the union of locked intervals.
  ThresholdPrediction w1{"omega1", kNaN, 4.80 * kPi, "no stable admissible stuck orbit in the range"};
  ThresholdPrediction wf{"omega_fall", kNaN, 3.24 * kPi, "no stable admissible stuck orbit in the range"};
  for (const auto& iv : out.intervals) {
    if (!(iv.omega_hi <= w1.predicted)) {
      w1.predicted = iv.omega_hi;
      w1.mechanism = fmt::format("{} at s = {:.4f} m (branch {})", iv.ends_hi, iv.s, iv.branch);
    }
    if (!(iv.omega_lo >= wf.predicted)) {
      wf.predicted = iv.omega_lo;
      wf.mechanism = fmt::format("{} at s = {:.4f} m (branch {})", iv.ends_lo, iv.s, iv.branch);
    }
  }
  // ω_rise: ramping up from hanging, the pair follows an orbit on the bottom stop. Where that
  // orbit folds it must jump, and it lands on one that exists there if there is one. Two
  // readings: (linear) the first end that is not a fold, a loss of stability included; (cone)
  // stability ignored, the first ω_m where the bead's static cone lets it climb off the ball.
  // A slow ramp may cross a short unstable stretch without the oscillation growing much, so
  // the truth lies between the two.
  ThresholdPrediction wr{"omega_rise", kNaN, 12.63 * kPi, "the bottom stop is off"};
  ThresholdPrediction wc{"omega_rise_cone", kNaN, 12.63 * kPi, "the bottom stop is off"};
  if (m.layers.bottom_stop) {
    std::vector<LockedInterval> stable, held;
    std::vector<double> bstarts{opt.omega_lo};
    bstarts.insert(bstarts.end(), starts.begin(), starts.end());
    trace_family(m, Closure::BottomStop, 0.0, bstarts, copt, stable, &held);
    const auto follow = [&](const std::vector<LockedInterval>& list, ThresholdPrediction& t, const char* none) {
      t.mechanism = none;
      const LockedInterval* at = nullptr;
      for (const auto& iv : list)
        if (iv.omega_lo <= opt.omega_lo * (1 + 1e-9) && (!at || iv.omega_hi > at->omega_hi)) at = &iv;
      for (int hops = 0; at && hops < 32; ++hops) {
        t.predicted = at->omega_hi;
        t.mechanism = at->ends_hi == "range" ? "orbits on the bottom stop up to the end of the range"
                                             : fmt::format("{} of the bottom-stop orbit (branch {})", at->ends_hi,
                                                           at->branch);
        if (at->ends_hi != "fold") break;
        const LockedInterval* next = nullptr;
        for (const auto& iv : list)
          if (&iv != at && iv.omega_lo < at->omega_hi && iv.omega_hi > at->omega_hi &&
              (!next || iv.omega_hi > next->omega_hi))
            next = &iv;
        at = next;
      }
    };
    follow(stable, wr, "no stable orbit on the bottom stop at the lowest ω_m");
    follow(held, wc, "no orbit held on the bottom stop at the lowest ω_m");
    out.intervals.insert(out.intervals.end(), stable.begin(), stable.end());
  }
  out.thresholds = {wr, wc, wf, w1};
  return out;
}

double held_orbit_end(const physics::Model& m, double omega0, double s_star, const numerics::Vec& y, double phi,
                      double limit) {
  const physics::Parameters& p = m.p;
  const OrbitProblem pb{m, omega0, Closure::Stuck, s_star};
  const Vec12 z = frame_state(y, phi, omega0);
  const Vec3 q1 = z.head<3>(), q2 = z.segment<3>(3), W(0, 0, omega0), P(1, 1, 0);
  // The pulls from the balance of each ball at rest in the frame (steady_orbit.hpp):
  //   F2 u2 = m2 ω² P p2 − c_D Ω×p2 − m2 g ẑ,   F1 u1 = F2 u2 + m1 ω² P p1 − c_D Ω×p1 − m1 g ẑ.
  const Vec3 z_hat = Vec3::UnitZ();
  const Vec3 f2 =
      p.ball_mass * omega0 * omega0 * P.cwiseProduct(q2) - p.drag * W.cross(q2) - p.ball_mass * p.gravity * z_hat;
  const Vec3 f1 =
      f2 + p.bead_mass * omega0 * omega0 * P.cwiseProduct(q1) - p.drag * W.cross(q1) - p.bead_mass * p.gravity * z_hat;
  Vec9 X0;
  X0 << q1, q2, f1.norm(), f2.norm(), s_star;
  const NewtonResult held = solve(pb, X0);
  // Within l/10 of the state: an orbit still swinging about its equilibrium, not the orbit of
  // another branch (those lie across the motor axis, a ball's ρ away).
  if (!held.converged || (held.X.head<6>() - X0.head<6>()).norm() > 0.1 * p.string_length) return kNaN;
  ContinuationOptions copt;
  copt.direction = limit < omega0 ? -1 : +1;
  copt.lambda_min = std::min(omega0, limit);
  copt.lambda_max = std::max(omega0, limit);
  copt.step_max = 0.05;  // events are located by bisection on their signs, not by the step
  copt.stop_at = [](const BranchPoint& q) { return !locked(q, true); };  // the interval's end is passed
  const Branch b = continue_branch(pb, held.X, "omega", copt);
  Walk w;
  for (const BranchPoint& q : b.points) w.points.push_back(&q);
  for (const BranchEvent& e : b.events) w.events.push_back({e.after_point, &e});
  if (w.points.empty() || !locked(*w.points.front(), true)) return kNaN;
  for (int i = 0; i + 1 < int(w.points.size()); ++i) {
    for (const auto& [seg, e] : w.events)  // past a fold the branch turns back: the orbit is gone
      if (seg == i && e->kind == EventKind::Fold) return e->lambda;
    if (!locked(*w.points[i + 1], true)) return boundary(w, i, true, true).first;
  }
  return kNaN;
}

}  // namespace ajx::orbits
