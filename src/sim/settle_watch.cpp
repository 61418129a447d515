#include "sim/settle_watch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "physics/rotating_axes.hpp"

namespace ajx::sim {

namespace idx = physics::idx;

SettleWatch::SettleWatch(RunContext& ctx) : ctx_(ctx) { restart(-std::numeric_limits<double>::infinity()); }

// Ω: ω_m for the top on the rod (held tie or none), χ̇ for a slipping tie.
double SettleWatch::top_rate(double t, const numerics::Vec& y) const {
  if (y.size() > idx::dim && ctx_.s.contact.tie.slip) return y(idx::chi_dot);
  double phi, w, wd;
  ctx_.schedule.phase(t, phi, w, wd);
  return w;
}

// V = max_i |v_i − Ω ẑ × r_i|: invariant under rotations about z, so the same in any axes.
double SettleWatch::relative_speed(double t, const numerics::Vec& y) const {
  const double Omega = top_rate(t, y);
  double v = 0.0;
  for (int b : {idx::r1, idx::r2}) {
    const int u = b + (idx::v1 - idx::r1);
    const double wx = y(u) + Omega * y(b + 1), wy = y(u + 1) - Omega * y(b), wz = y(u + 2);
    v = std::max(v, std::sqrt(wx * wx + wy * wy + wz * wz));
  }
  return v;
}

SettleWatch::Record SettleWatch::record(double t, const numerics::Vec& y) const {
  return {t, {y(idx::motor_work), y(idx::drag_loss), y(idx::friction_loss)}, ctx_.s.impact_loss};
}

void SettleWatch::restart(double t) {
  block_end_ = t + kBlock;
  v_now_ = 0.0;
  v_prev_ = -1.0;
  q_prev_ = 2.0;
  pending_ = false;
  mode_ = ctx_.s.contact.mode;
  tie_slip_ = ctx_.s.contact.tie.slip;
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
    block_start_ = record(t, yend_);
    v_now_ = relative_speed(t, yend_);
    return true;
  }
  v_now_ = std::max(v_now_, relative_speed(t, yend_));
  if (t < block_end_) return true;
  // A block closed: V_j against V_{j−1}, λ_j = −ln(V_j/V_{j−1})/B_j.
  const double len = t - block_start_.t;
  const double q = v_prev_ > 0.0 ? v_now_ / v_prev_ : (v_now_ > 0.0 ? 2.0 : 0.0);
  if (v_prev_ >= 0.0 && (v_now_ == 0.0 || (q < 1.0 && q_prev_ < 1.0))) {
    const double lambda = -std::log(std::max(q, q_prev_)) / len;  // the slower decay of the two
    const double distance = v_now_ == 0.0 ? 0.0 : v_now_ / lambda;   // D ≤ V/λ [m]
    if (distance <= ctx_.opt.settle_tolerance * ctx_.model.p.string_length && spans[span_].second - t > kBlock) {
      const Record now = record(t, yend_);
      for (int k = 0; k < 3; ++k) rate_[k] = (now.work[k] - block_start_.work[k]) / len;
      rate_[3] = (now.impact - block_start_.impact) / len;
      pending_ = true;
      return false;
    }
  }
  if (v_prev_ >= 0.0) q_prev_ = q;
  v_prev_ = v_now_;
  v_now_ = 0.0;
  block_start_ = record(t, yend_);
  block_end_ = t + kBlock;
  return true;
}

void SettleWatch::jump() {
  pending_ = false;
  State& s = ctx_.s;
  const double end = ctx_.opt.settle_spans[span_].second, dt = end - s.t;
  const double Omega = top_rate(s.t, s.y);
  // The lab state turns by Ω Δ; the integrator's axes turn by their own angle meanwhile.
  physics::rotate_about_z(s.y, Omega * dt - (ctx_.axes.angle(end) - ctx_.axes.angle(s.t)));
  if (s.y.size() > idx::dim) s.y(idx::chi) += Omega * dt;  // the held tie keeps χ − φ
  s.y(idx::motor_work) += rate_[0] * dt;
  s.y(idx::drag_loss) += rate_[1] * dt;
  s.y(idx::friction_loss) += rate_[2] * dt;
  s.impact_loss += rate_[3] * dt;
  s.t = end;
  ctx_.sum.skipped += dt;
  ++ctx_.sum.settle_stops;
  ++span_;
  restart(-std::numeric_limits<double>::infinity());
}

}  // namespace ajx::sim
