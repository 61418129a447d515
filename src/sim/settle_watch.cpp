#include "sim/settle_watch.hpp"

#include <algorithm>
#include <cmath>

#include "physics/rotating_axes.hpp"
#include "sim/step.hpp"

namespace ajx::sim {

namespace idx = physics::idx;

SettleWatch::SettleWatch(RunContext& ctx)
    : ctx_(ctx), recurrence_(ctx.opt.settle_tolerance * ctx.model.p.string_length, kBlock) {
  restart(-std::numeric_limits<double>::infinity());
}

// Ω: ω_m for the top on the rod (held tie or none), χ̇ for a slipping tie.
double SettleWatch::top_rate(double t, const numerics::Vec& y) const {
  if (physics::has_tie(y) && ctx_.s.contact.tie.slip) return y(idx::chi_dot);
  double phi, w, wd;
  ctx_.schedule.phase(t, phi, w, wd);
  return w;
}

// ψ in the integrator's axes: χ (the tie's azimuth, in the lab) or φ, less the axes' own angle.
double SettleWatch::top_azimuth(double t, const numerics::Vec& y) const {
  double psi;
  if (physics::has_tie(y)) {
    psi = y(idx::chi);
  } else {
    double w, wd;
    ctx_.schedule.phase(t, psi, w, wd);
  }
  return psi - ctx_.axes.angle(t);
}

SettleWatch::Vec6 SettleWatch::in_top_frame(double t, const numerics::Vec& y) const {
  const double psi = top_azimuth(t, y);
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
  Record r{t, {}};
  for (int k = 0; k < 5; ++k) r.works[std::size_t(k)] = kWorks[k] < y.size() ? y(kWorks[k]) : 0.0;
  r.works[5] = ctx_.s.impact_loss;
  return r;
}

void SettleWatch::reset_rates() {
  blocks_ = 0;
  grid_count_ = 0;
  dist_.fill(0.0);
}

void SettleWatch::restart(double t) {
  block_end_ = t + kBlock;
  reset_rates();
  pending_ = false;
  mode_ = ctx_.s.contact.mode;
  tie_slip_ = ctx_.s.contact.tie.slip;
  tie_switched_ = false;
  recurrence_.clear();
  section_axis_ = -1;
  period_.reset();
}

void SettleWatch::open_block(double t, const numerics::Vec& y) {
  lo_ = hi_ = in_top_frame(t, y);
  block_start_ = record(t, y);
  block_end_ = t + kBlock;
}

// The state as lengths at the block's boundary t_b, read off the step's interpolant: the
// boundaries lie exactly B apart while no step is longer than a block.
void SettleWatch::sample_grid(const numerics::StepView& step) {
  const double tb = block_end_;
  if (grid_count_ > 0 && std::abs(tb - grid_t_ - kBlock) > 1e-9 * kBlock) grid_count_ = 0;
  numerics::Vec y(yend_.size());
  step.at(tb, y);
  std::rotate(grid_.begin(), grid_.begin() + 1, grid_.end());
  grid_.back() = section_point(tb, y, 0).p;
  grid_t_ = tb;
  grid_count_ = std::min(grid_count_ + 1, int(grid_.size()));
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
  // The first step in the span, or a switch of the bead's mode: blocks anew.
  if (!std::isfinite(block_end_) || ctx_.s.contact.mode != mode_) {
    restart(t);
    open_block(t, yend_);
    return true;
  }
  // The tie caught the rod or slipped again. The frame turns with χ either way (ψ = χ, continuous
  // through the switch), so a stick-slip cycle of the tie is a periodic orbit of that frame: the
  // section's crossings go on; a fixed point has a tie that no longer switches, so the blocks of
  // the fixed-point test start anew (recognised()).
  if (ctx_.s.contact.tie.slip != tie_slip_) {
    tie_slip_ = ctx_.s.contact.tie.slip;
    tie_switched_ = true;
  }
  const Vec6 x = in_top_frame(t, yend_);
  lo_ = lo_.cwiseMin(x);
  hi_ = hi_.cwiseMax(x);
  if (section_axis_ >= 0) {  // g = x_i − c changed sign: a crossing of the section
    const double g_begin = section_g_;
    section_g_ = x(section_axis_) - section_level_;
    if ((g_begin < 0.0) != (section_g_ < 0.0) && crossed(step, g_begin)) {
      pending_ = true;
      return false;
    }
  }
  if (t < block_end_) return true;
  sample_grid(step);
  if (recognised(t) && spans[span_].second - t > kBlock) {
    pending_ = true;
    return false;
  }
  if (section_axis_ < 0) choose_section(x);
  const double next = block_end_ + kBlock;
  open_block(t, yend_);
  if (next > t) block_end_ = next;  // the boundaries stay B apart
  return true;
}

// The section x_i = c: the coordinate that swung most over the block just closed, through the
// middle of its swing (every orbit that is not a fixed point crosses it twice a period). None
// while the block's swing is below ε l: the fixed-point test covers that.
void SettleWatch::choose_section(const Vec6& x) {
  Vec6::Index i;
  const double swing = (hi_ - lo_).maxCoeff(&i);
  if (!(swing > ctx_.opt.settle_tolerance * ctx_.model.p.string_length)) return;
  section_axis_ = int(i);
  section_level_ = 0.5 * (hi_(i) + lo_(i));
  section_g_ = x(i) - section_level_;
}

// The distance d_j = a_j + s_j of each closed block (its swing and the shift of its centre),
// over the last kRateBlocks blocks: Λ_j = ln(d_{j−1}/d_j) = σ B, σ the deviation's decay rate.
// The orbit is known when every Λ_j > 0 (the deviation decreased at every block), the newest
// Λ is not below the smallest before it (the rate has not slowed: a slower mode has not
// surfaced), a_j ≤ a_{j−1}, and D = a_j + s_j q/(1 − q) ≤ ε l with q = exp(−min Λ), the slowest
// contraction seen. A deviation that grows, stalls or decays ever more slowly (a lag near its
// Hopf point, where σ → 0 and then < 0) never ends its stretch.
bool SettleWatch::recognised(double t) {
  const Vec6 centre = 0.5 * (lo_ + hi_);
  const double spread = 0.5 * (hi_ - lo_).norm();
  const double shift = blocks_ > 0 ? (centre - centre_).norm() : 0.0;
  if (blocks_ > 0) {  // block 0 has no shift: its distance is not comparable
    std::rotate(dist_.begin(), dist_.begin() + 1, dist_.end());
    dist_.back() = spread + shift;
  }
  if (tie_switched_) {  // the tie switched in this block: no fixed point yet, the rates start anew
    tie_switched_ = false;
    reset_rates();
  }
  bool known = false;
  if (blocks_ >= kRateBlocks && spread <= spread_prev_) {
    double slowest = std::numeric_limits<double>::infinity(), before = slowest, newest = 0.0;
    bool falling = true;
    for (int j = 1; j < kRateBlocks; ++j) {
      const double d0 = dist_[std::size_t(j - 1)], d1 = dist_[std::size_t(j)];
      falling = falling && d1 < d0 && d1 > 0.0;
      if (!falling) break;
      newest = std::log(d0 / d1);
      if (j < kRateBlocks - 1) before = std::min(before, newest);
      slowest = std::min(slowest, newest);
    }
    if (falling && newest >= before) {
      const double q = std::exp(-slowest);
      distance_ = spread + shift * q / (1.0 - q);
      known = distance_ <= ctx_.opt.settle_tolerance * ctx_.model.p.string_length;
    }
  }
  ++blocks_;
  centre_ = centre;
  spread_prev_ = spread;
  if (known) {
    const Record now = record(t, yend_);
    const double len = t - block_start_.t;
    for (std::size_t k = 0; k < 6; ++k) rate_[k] = (now.works[k] - block_start_.works[k]) / len;
  }
  return known;
}

void SettleWatch::jump() {
  if (period_) return jump_periods();
  pending_ = false;
  State& s = ctx_.s;
  const double end = ctx_.opt.settle_spans[span_].second, dt = end - s.t;
  if (!land_on_fixed_point(end)) {
    const double Omega = top_rate(s.t, s.y);
    // The lab state turns by Ω Δ; the integrator's axes turn by their own angle meanwhile.
    physics::rotate_about_z(s.y, Omega * dt - (ctx_.axes.angle(end) - ctx_.axes.angle(s.t)));
    if (physics::has_tie(s.y)) s.y(idx::chi) += Omega * dt;  // the held tie keeps χ − φ
  }
  for (int k = 0; k < 5; ++k)
    if (kWorks[k] < s.y.size()) s.y(kWorks[k]) += rate_[k] * dt;
  s.impact_loss += rate_[5] * dt;
  s.t = end;
  ctx_.sum.skipped += dt;
  ++ctx_.sum.settle_stops;
  ++span_;
  restart(-std::numeric_limits<double>::infinity());
}

// The deviation of a single decaying mode, w(t) − w* = e^{−σ (t − t_b)} (w_b − w*), w the state
// in the turning frame as lengths (section_recurrence.hpp), read at three boundaries B apart:
// Δ_b = w_b − w_{b−1} = q Δ_{b−1}, q = e^{−σ B}, so w* = w_b + Δ_b q/(1 − q), up to
// E = |Δ_b − q Δ_{b−1}|/(1 − q)² for what the single mode leaves out. Where E < D (the plain
// stop's distance), the stretch ends where the full settle would: w(end) = w* + e^{−σ Δ}(w − w*),
// the frame's turn the integral of its rate Ω(t) = Ω* + e^{−σ t}(Ω − Ω*), then projected onto
// the mode's constraints; the window then starts within E + D e^{−σ Δ} of the full settle's
// state instead of D. Otherwise (an oscillating deviation, sampled at any phase) false.
bool SettleWatch::land_on_fixed_point(double end) {
  if (grid_count_ < 3 || grid_[0].size() != grid_[2].size() || grid_[1].size() != grid_[2].size()) return false;
  State& s = ctx_.s;
  const Eigen::VectorXd d1 = grid_[1] - grid_[0], d2 = grid_[2] - grid_[1];
  const double nn = d1.squaredNorm();
  if (!(nn > 0.0)) return false;
  const double q = d2.dot(d1) / nn;
  if (!(q > 0.0 && q < 1.0)) return false;
  const double E = (d2 - q * d1).norm() / ((1.0 - q) * (1.0 - q));
  if (!(E < distance_)) return false;
  const Eigen::VectorXd wstar = grid_[2] + d2 * (q / (1.0 - q));
  const double sigma = -std::log(q) / kBlock, dt = end - s.t, decay = std::exp(-sigma * dt);
  const Eigen::VectorXd w = wstar + (section_point(s.t, s.y, 0).p - wstar) * decay;
  const physics::Parameters& p = ctx_.model.p;
  const double omega0 = std::sqrt(p.gravity / p.string_length);
  const bool tie = physics::has_tie(s.y);
  double psi;  // the frame's azimuth at the end, in the integrator's axes
  if (tie) {
    const double rate = s.y(idx::chi_dot), rate_star = wstar(12) * omega0 / p.drive_radius;
    s.y(idx::chi) += rate_star * dt + (rate - rate_star) * (1.0 - decay) / sigma;
    s.y(idx::chi_dot) = w(12) * omega0 / p.drive_radius;
    psi = s.y(idx::chi) - ctx_.axes.angle(end);
  } else {
    psi = top_azimuth(end, s.y);
  }
  const double c = std::cos(psi), sn = std::sin(psi);
  for (int b = 0; b < 4; ++b) {  // r1, r2, v1, v2 turned back by ψ
    const int k = 3 * b;
    const double f = b < 2 ? 1.0 : omega0;
    s.y(k) = f * (c * w(k) - sn * w(k + 1));
    s.y(k + 1) = f * (sn * w(k) + c * w(k + 1));
    s.y(k + 2) = f * w(k + 2);
  }
  project_after_step(ctx_, end, s.y);
  return true;
}

// The section point at t (the state in the turning frame as lengths, section_recurrence.hpp).
SectionPoint SettleWatch::section_point(double t, const numerics::Vec& y, int direction) const {
  const physics::Parameters& p = ctx_.model.p;
  const double omega0 = std::sqrt(p.gravity / p.string_length);  // ω0 = √(g/l)
  const double psi = top_azimuth(t, y), c = std::cos(psi), s = std::sin(psi);
  const bool tie = physics::has_tie(y);
  SectionPoint pt;
  pt.t = t;
  pt.psi = psi + ctx_.axes.angle(t);
  pt.direction = direction;
  pt.p.resize(tie ? 13 : 12);
  for (int b = 0; b < 4; ++b) {  // r1, r2, v1 / ω0, v2 / ω0 turned by −ψ
    const int k = 3 * b;
    const double f = b < 2 ? 1.0 : 1.0 / omega0;
    pt.p(k) = f * (c * y(k) + s * y(k + 1));
    pt.p(k + 1) = f * (-s * y(k) + c * y(k + 1));
    pt.p(k + 2) = f * y(k + 2);
  }
  if (tie) pt.p(12) = p.drive_radius * y(idx::chi_dot) / omega0;  // the tie's speed R χ̇ / ω0
  const Record r = record(t, y);
  pt.works = r.works;
  return pt;
}

// The crossing located in the step by regula falsi (Illinois) on g(t) = x_i(t) − c of its
// interpolant, to the integrator's event precision; the recurrence is tested there.
bool SettleWatch::crossed(const numerics::StepView& step, double g_begin) {
  double a = step.t0(), b = step.t1(), ga = g_begin, gb = section_g_;
  numerics::Vec y(yend_.size());
  int side = 0;
  for (int it = 0; it < 60 && b - a > 1e-13 * std::max(1.0, std::abs(b)); ++it) {
    const double t = (a * gb - b * ga) / (gb - ga);
    step.at(t, y);
    const double g = in_top_frame(t, y)(section_axis_) - section_level_;
    if ((g < 0.0) == (ga < 0.0)) {
      a = t, ga = g;
      if (side == -1) gb *= 0.5;
      side = -1;
    } else {
      b = t, gb = g;
      if (side == 1) ga *= 0.5;
      side = 1;
    }
  }
  const double tc = 0.5 * (a + b);
  step.at(tc, y);
  const double end = ctx_.opt.settle_spans[span_].second;
  period_ = recurrence_.add(section_point(tc, y, g_begin < 0.0 ? 1 : -1), end - step.t1());
  // Worth a stop: at least a block of the stretch skipped.
  if (period_ && std::floor((end - step.t1()) / period_->T) * period_->T < kBlock) period_.reset();
  return period_.has_value();
}

// n whole periods: the lab state turned by n Δψ, the integrals advanced by n times their
// increase over a period; the rest of the stretch is integrated.
void SettleWatch::jump_periods() {
  pending_ = false;
  State& s = ctx_.s;
  const Period per = *period_;
  const double end = ctx_.opt.settle_spans[span_].second;
  const double n = std::floor((end - s.t) / per.T), dt = n * per.T;
  physics::rotate_about_z(s.y, n * per.turn - (ctx_.axes.angle(s.t + dt) - ctx_.axes.angle(s.t)));
  if (physics::has_tie(s.y)) {
    s.y(idx::chi) += n * per.turn;
    // A held tie sits at χ = φ + δ: over periods in which it slipped, χ turned by n Δψ and φ by
    // n ω_m T, so δ moves by the difference.
    if (!s.contact.tie.slip) {
      double phi, w, wd;
      ctx_.schedule.phase(s.t + dt, phi, w, wd);
      s.contact.tie.offset = s.y(idx::chi) - phi;
    }
  }
  for (int k = 0; k < 5; ++k)
    if (kWorks[k] < s.y.size()) s.y(kWorks[k]) += n * per.works[std::size_t(k)];
  s.impact_loss += n * per.works[5];
  s.t += dt;
  ctx_.sum.skipped += dt;
  ++ctx_.sum.settle_stops;
  ++span_;  // the rest of this stretch is integrated without the watch
  restart(-std::numeric_limits<double>::infinity());
}

}  // namespace ajx::sim
