// The hand: before the motor takes the top of the string, a hand holds it and moves it about in
// the horizontal plane. For 0 <= t < T the top is
//   x_top(t) = a(t) + w(τ) h(τ),   τ = t/T,   w(τ) = sin²(πτ),
//   h(τ) = Σ_{k=1..K} (p_k cos 2πkτ + q_k sin 2πkτ),  p_k, q_k horizontal, |p_k|, |q_k| <= A/(2K),
// a(t) = R (cos φ, sin φ, 0) the motor's top (physics/drive.hpp), so |x_top − a| <= A. Since
// w(0) = ẇ(0) = w(1) = ẇ(1) = 0 the hand takes the top at a(0) with ȧ(0) and hands it over at T
// onto the motor's circle with x_top(T) = a(T), ẋ_top(T) = ȧ(T): position and velocity are
// continuous, the acceleration jumps by ẅ h (a breakpoint of the schedule). After T, x_top = a.
// The top's motion is prescribed either way, so the work it does, ∫ −F1 u1·ẋ_top dt, is W_m.
#pragma once
#include <Eigen/Core>
#include <vector>

namespace ajx::physics {

struct HandOffset {
  Eigen::Vector3d d, d_dot, d_ddot;  // w h [m], its rate [m/s] and acceleration [m/s²]
};

struct HandPath {
  double duration = 0.0;               // T [s]
  std::vector<Eigen::Vector3d> p, q;   // modes k = 1..K: cos and sin amplitudes [m], z = 0

  bool holds(double t) const { return t >= 0.0 && t < duration; }
  // x_top − a at time t (zero outside [0, T)).
  HandOffset offset(double t) const;
  // A bound on |ḋ| over [0, T): (π H0 + H1)/T, H0 = Σ (|p_k| + |q_k|) >= |h|, H1 = Σ 2πk (|p_k| + |q_k|) >= |h'| [m/s].
  double speed_bound() const;
};

}  // namespace ajx::physics
