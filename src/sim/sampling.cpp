#include "sim/sampling.hpp"

#include "physics/rotating_axes.hpp"
#include "physics/tie.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ajx::sim {

using numerics::Vec;
using physics::Mode;

void Azimuth::advance(const physics::Vec3& r, double dbeta) {
  const Eigen::Vector2d now = r.head<2>();
  Eigen::Vector2d seen = now;
  if (dbeta != 0.0) {
    const double c = std::cos(dbeta), s = std::sin(dbeta);
    seen = Eigen::Vector2d(c * now.x() + s * now.y(), -s * now.x() + c * now.y());
  }
  const double cross = last.x() * seen.y() - last.y() * seen.x();
  theta += std::atan2(cross, last.dot(seen)) + dbeta;
  last = now;
}

Sampler::Sampler(RunContext& ctx, double t_end, double sample_dt, const SampleObserver& on_sample,
                 double sample_origin)
    : ctx_(ctx), on_sample_(on_sample), t_end_(t_end), sample_dt_(sample_dt), t_start_(ctx.s.t) {
  const State& s = ctx.s;
  origin_ = std::isfinite(sample_origin) ? sample_origin : t_start_;
  next_sample_ = sample_dt > 0.0 ? long(std::ceil((t_start_ - origin_) / sample_dt - 1e-9)) : 0;
  ybuf_.resize(s.y.size());
  // The azimuths for ω_ball, in the integrator's axes (the lab azimuth adds the axes' angle φ).
  az1_.reset(s.y.segment<3>(physics::idx::r1));
  az2_.reset(s.y.segment<3>(physics::idx::r2));
  window_ = std::min(ctx.opt.omega_window, 0.5 * (t_end - t_start_));
  t_window_ = t_end - window_;
  window_started_ = t_window_ <= t_start_;
  ctx.sum.min_tension = std::numeric_limits<double>::infinity();
  ctx.sum.min_friction_power = std::numeric_limits<double>::infinity();
  ylab_.resize(s.y.size());
  yend_.resize(physics::idx::dim);
  rate_start_ = azimuth_rates(s.t, s.y);
}

// Samples are handed out in the lab.
void Sampler::emit(double t, const Vec& y) {
  const Contact& contact = ctx_.contact();
  RunSummary& sum = ctx_.sum;
  ylab_ = y;
  if (ctx_.axes.rotating) physics::rotate_about_z(ylab_, ctx_.axes.angle(t));
  const physics::TopKinematics top = physics::top_kinematics(ctx_.model, ctx_.schedule, contact, t, ylab_);
  const physics::Dynamics dyn = physics::evaluate(ctx_.model, top, contact, ylab_);
  if (ctx_.opt.run_statistics) {
    sum.max_sample_drift =
        std::max(sum.max_sample_drift, physics::constraint_drift(ctx_.model, contact, top, ylab_).position);
    if (contact.mode != Mode::Slack) sum.min_tension = std::min({sum.min_tension, dyn.T1, dyn.T2});
    sum.min_friction_power = std::min(sum.min_friction_power, dyn.friction_power);
  }
  if (on_sample_) on_sample_(Sample{t, contact, ylab_, dyn, top, ctx_.s.impact_loss});
}

bool Sampler::wanted(double ts) {
  const auto& spans = ctx_.opt.sample_spans;
  if (spans.empty()) return true;
  while (span_ < spans.size() && ts >= spans[span_].second) ++span_;
  if (span_ < spans.size() && ts >= spans[span_].first) return true;
  // The grid index one below the next span's first: the caller re-tests each grid time from
  // there, so the jump does not depend on how (begin - origin)/dt rounds.
  const double next = span_ < spans.size() ? spans[span_].first : t_end_ + 2.0 * sample_dt_;
  next_sample_ = std::max(next_sample_ + 1, long(std::ceil((next - origin_) / sample_dt_)) - 1);
  return false;
}

void Sampler::start() {
  if (sample_dt_ > 0.0 && origin_ + double(next_sample_) * sample_dt_ <= t_start_) {
    if (wanted(ctx_.s.t)) {
      emit(ctx_.s.t, ctx_.s.y);
      ++next_sample_;
    }
  }
}

// θ̇ = (x w_y − y w_x)/(x² + y²), w the velocity seen in the axes (v − Ω×r when rotating),
// and in the other frame (the lab's θ̇ = θ̇' + ω, or the rotating θ̇' = θ̇ − ω).
Sampler::Rates Sampler::azimuth_rates(double t, const Vec& y) const {
  double phi, w, wd;
  ctx_.schedule.phase(t, phi, w, wd);
  Rates r;
  for (int b : {physics::idx::r1, physics::idx::r2}) {
    const double x = y(b), yy = y(b + 1), vx = y(b + 6), vy = y(b + 7);
    const double rho2 = x * x + yy * yy;
    const double lab_rate = rho2 > 0.0 ? (x * vy - yy * vx) / rho2 : 0.0;  // v is the lab velocity
    const double rot_rate = lab_rate - w;
    r.own = std::max(r.own, std::abs(ctx_.axes.rotating ? rot_rate : lab_rate));
    r.other = std::max(r.other, std::abs(ctx_.axes.rotating ? lab_rate : rot_rate));
  }
  return r;
}

bool Sampler::observe(const numerics::StepView& step) {
  // Samples in (t0, t1] (the first one at t_start is emitted before integrating).
  while (sample_dt_ > 0.0) {
    const double ts = origin_ + double(next_sample_) * sample_dt_;
    if (ts > step.t1() || ts > t_end_) break;
    if (!wanted(ts)) continue;  // next_sample_ moved on
    if (ts >= step.t0()) {
      step.at(ts, ybuf_);
      emit(ts, ybuf_);
    }
    ++next_sample_;
  }
  if (ctx_.opt.run_statistics) advance_azimuths(step);
  return true;
}

// Azimuths in increments small enough to unwrap (< 0.25 rad, with the rates of both ends of
// the step). One increment takes the end state and leaves the interpolant alone (DOP853's
// costs 3 extra evaluations per step).
// ω_ball needs θ only from the window's start: steps before it are not followed at all, and
// the azimuths start (θ = 0) from the interpolated state at t_window.
// The increments are measured in the integrator's axes or in the other frame (the lab or
// the rotating one, turned by β = ∓φ against them), whichever the balls turn slower in.
void Sampler::advance_azimuths(const numerics::StepView& step) {
  step.end(yend_);
  const Rates rate_end = azimuth_rates(step.t1(), yend_);
  const Rates rate_begin = rate_start_;
  rate_start_ = rate_end;
  double t0 = step.t0();
  if (!window_started_) {
    if (step.t1() < t_window_) return;
    if (t_window_ < step.t1()) {
      step.at(t_window_, ybuf_);
    } else {
      ybuf_ = yend_;
    }
    az1_.reset(ybuf_.segment<3>(physics::idx::r1));
    az2_.reset(ybuf_.segment<3>(physics::idx::r2));
    window_started_ = true;
    t0 = t_window_;
  }
  const double dt = std::abs(step.t1() - t0);
  const double own = std::max(rate_begin.own, rate_end.own), other = std::max(rate_begin.other, rate_end.other);
  const bool use_other = other < own;
  const int n = 1 + int(std::min(1e3, std::min(own, other) * dt / 0.25));
  // β(t): the other frame's angle against the integrator's axes (−φ from rotating axes to the
  // lab, +φ from the lab to rotating axes).
  const auto beta = [&](double t) {
    if (!use_other) return 0.0;
    double phi, w, wd;
    ctx_.schedule.phase(t, phi, w, wd);
    return ctx_.axes.rotating ? -phi : phi;
  };
  double beta_prev = beta(t0);
  for (int k = 1; k <= n; ++k) {
    const double t = t0 + (step.t1() - t0) * k / n;
    const double beta_t = beta(t);
    if (k == n)
      ybuf_ = yend_;
    else
      step.at(t, ybuf_);
    az1_.advance(ybuf_.segment<3>(physics::idx::r1), beta_t - beta_prev);
    az2_.advance(ybuf_.segment<3>(physics::idx::r2), beta_t - beta_prev);
    beta_prev = beta_t;
  }
}

void Sampler::finish() {
  RunSummary& sum = ctx_.sum;
  const double t = ctx_.s.t;
  if (window_ > 0 && window_started_) {
    const double theta_axes_window = ctx_.axes.angle(std::max(t_window_, t_start_));  // the axes' angle at t_window
    // (θ1 + θ2)/2 counts from t_window (the azimuths start there) in the integrator's axes; the
    // axes' own turn since then adds.
    sum.omega_ball =
        (0.5 * (az1_.theta + az2_.theta) + ctx_.axes.angle(t) - theta_axes_window) / (t - t_window_);
  }
  if (!std::isfinite(sum.min_tension)) sum.min_tension = 0.0;
  if (!std::isfinite(sum.min_friction_power)) sum.min_friction_power = 0.0;
  if (!ctx_.opt.run_statistics) {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    sum.omega_ball = sum.min_tension = sum.min_friction_power = sum.max_sample_drift = nan;
  }
}

}  // namespace ajx::sim
