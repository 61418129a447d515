#include "web/engine.hpp"

#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "physics/energy.hpp"
#include "physics/tie.hpp"
#include "sweep/orbit_classifier.hpp"
#include "sweep/seeds.hpp"

namespace ajx::web {

using physics::Mode;
using physics::Vec3;

Engine::Engine(std::string scene_text, std::string scene_name)
    : scene_text_(std::move(scene_text)), scene_name_(std::move(scene_name)) {
  config_ = config::parse_run_config(scene_text_, scene_name_);
  start("hanging", 0.0);
}

std::string Engine::configure(const std::vector<std::string>& overrides) {
  config::RunConfig next;
  try {
    next = config::parse_run_config(scene_text_, scene_name_, overrides);
  } catch (const std::exception& e) {
    return e.what();  // the text `astrojax run sweeps/live.toml --set ...` prints after "error: "
  }
  // Carry the motion over: the same positions, velocities and mode under the new model,
  // projected onto its constraints (the new l, R or d move them by at most a few per cent).
  const Vec3 r1 = state_.r1(), r2 = state_.r2(), v1 = state_.v1(), v2 = state_.v2();
  Mode mode = state_.contact.mode;
  const double omega = omega_m();
  config_ = std::move(next);
  new_schedule(omega, omega_target_, rate_);  // an ongoing ramp goes on
  // A string made longer than L1 + L2 is slack: the balls fly until it is taut again.
  const Vec3 a = schedule_.top(0.0).a;
  if (config_.model.layers.slack && (r1 - a).norm() + (r2 - r1).norm() < config_.model.p.string_length - 1e-6)
    mode = Mode::Slack;
  try {
    state_ = sim::explicit_state(config_.model, schedule_, r1, r2, v1, v2, mode, 0.0,
                                 0.05 * config_.model.p.string_length);
    begin_ = state_;
    failure_.clear();
  } catch (const std::exception& e) {
    return start(seed_, omega).empty() ? std::string() : e.what();
  }
  window_.clear();
  return {};
}

std::string Engine::start(const std::string& seed, double omega) {
  seed_ = seed;
  seed_omega_ = omega;
  schedule_ = {};  // the seeds put the top at φ = 0
  state_.t = 0.0;
  t_offset_ = 0.0;
  new_schedule(omega, omega, 0.0);
  failure_.clear();
  totals_ = {};
  window_.clear();
  recent_.clear();
  try {
    state_ = sweep::seed_state(config_.model, schedule_, seed, omega, 0, 0.0);
  } catch (const std::exception& e) {
    failure_ = e.what();
    return failure_;
  }
  begin_ = state_;
  return {};
}

double Engine::omega_m() const {
  double phi, omega, omega_dot;
  schedule_.phase(state_.t, phi, omega, omega_dot);
  return omega;
}

// A schedule from the state's clock restarted at 0: ω_m from omega_begin to omega_end at
// `rate`, then held. φ(0) is the old schedule's φ now, so the top moves on continuously.
void Engine::new_schedule(double omega_begin, double omega_end, double rate) {
  double phi = 0.0, omega, omega_dot;
  if (!schedule_.segments().empty()) schedule_.phase(state_.t, phi, omega, omega_dot);
  t_offset_ += state_.t;
  state_.t = 0.0;
  std::vector<physics::DriveSegment> segs;
  const double change = std::abs(omega_end - omega_begin);
  if (change > 0.0 && rate > 0.0) segs.push_back({omega_begin, omega_end, change / rate});
  segs.push_back({omega_end, omega_end, 1.0});  // past its end the schedule holds the last ω
  schedule_ = physics::MotorSchedule(config_.model.p.drive_radius, std::move(segs), phi);
  omega_target_ = omega_end;
  rate_ = rate;
  // A held tie keeps its offset χ − φ; the schedule's φ is continuous, so χ is too.
}

void Engine::hold() {
  const double w = omega_m();
  new_schedule(w, w, 0.0);
}

std::string Engine::ramp(double omega_target, double rate) {
  if (!(rate > 0.0) || !std::isfinite(rate))
    return fmt::format("ramp rate: {} is out of range; allowed (0, ∞) rad/s^2", rate);
  if (!(omega_target >= 0.0) || !std::isfinite(omega_target))
    return fmt::format("ramp target: {} is out of range; allowed [0, ∞) rad/s", omega_target);
  new_schedule(omega_m(), omega_target, rate);
  return {};
}

void Engine::add_totals(const sim::RunSummary& r) {
  totals_.steps += r.steps;
  totals_.rejected += r.rejected;
  totals_.rhs_evals += r.rhs_evals;
  totals_.mode_switches += r.mode_switches;
  totals_.impacts += r.impacts;
  totals_.projections += r.projections;
  if (totals_.first_stick < 0 && r.first_stick >= 0) totals_.first_stick = t_offset_ + r.first_stick;
  totals_.sticks += r.sticks;
  totals_.slack_phases += r.slack_phases;
  if (totals_.first_tie_slip < 0 && r.first_tie_slip >= 0) totals_.first_tie_slip = t_offset_ + r.first_tie_slip;
  totals_.tie_slips += r.tie_slips;
  totals_.chatter += r.chatter;
}

bool Engine::advance(double dt) {
  recent_.clear();
  if (!failure_.empty()) return false;
  if (!(dt > 0.0)) return true;
  sim::RunOptions opt = config_.run;
  opt.run_statistics = false;  // the classifier measures the window from the samples
  sim::Simulation sim(config_.model, schedule_, opt);
  const double origin = t_offset_;
  auto on_sample = [&](const sim::Sample& s) {
    if (!window_.empty() && origin + s.t <= window_.back().t) return;  // the last advance's end
    Row r{origin + s.t, s.top.motor_omega, {}, {}, s.dyn.g.L1, s.dyn.T1, s.dyn.T2, int(s.contact.mode)};
    for (int k = 0; k < 3; ++k) {
      r.r1[k] = s.y(physics::idx::r1 + k);
      r.r2[k] = s.y(physics::idx::r2 + k);
    }
    window_.push_back(r);
    recent_.insert(recent_.end(), {r.t, r.omega_m, r.r1[0], r.r1[1], r.r1[2], r.r2[0], r.r2[1], r.r2[2],
                                   double(r.mode)});
  };
  // Samples on the grid k·Δt of the page's clock (state clock −t_offset + k·Δt), whatever the
  // frame boundaries.
  const sim::RunSummary r = sim.run(state_, state_.t + dt, kSampleInterval, on_sample, -t_offset_);
  add_totals(r);
  while (!window_.empty() && window_.front().t < time() - kWindow) window_.pop_front();
  if (!r.ok()) failure_ = r.failure;
  return r.ok();
}

std::vector<double> Engine::positions() const {
  const physics::TopKinematics top = physics::top_kinematics(config_.model, schedule_, state_.contact, state_.t, state_.y);
  const auto r1 = state_.r1(), r2 = state_.r2();
  return {top.a.x(), top.a.y(), top.a.z(), r1.x(), r1.y(), r1.z(), r2.x(), r2.y(), r2.z()};
}

Energies Engine::energies() const {
  const physics::Parameters& p = config_.model.p;
  const physics::EnergyBalance b = physics::energy_balance(p, begin_, state_);
  Energies e{};
  e.kinetic = 0.5 * p.bead_mass * state_.v1().squaredNorm() + 0.5 * p.ball_mass * state_.v2().squaredNorm();
  e.potential = physics::mechanical_energy(p, state_.y) - e.kinetic;
  e.motor_work = b.motor_work;
  e.drag_loss = b.drag_loss;
  e.friction_loss = b.friction_loss;
  e.impact_loss = b.impact_loss;
  e.delta_energy = b.delta_energy;
  e.residual = b.residual;
  return e;
}

Verdict Engine::classify() const {
  Verdict v;
  v.t_end = time();
  if (window_.empty() || window_.back().t - window_.front().t < 0.95 * kWindow) {
    v.cls = "none";
    v.reason = fmt::format("fewer than {:g} s of samples since the last start or change", kWindow);
    return v;
  }
  const std::size_t n = window_.size();
  std::vector<double> t(n), om(n), r1(3 * n), r2(3 * n), L1(n), T1(n), T2(n);
  std::vector<int> mode(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Row& r = window_[i];
    t[i] = r.t, om[i] = r.omega_m, L1[i] = r.L1, T1[i] = r.T1, T2[i] = r.T2, mode[i] = r.mode;
    for (int k = 0; k < 3; ++k) r1[3 * i + k] = r.r1[k], r2[3 * i + k] = r.r2[k];
  }
  sweep::OrbitWindow w{t, om, r1, r2, L1, T1, T2, mode, false, {}};
  const sweep::OrbitClassification c = sweep::classify_orbit(w, sweep::orbit_scales(config_.model.p));
  v.cls = std::string(sweep::to_string(c.cls));
  v.omega_ball = c.stats.omega_ball;
  v.omega_m = c.stats.omega_m.mean;
  v.confidence = c.confidence;
  v.reason = c.reason;
  return v;
}

}  // namespace ajx::web
