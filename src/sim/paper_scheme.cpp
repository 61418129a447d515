#include "sim/paper_scheme.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <stdexcept>

#include "physics/astrojax_system.hpp"
#include "physics/contact_modes.hpp"
#include "physics/energy.hpp"
#include "physics/mode_transitions.hpp"
#include "physics/string_friction.hpp"

namespace ajx::sim {

using physics::Vec3;
namespace idx = physics::idx;

std::optional<PaperDrag> paper_variant(std::string_view method) {
  if (method == "paper") return PaperDrag::Printed;
  if (method == "paper_corrected") return PaperDrag::Corrected;
  return std::nullopt;
}

Vec3 central_step(const Vec3& q, const Vec3& q_prev, const Vec3& f, double m, double c, double h, PaperDrag drag) {
  const double s = drag == PaperDrag::Printed ? 1.0 : -1.0;  // eq. (15) as printed / eq. (8)
  return 2.0 * q - q_prev + (h * h / m) * (f + s * c * (q - q_prev) / h);
}

namespace {

const physics::Contact kTaut{physics::Mode::Sliding, 0, 0.0};

numerics::Vec positions(const Vec3& r1, const Vec3& r2) {
  numerics::Vec y = numerics::Vec::Zero(idx::dim);
  y.segment<3>(idx::r1) = r1;
  y.segment<3>(idx::r2) = r2;
  return y;
}

double length_excess(const Vec3& a, const Vec3& r1, const Vec3& r2, double l) {
  return (r1 - a).norm() + (r2 - r1).norm() - l;
}

// T2 with L1 + L2 = l at q^(k+1) = p + T2 b (eq. 29): Newton from T_guess. L1 + L2 is convex in
// T2 (a sum of norms of affine functions), so it has at most two roots; the one near the last
// step's tension is the continuous one.
std::optional<double> solve_tension(const Vec3& a, const Vec3& p1, const Vec3& p2, const Vec3& b1, const Vec3& b2,
                                    double l, double T_guess) {
  double T = T_guess;
  for (int it = 0; it < 60; ++it) {
    const Vec3 d1 = p1 + T * b1 - a, d2 = p2 + T * b2 - (p1 + T * b1);
    const double n1 = d1.norm(), n2 = d2.norm();
    const double g = n1 + n2 - l;
    if (std::abs(g) <= 16.0 * std::numeric_limits<double>::epsilon() * l) return T;
    const double dg = d1.dot(b1) / n1 + d2.dot(b2 - b1) / n2;
    if (!(std::abs(dg) > 0.0) || !std::isfinite(g)) return std::nullopt;
    T -= g / dg;
  }
  return std::nullopt;
}

// A watch of an omitted layer: entered when its value goes below zero.
struct Watch {
  Violation v;
  bool inside = false;
  void see(double t, double value) {
    if (value < 0.0) {
      if (!inside && v.count++ == 0) v.first_time = t;
      v.worst = std::max(v.worst, -value);
    }
    inside = value < 0.0;
  }
};

// The unwrapped mean azimuth of the two balls about the motor axis.
struct MeanAzimuth {
  double theta = 0.0;
  Vec3 last1, last2;
  void reset(const Vec3& r1, const Vec3& r2) { theta = 0.0; last1 = r1; last2 = r2; }
  static double turn(const Vec3& a, const Vec3& b) {
    return std::atan2(a.x() * b.y() - a.y() * b.x(), a.x() * b.x() + a.y() * b.y());
  }
  void advance(const Vec3& r1, const Vec3& r2) {
    theta += 0.5 * (turn(last1, r1) + turn(last2, r2));
    last1 = r1;
    last2 = r2;
  }
};

}  // namespace

double project_pair(const physics::Model& model, const physics::MotorSchedule& schedule, double h, PairStart& pair) {
  const double l = model.p.string_length;
  double worst = 0.0;
  for (int k = 0; k < 2; ++k) {
    Vec3& r1 = k == 0 ? pair.r1_0 : pair.r1_1;
    Vec3& r2 = k == 0 ? pair.r2_0 : pair.r2_1;
    const physics::TopKinematics top = schedule.top(pair.t0 + k * h);
    worst = std::max(worst, std::abs(length_excess(top.a, r1, r2, l)));
    numerics::Vec y = positions(r1, r2);
    physics::project_positions(model, kTaut, top, y);
    r1 = y.segment<3>(idx::r1);
    r2 = y.segment<3>(idx::r2);
  }
  return worst;
}

physics::State state_from_pair(const physics::Model& model, const physics::MotorSchedule& schedule,
                               const PairStart& pair, double h, double tol) {
  const physics::TopKinematics top = schedule.top(pair.t0);
  const double excess = length_excess(top.a, pair.r1_0, pair.r2_0, model.p.string_length);
  const physics::Mode mode = excess >= -tol ? physics::Mode::Sliding : physics::Mode::Slack;
  return explicit_state(model, schedule, pair.r1_0, pair.r2_0, (pair.r1_1 - pair.r1_0) / h,
                        (pair.r2_1 - pair.r2_0) / h, mode, pair.t0, std::max(tol, std::abs(excess)) * (1 + 1e-12));
}

std::vector<std::pair<std::string, std::string>> paper_scheme_conflicts(const physics::Model& model) {
  const physics::Layers& L = model.layers;
  std::vector<std::pair<std::string, std::string>> out;
  if (L.friction != physics::Friction::None && L.friction != physics::Friction::Kinetic)
    out.emplace_back("layers.friction", "\"kinetic\" or \"none\" (the paper's scheme has no stuck bead)");
  if (L.slack) out.emplace_back("layers.slack", "false (the paper's scheme keeps the string taut; negative tensions are reported)");
  if (L.bottom_stop) out.emplace_back("layers.bottom_stop", "false (the paper's scheme has no stops; L2 < d is reported)");
  if (L.top_stop) out.emplace_back("layers.top_stop", "false (the paper's scheme has no stops; L1 < s_min is reported)");
  if (L.tie_clutch) out.emplace_back("layers.tie", "\"rigid\" (the paper's string is tied to the rod)");
  if (L.pair_couple != physics::PairCouple::None) out.emplace_back("layers.pair_couple", "\"none\"");
  return out;
}

namespace {

// The scheme's state between steps and what a run accumulates.
class PaperRun {
 public:
  PaperRun(const physics::Model& model, const physics::MotorSchedule& schedule, PaperDrag drag, double h)
      : m_(model), p_(model.p), sched_(schedule), drag_(drag), h_(h) {
    using physics::Guard;
    watches_[0].v = {std::string(physics::to_string(Guard::WatchTension)), 0, -1.0, 0.0, "N"};
    watches_[1].v = {std::string(physics::to_string(Guard::WatchBottom)), 0, -1.0, 0.0, "m"};
    watches_[2].v = {std::string(physics::to_string(Guard::WatchTop)), 0, -1.0, 0.0, "m"};
  }

  RunSummary run(const PairStart& pair, double t_end, double sample_dt, const SampleObserver& on_sample,
                 physics::State& end, double omega_window);

 private:
  // q^(k+1) from q^(k-1), q^(k) at t_k; sets T1_, T2_. Returns false (with failure_) if it cannot.
  bool step(double t, const Vec3& a, const Vec3& a_next);
  // The sampled state and forces of step k, once q^(k+1) is known.
  void diagnose(double t);

  const physics::Model& m_;
  const physics::Parameters& p_;
  const physics::MotorSchedule& sched_;
  PaperDrag drag_;
  double h_;
  Vec3 q1_prev_, q2_prev_, q1_, q2_, q1_next_, q2_next_;
  double L1_prev_ = 0.0;  // L1 at step k-1
  double T1_ = 0.0, T2_ = 0.0;
  std::string failure_;
  // Diagnostics of step k.
  numerics::Vec y_ = numerics::Vec::Zero(idx::dim);
  physics::Dynamics dyn_{};
  physics::TopKinematics top_{};
  double powers_prev_[3] = {0, 0, 0};
  bool have_prev_powers_ = false;
  Watch watches_[3];
};

bool PaperRun::step(double t, const Vec3& a, const Vec3& a_next) {
  const Vec3 d1 = q1_ - a, d2 = q2_ - q1_;
  const double L1 = d1.norm(), L2 = d2.norm();
  if (!(L1 > 0.0 && L2 > 0.0)) {
    failure_ = fmt::format("at t = {:.6f} s a string segment has zero length (L1 = {:g} m, L2 = {:g} m)", t, L1, L2);
    return false;
  }
  const Vec3 u1 = d1 / L1, u2 = d2 / L2;
  // T1 = κ T2 from the kinetic law at ψ^(k), sliding sense from the backward difference of L1.
  const double ds = L1 - L1_prev_;
  const double sigma = ds > 0.0 ? 1.0 : (ds < 0.0 ? -1.0 : 0.0);
  const double kappa = physics::tension_ratio(m_.layers.friction_law, physics::sliding_mu(m_),
                                              physics::deflection(u1, u2), sigma);
  const Vec3 gz(0, 0, p_.gravity);
  const Vec3 p1 = central_step(q1_, q1_prev_, -p_.bead_mass * gz, p_.bead_mass, p_.drag, h_, drag_);
  const Vec3 p2 = central_step(q2_, q2_prev_, -p_.ball_mass * gz, p_.ball_mass, p_.drag, h_, drag_);
  const Vec3 b1 = (h_ * h_ / p_.bead_mass) * (u2 - kappa * u1), b2 = -(h_ * h_ / p_.ball_mass) * u2;
  const std::optional<double> T2 = solve_tension(a_next, p1, p2, b1, b2, p_.string_length, T2_);
  if (!T2) {
    failure_ = fmt::format("at t = {:.6f} s no tension puts the next step on L1 + L2 = l (eq. 29)", t);
    return false;
  }
  T2_ = *T2;
  T1_ = kappa * T2_;
  q1_next_ = p1 + T2_ * b1;
  q2_next_ = p2 + T2_ * b2;
  L1_prev_ = L1;
  if (!q1_next_.allFinite() || !q2_next_.allFinite()) {
    failure_ = fmt::format("at t = {:.6f} s the positions are no longer finite", t);
    return false;
  }
  return true;
}

void PaperRun::diagnose(double t) {
  top_ = sched_.top(t);
  const double h2 = h_ * h_;
  const Vec3 v1 = (q1_next_ - q1_prev_) / (2 * h_), v2 = (q2_next_ - q2_prev_) / (2 * h_);
  dyn_.g = physics::geometry(top_, q1_, q2_, v1, v2);
  dyn_.T1 = T1_;
  dyn_.T2 = T2_;
  dyn_.pull = T1_;
  dyn_.contact = 0.0;
  dyn_.margins = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  dyn_.acc1 = (q1_next_ - 2 * q1_ + q1_prev_) / h2;
  dyn_.acc2 = (q2_next_ - 2 * q2_ + q2_prev_) / h2;
  dyn_.motor_power = -T1_ * dyn_.g.u1.dot(top_.a_dot);
  dyn_.drag_power = p_.drag * (v1.squaredNorm() + v2.squaredNorm());
  dyn_.friction_power = (T1_ - T2_) * dyn_.g.L1_dot;
  dyn_.couple_power = 0.0;
  // Work integrals: trapezoidal sums of the powers at the steps.
  const double P[3] = {dyn_.motor_power, dyn_.drag_power, dyn_.friction_power};
  for (int i = 0; i < 3; ++i) {
    if (have_prev_powers_) y_(idx::motor_work + i) += 0.5 * h_ * (powers_prev_[i] + P[i]);
    powers_prev_[i] = P[i];
  }
  have_prev_powers_ = true;
  y_.segment<3>(idx::r1) = q1_;
  y_.segment<3>(idx::r2) = q2_;
  y_.segment<3>(idx::v1) = v1;
  y_.segment<3>(idx::v2) = v2;
  watches_[0].see(t, std::min(T1_, T2_));
  watches_[1].see(t, dyn_.g.L2 - p_.contact_distance);
  watches_[2].see(t, dyn_.g.L1 - p_.top_stop);
}

RunSummary PaperRun::run(const PairStart& pair, double t_end, double sample_dt, const SampleObserver& on_sample,
                         physics::State& end, double omega_window) {
  RunSummary sum;
  q1_prev_ = pair.r1_0;
  q2_prev_ = pair.r2_0;
  q1_ = pair.r1_1;
  q2_ = pair.r2_1;
  L1_prev_ = (pair.r1_0 - sched_.top(pair.t0).a).norm();
  // A first guess for the tension: the weight below the bead.
  T2_ = p_.ball_mass * p_.gravity;
  const double t1 = pair.t0 + h_;
  const double window = std::min(omega_window, 0.5 * (t_end - t1));
  MeanAzimuth az;
  az.reset(q1_, q2_);
  double theta_window = 0.0;
  bool window_started = false;
  double t_window = t_end - window;
  long next_sample = 0;
  physics::State begin;
  end = physics::State{};
  end.contact = kTaut;
  sum.min_tension = std::numeric_limits<double>::infinity();
  sum.min_friction_power = std::numeric_limits<double>::infinity();
  const physics::Contact contact = kTaut;
  long k = 1;
  for (;; ++k) {
    const double t = pair.t0 + double(k) * h_;
    if (t > t_end + 0.5 * h_) break;
    const Vec3 a = sched_.top(t).a, a_next = sched_.top(t + h_).a;
    bool ok = false;
    try {
      ok = step(t, a, a_next);
    } catch (const std::domain_error& e) {
      failure_ = fmt::format("the friction law failed at t = {:.6f} s: {}", t, e.what());
    }
    if (!ok) break;
    diagnose(t);
    ++sum.steps;
    sum.max_drift = std::max(sum.max_drift, std::abs(length_excess(a_next, q1_next_, q2_next_, p_.string_length)));
    if (k > 1) az.advance(q1_, q2_);
    if (!window_started && t >= t_window - 0.5 * h_) {
      theta_window = az.theta;
      t_window = t;
      window_started = true;
    }
    sum.min_tension = std::min({sum.min_tension, T1_, T2_});
    sum.min_friction_power = std::min(sum.min_friction_power, dyn_.friction_power);
    end.t = t;
    end.y = y_;
    if (k == 1) begin = end;
    const bool due = sample_dt > 0.0 && t >= pair.t0 + double(next_sample) * sample_dt - 1e-9 * h_;
    if (due || k == 1) {
      if (on_sample) on_sample(Sample{t, contact, y_, dyn_, top_, 0.0});
      while (sample_dt > 0.0 && pair.t0 + double(next_sample) * sample_dt <= t + 1e-9 * h_) ++next_sample;
    }
    q1_prev_ = q1_;
    q2_prev_ = q2_;
    q1_ = q1_next_;
    q2_ = q2_next_;
  }
  sum.failure = failure_;
  sum.status = failure_.empty() ? numerics::IntegrateStatus::Reached : numerics::IntegrateStatus::Stopped;
  sum.t_end = end.t;
  sum.max_sample_drift = sum.max_drift;
  for (const Watch& w : watches_) sum.violations.push_back(w.v);
  if (sum.steps > 0) sum.energy = physics::energy_balance(p_, begin, end);
  if (window_started && end.t > t_window) sum.omega_ball = (az.theta - theta_window) / (end.t - t_window);
  if (!std::isfinite(sum.min_tension)) sum.min_tension = 0.0;
  if (!std::isfinite(sum.min_friction_power)) sum.min_friction_power = 0.0;
  return sum;
}

}  // namespace

RunSummary run_paper_scheme(const physics::Model& model, const physics::MotorSchedule& schedule, PaperDrag drag,
                            double h, const PairStart& pair, double t_end, double sample_dt,
                            const SampleObserver& on_sample, physics::State& end, double omega_window) {
  if (!(h > 0.0)) throw std::invalid_argument("the paper's scheme needs a step h > 0");
  PaperRun run(model, schedule, drag, h);
  return run.run(pair, t_end, sample_dt, on_sample, end, omega_window);
}

}  // namespace ajx::sim
