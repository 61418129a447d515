// The drive: the top of the string on a circle of radius R, a(t) = R (cos φ, sin φ, 0),
// dφ/dt = ω_m(t) from a schedule of holds and linear ramps.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products
#include <optional>
#include <string>
#include <vector>

#include "physics/hand.hpp"

namespace ajx::physics {

using Vec3 = Eigen::Vector3d;

// One piece of the motor schedule: ω_m goes linearly from omega_begin to omega_end over
// duration (a hold has omega_begin == omega_end).
struct DriveSegment {
  double omega_begin;  // ω_m at the segment's start [rad/s]
  double omega_end;    // ω_m at its end [rad/s]
  double duration;     // [s], > 0
};

// Top position and its derivatives at one instant.
struct TopKinematics {
  double phi;        // φ [rad]
  double omega;      // ω_m = dφ/dt [rad/s]
  double omega_dot;  // dω_m/dt [rad/s²]
  Vec3 a;            // a(t) [m]
  Vec3 a_dot;        // ȧ = R ω (-sin φ, cos φ, 0) [m/s]
  Vec3 a_ddot;       // ä = R ω̇ (-sin φ, cos φ, 0) - R ω² (cos φ, sin φ, 0) [m/s²]
  // The motor's own ω_m and ω̇_m: equal to omega and omega_dot unless the tie slips on the rod
  // (physics/tie.hpp), when φ, ω above are the tie's χ, χ̇.
  double motor_omega;
  double motor_omega_dot;
  bool hand = false;  // a hand holds the top (physics/hand.hpp): a and its rates are x_top's, not on the circle
};

// A point turning on the circle of radius R at phase φ with rate ω and acceleration ω̇:
// a = R ê_r, ȧ = R ω ê_φ, ä = R ω̇ ê_φ − R ω² ê_r (ê_r = (cos φ, sin φ, 0), ê_φ = (−sin φ, cos φ, 0)).
// motor_omega(_dot) are set to ω (ω̇): the motor's own, unless the caller says otherwise.
TopKinematics point_on_circle(double R, double phi, double omega, double omega_dot);

// The motor: its schedule of ω_m and the radius R of the circle it turns the top on, held
// together so that no caller pairs them by hand. R is the model's drive_radius (the Simulation
// refuses a schedule whose R is not its model's).
class MotorSchedule {
 public:
  MotorSchedule() = default;
  // Throws std::invalid_argument for an empty schedule, a segment with duration <= 0, or R < 0.
  MotorSchedule(double drive_radius, std::vector<DriveSegment> segments, double phi0 = 0.0);

  double duration() const { return t_begin_.empty() ? 0.0 : t_begin_.back() + segs_.back().duration; }
  const std::vector<DriveSegment>& segments() const { return segs_; }
  // Segment start times; ω̇ jumps there, so integrators stop on them.
  const std::vector<double>& breakpoints() const { return t_begin_; }

  // φ, ω, ω̇ at time t (t beyond the end holds the last ω).
  void phase(double t, double& phi, double& omega, double& omega_dot) const;
  double radius() const { return radius_; }  // R [m]
  // a(t) = R (cos φ, sin φ, 0) and its derivatives; x_top(t) while a hand holds the top.
  TopKinematics top(double t) const;

  // The hand that holds the top for 0 <= t < T before the motor takes it (physics/hand.hpp).
  // Throws std::invalid_argument unless T > 0 is the start of a segment or the schedule's end
  // (the acceleration jumps at T, so integrators must stop there).
  void set_hand(HandPath hand);
  const HandPath* hand() const { return hand_ ? &*hand_ : nullptr; }
  // k (the top on the circle at t) moved to x_top(t) while the hand holds it.
  void add_hand(double t, TopKinematics& k) const {
    if (!hand_ || !hand_->holds(t)) return;
    const HandOffset o = hand_->offset(t);
    k.a += o.d, k.a_dot += o.d_dot, k.a_ddot += o.d_ddot, k.hand = true;
  }

 private:
  double radius_ = 0.0;            // R [m]
  std::vector<DriveSegment> segs_;
  std::vector<double> t_begin_;    // [s]
  std::vector<double> phi_begin_;  // φ at each segment start [rad]
  std::vector<double> rate_;       // ω̇ = (ω_end − ω_begin)/duration of each segment [rad/s²]
  std::optional<HandPath> hand_;
};

}  // namespace ajx::physics
