#include "physics/drive.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ajx::physics {

MotorSchedule::MotorSchedule(double drive_radius, std::vector<DriveSegment> segments, double phi0)
    : radius_(drive_radius), segs_(std::move(segments)) {
  if (!(radius_ >= 0.0)) throw std::invalid_argument("motor schedule: drive radius R < 0 or not a number");
  if (segs_.empty()) throw std::invalid_argument("motor schedule is empty");
  double t = 0.0, phi = phi0;
  for (const auto& s : segs_) {
    if (!(s.duration > 0.0)) throw std::invalid_argument("motor schedule segment has duration <= 0");
    t_begin_.push_back(t);
    phi_begin_.push_back(phi);
    rate_.push_back((s.omega_end - s.omega_begin) / s.duration);  // once here, not at every evaluation
    // φ advances by the mean ω over a linear ramp.
    phi += 0.5 * (s.omega_begin + s.omega_end) * s.duration;
    t += s.duration;
  }
}

void MotorSchedule::phase(double t, double& phi, double& omega, double& omega_dot) const {
  // The last segment whose start is <= t (the first one for t < 0).
  std::size_t k = 0;
  if (t_begin_.size() > 1) {
    auto it = std::upper_bound(t_begin_.begin(), t_begin_.end(), t);
    k = it == t_begin_.begin() ? 0 : std::size_t(it - t_begin_.begin()) - 1;
  }
  const DriveSegment& s = segs_[k];
  const double tau = t - t_begin_[k];
  if (tau <= s.duration) {
    omega_dot = rate_[k];
    omega = s.omega_begin + omega_dot * tau;
    phi = phi_begin_[k] + s.omega_begin * tau + 0.5 * omega_dot * tau * tau;
  } else {  // past the end: hold the final ω
    omega_dot = 0.0;
    omega = s.omega_end;
    phi = phi_begin_[k] + 0.5 * (s.omega_begin + s.omega_end) * s.duration +
          s.omega_end * (tau - s.duration);
  }
}

TopKinematics point_on_circle(double R, double phi, double omega, double omega_dot) {
  TopKinematics k;
  k.phi = phi;
  k.omega = omega;
  k.omega_dot = omega_dot;
  const double c = std::cos(phi), s = std::sin(phi);
  const Vec3 radial(c, s, 0.0), tangential(-s, c, 0.0);
  k.a = R * radial;
  k.a_dot = R * omega * tangential;
  k.a_ddot = R * omega_dot * tangential - R * omega * omega * radial;
  k.motor_omega = omega;
  k.motor_omega_dot = omega_dot;
  return k;
}

TopKinematics MotorSchedule::top(double t) const {
  double phi, omega, omega_dot;
  phase(t, phi, omega, omega_dot);
  TopKinematics k = point_on_circle(radius_, phi, omega, omega_dot);
  add_hand(t, k);
  return k;
}

void MotorSchedule::set_hand(HandPath hand) {
  const double T = hand.duration, tol = 1e-12 * std::max(1.0, T);
  if (!(T > 0.0)) throw std::invalid_argument("hand: duration T <= 0 or not a number");
  bool at_break = std::abs(T - duration()) <= tol;
  for (double tb : t_begin_) at_break = at_break || std::abs(T - tb) <= tol;
  if (!at_break) throw std::invalid_argument("hand: its end T is not a breakpoint of the motor's schedule");
  hand_ = std::move(hand);
}

}  // namespace ajx::physics
