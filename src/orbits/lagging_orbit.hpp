// The lagging circular orbit of the tie-clutch layer (physics/tie.hpp) as a relative
// equilibrium. While the tie slips forward (σ = +1, ω_m > χ̇) the motor enters only through
// the clutch torque
//   τ = τ_k + c_a (ω_m − ω_b),
// so in the frame turning with the tie at ω_b = χ̇ the top sits still at (R, 0, 0) and so do
// the balls: the locked-orbit balance of steady_orbit.hpp at ω = ω_b, closed by the tie's
// steady equation I_a χ̈ = 0,
//   τ + R (ê_χ·u1) F1 = 0,
// which at the equilibrium is the balls' angular-momentum balance about z:
//   τ = c_D ω_b (ρ1² + ρ2²)        (the drag torque of the circle).
// With the bead stuck at s that is one equation in ω_b along the stuck family at s.
//
// Stability: the frame dynamics of q = (q1, q2, θ), θ = χ − ω_b t the tie's azimuth in the
// frame, with the tie's χ̈ solved as physics::top_kinematics solves it, linearised and
// restricted to the constraint manifold {|q1 − a(θ)| = s, |q2 − q1| = l − s} (5 degrees of
// freedom). Turning all of (q1, q2, θ) about z is a symmetry (the clutch's torque does not
// depend on χ), so one eigenvalue is exactly zero; it is factored out and the other nine decide.
// Their leading pair crossing Re λ = 0 as τ grows is the Hopf point τ_H where the lag turns
// into a flower (docs/reports/reproduction-evidence.md, "ω2 and the flower orbits").
#pragma once
#include <Eigen/Core>
#include <vector>

#include "orbits/steady_orbit.hpp"

namespace ajx::orbits {

// τ = −R (ê_χ·u1) F1 that the tie passes to the string on the orbit o (top at (R, 0, 0),
// ê_χ = ŷ) [N m]: at an equilibrium, c_D ω (ρ1² + ρ2²).
double tie_drive_torque(const physics::Model& m, const SteadyOrbit& o);

// |Δp1| + |Δp2| between two orbits' positions [m]: how far apart two points of the family are.
double separation(const SteadyOrbit& a, const SteadyOrbit& b);

// Whether o lies on a branch continued in ω (points in order along it, each with an `orbit`):
// two neighbours bracket o's ω, and their positions, interpolated linearly to it, lie within
// 1e-3 l of o's (the interpolation's error over a continuation step is far smaller; another
// branch at the same ω lies farther, except where branches cross).
template <class Point>
bool on_branch(const std::vector<Point>& path, const SteadyOrbit& o, double string_length) {
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const SteadyOrbit &a = path[i].orbit, &b = path[i + 1].orbit;
    if ((a.omega - o.omega) * (b.omega - o.omega) > 0.0) continue;
    const double t = b.omega != a.omega ? (o.omega - a.omega) / (b.omega - a.omega) : 0.0;
    const Vec3 p1 = a.p1 + t * (b.p1 - a.p1), p2 = a.p2 + t * (b.p2 - a.p2);
    if ((p1 - o.p1).norm() + (p2 - o.p2).norm() < 1e-3 * string_length) return true;
  }
  return false;
}

// The clutch torque τ_k + c_a (ω_m − ω_b) at a lag of rate ω_b [N m].
double clutch_torque(const physics::Model& m, double omega_m, double omega_ball);

// The motor speed of a lag of rate ω_b passing τ: ω_m = ω_b + (τ − τ_k)/c_a [rad/s]; NaN where no
// ω_m > ω_b gives τ with the tie slipping forward (τ < τ_k, or c_a = 0).
double lag_motor_speed(const physics::Model& m, double omega_b, double torque);

struct LagStability {
  Eigen::VectorXcd eigenvalues;  // the nine that remain, largest real part first [1/s]
  double symmetry_eigenvalue = 0;  // the factored-out one, zero up to the differences' error [1/s]
  double growth = 0.0;             // max Re λ [1/s]
  double frequency = 0.0;          // |Im λ| of that eigenvalue [rad/s]
  bool stable = false;             // growth below the differences' noise (growth_noise)
};

// Linear stability of the lag o (an orbit of the stuck family at ω = ω_b) with the tie slipping
// forward. The motor speed drops out: the clutch's torque depends on χ̇ only through −c_a χ̇.
LagStability lag_stability(const physics::Model& m, const SteadyOrbit& o);

struct LagOrbit {
  SteadyOrbit orbit;      // at ω = ω_b (orbit.omega), positions in the frame turning with the tie
  double omega_m = 0.0;   // the motor speed it belongs to [rad/s]
  double torque = 0.0;    // τ the tie passes [N m]
  LagStability st;
};

struct LagSearch {
  double omega_lo = 0.0, omega_hi = 0.0;  // interval of ω_b searched [rad/s]; 0, 0: 0.1 ω_m .. ω_m
  bool stability = true;
};

// Every lag with the bead stuck at s for motor speed ω_m: the roots ω_b < ω_m of
//   c_D ω_b (ρ1² + ρ2²) = τ_k + c_a (ω_m − ω_b)
// along each branch of the stuck family at s (continued in ω from the planar guesses), sorted
// by ω_b. Orbits outside the static cone are returned too (orbit.admissible says which hold).
std::vector<LagOrbit> lag_orbits(const physics::Model& m, double s, double omega_m, const LagSearch& opt = {});

// Along one branch of the stuck family at s: the branch through `start` continued in ω_b over
// [omega_lo, omega_hi], each point a lag (its τ from the balance above, ω_m = ω_b + (τ − τ_k)/c_a
// where that exceeds ω_b, else NaN), and the events along it, located by bisection in ω_b:
enum class LagEventKind { StabilityLoss, StabilityGain, ConeExit, ConeEntry };
struct LagEvent {
  LagEventKind kind;       // as τ (and ω_b) grow along the branch
  LagOrbit at;
  bool complex_pair = false;  // the crossing eigenvalue has Im λ != 0 (a Hopf point)
};
struct LagBranch {
  std::vector<LagOrbit> points;  // in order of ω_b along the branch
  std::vector<LagEvent> events;
};
LagBranch lag_branch(const physics::Model& m, const SteadyOrbit& start, double omega_lo, double omega_hi);

}  // namespace ajx::orbits
