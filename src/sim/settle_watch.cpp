#include "sim/settle_watch.hpp"

#include <algorithm>
#include <cmath>

#include "physics/rotating_axes.hpp"

namespace ajx::sim {

namespace idx = physics::idx;

SettleWatch::SettleWatch(RunContext& ctx) : ctx_(ctx) { restart(-std::numeric_limits<double>::infinity()); }

// Ω: ω_m for the top on the rod (held tie or none), χ̇ for a slipping tie.
double SettleWatch::top_rate(double t, const numerics::Vec& y) const {
  if (physics::has_tie(y) && ctx_.s.contact.tie.slip) return y(idx::chi_dot);
  double phi, w, wd;
  ctx_.schedule.phase(t, phi, w, wd);
  return w;
}

// ψ in the integrator's axes: χ (the tie's azimuth, in the lab) or φ, less the axes' own angle.
SettleWatch::Vec6 SettleWatch::in_top_frame(double t, const numerics::Vec& y) const {
  double psi;
  if (physics::has_tie(y)) {
    psi = y(idx::chi);
  } else {
    double w, wd;
    ctx_.schedule.phase(t, psi, w, wd);
  }
  psi -= ctx_.axes.angle(t);
  const double c = std::cos(psi), s = std::sin(psi);
  Vec6 x;
  for (int b = 0; b < 2; ++b) {
    const int k = b == 0 ? idx::r1 : idx::r2;
    x(3 * b) = c * y(k) + s * y(k + 1);
    x(3 * b + 1) = -s * y(k) + c * y(k + 1);
    x(3 * b + 2) = y(k + 2);
  }
  return x;
}

// The work integrals of y that a jump carries on: the string's, drag's and friction's, and
// where a clutch is modelled the motor's and the clutch's (physics/state.hpp).
constexpr int kWorks[] = {idx::motor_work, idx::drag_loss, idx::friction_loss, idx::rod_work, idx::clutch_loss};

SettleWatch::Record SettleWatch::record(double t, const numerics::Vec& y) const {
  Record r{t, {}, ctx_.s.impact_loss};
  for (int k = 0; k < 5; ++k) r.work[k] = kWorks[k] < y.size() ? y(kWorks[k]) : 0.0;
  return r;
}

void SettleWatch::restart(double t) {
  block_end_ = t + kBlock;
  blocks_ = 0;
  pending_ = false;
  mode_ = ctx_.s.contact.mode;
  tie_slip_ = ctx_.s.contact.tie.slip;
}

void SettleWatch::open_block(double t, const numerics::Vec& y) {
  lo_ = hi_ = in_top_frame(t, y);
  block_start_ = record(t, y);
  block_end_ = t + kBlock;
}

bool SettleWatch::observe(const numerics::StepView& step) {
  const auto& spans = ctx_.opt.settle_spans;
  const double t = step.t1();
  while (span_ < spans.size() && t >= spans[span_].second) {
    ++span_;
    restart(-std::numeric_limits<double>::infinity());
  }
  if (span_ == spans.size() || t < spans[span_].first) return true;
  if (yend_.size() == 0) yend_.resize(ctx_.s.y.size());
  step.end(yend_);
  // The first step in the span, or a switch of the bead's mode or of the tie: blocks anew.
  if (!std::isfinite(block_end_) || ctx_.s.contact.mode != mode_ || ctx_.s.contact.tie.slip != tie_slip_) {
    restart(t);
    open_block(t, yend_);
    return true;
  }
  const Vec6 x = in_top_frame(t, yend_);
  lo_ = lo_.cwiseMin(x);
  hi_ = hi_.cwiseMax(x);
  if (t < block_end_) return true;
  if (recognised(t) && spans[span_].second - t > kBlock) {
    pending_ = true;
    return false;
  }
  open_block(t, yend_);
  return true;
}

// D = a_j + s_j q/(1 − q), q = s_j/s_{j−1} < 1, a_j ≤ a_{j−1}: at most ε l.
bool SettleWatch::recognised(double t) {
  const Vec6 centre = 0.5 * (lo_ + hi_);
  const double spread = 0.5 * (hi_ - lo_).norm();
  const double shift = blocks_ > 0 ? (centre - centre_).norm() : 0.0;
  bool known = false;
  if (blocks_ >= 2 && spread <= spread_prev_ && shift < shift_prev_) {
    const double q = shift / shift_prev_;
    known = spread + shift * q / (1.0 - q) <= ctx_.opt.settle_tolerance * ctx_.model.p.string_length;
  }
  ++blocks_;
  centre_ = centre;
  spread_prev_ = spread;
  shift_prev_ = shift;
  if (known) {
    const Record now = record(t, yend_);
    const double len = t - block_start_.t;
    for (int k = 0; k < 5; ++k) rate_[k] = (now.work[k] - block_start_.work[k]) / len;
    rate_[5] = (now.impact - block_start_.impact) / len;
  }
  return known;
}

void SettleWatch::jump() {
  pending_ = false;
  State& s = ctx_.s;
  const double end = ctx_.opt.settle_spans[span_].second, dt = end - s.t;
  const double Omega = top_rate(s.t, s.y);
  // The lab state turns by Ω Δ; the integrator's axes turn by their own angle meanwhile.
  physics::rotate_about_z(s.y, Omega * dt - (ctx_.axes.angle(end) - ctx_.axes.angle(s.t)));
  if (physics::has_tie(s.y)) s.y(idx::chi) += Omega * dt;  // the held tie keeps χ − φ
  for (int k = 0; k < 5; ++k)
    if (kWorks[k] < s.y.size()) s.y(kWorks[k]) += rate_[k] * dt;
  s.impact_loss += rate_[5] * dt;
  s.t = end;
  ctx_.sum.skipped += dt;
  ++ctx_.sum.settle_stops;
  ++span_;
  restart(-std::numeric_limits<double>::infinity());
}

}  // namespace ajx::sim
