// Locked circular orbits as equilibria of the co-rotating frame (corotating_frame.hpp).
// The top sits at a = (R, 0, 0); the balls sit still at p1, p2 with lab velocity Ω×p and
// acceleration −ω² P p, so the equations of motion become the algebraic balance
//   −m1 ω² P p1 = −F1 u1 + F2 u2 − c_D Ω×p1 − m1 g ẑ
//   −m2 ω² P p2 =         −F2 u2 − c_D Ω×p2 − m2 g ẑ
//   |p1 − a| = s,   |p2 − p1| = l − s,
// eight equations in X = (p1, p2, F1, F2, s), closed by one more (the closure):
//   Stuck         s = s*                    (a family in s*; the static cone decides which hold)
//   BottomStop    s = l − d                 (the bead rests on the ball: F2 = T2 − N_c)
//   Frictionless  F1 = F2                   (T1 = T2: the orbits of the frictionless model)
//   ConeUp        F1 = κ_lo(ψ) F2           (the edge where a stuck bead starts to slide up)
//   ConeDown      F1 = κ_hi(ψ) F2           (the edge where it starts to slide down)
// F1, F2 are the net pulls of the two links (T1, T2 except at a stop).
#pragma once
#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>

#include "physics/contact_modes.hpp"
#include "physics/model.hpp"
#include "physics/state.hpp"

namespace ajx::orbits {

using physics::Vec3;
using Vec9 = Eigen::Matrix<double, 9, 1>;
using Mat9 = Eigen::Matrix<double, 9, 9>;

enum class Closure { Stuck, BottomStop, Frictionless, ConeUp, ConeDown };
std::string_view to_string(Closure c);

struct OrbitProblem {
  physics::Model model;
  double omega = 0.0;           // ω_m [rad/s]
  Closure closure = Closure::Stuck;
  double s_star = 0.0;          // L1 held by Closure::Stuck [m]
};

// Scales that make the unknowns and equations O(1): lengths by l, forces by W = (m1 + m2) g.
struct Scales {
  double length;  // l [m]
  double force;   // (m1 + m2) g [N]
};
Scales scales(const physics::Model& m);

// X = (p1, p2, F1, F2, s) in SI units; the residual is scaled (forces / W, lengths / l).
Vec9 residual(const OrbitProblem& pb, const Vec9& X);
// ∂residual/∂X by central differences (steps ε^(1/3) of each unknown's scale).
Mat9 jacobian(const OrbitProblem& pb, const Vec9& X);

struct NewtonOptions {
  int max_iterations = 60;
  double tolerance = 0.0;  // on max|residual|; 0: 8 ε (1 + ω² l / g), the round-off floor
};
struct NewtonResult {
  Vec9 X;
  double residual = 0.0;   // max |scaled residual|
  int iterations = 0;
  bool converged = false;
};
// Damped Newton with a rank-revealing solve (R = 0 leaves the azimuth free).
NewtonResult solve(const OrbitProblem& pb, Vec9 X0, const NewtonOptions& opt = {});
double default_tolerance(const OrbitProblem& pb);

// Everything a user wants to know about one orbit.
struct SteadyOrbit {
  Closure closure = Closure::Stuck;
  double omega = 0.0;          // ω_m [rad/s]
  Vec3 p1, p2;                 // positions in the frame, top at (R, 0, 0) [m]
  double s = 0.0;              // L1, the bead's position along the string [m]
  double rho1 = 0, z1 = 0;     // bead: distance from the motor axis, height [m]
  double rho2 = 0, z2 = 0;     // bottom ball [m]
  double phase1 = 0, phase2 = 0;  // azimuth of each ball relative to the top, in (−π, π] [rad]
  double F1 = 0, F2 = 0;       // net pulls of the links [N]
  double T1 = 0, T2 = 0;       // tensions [N] (at the bottom stop: T2 as physics::evaluate picks it)
  double contact = 0;          // push N_c of the bottom ball on the bead [N] (BottomStop)
  double psi = 0;              // deflection ψ at the bead [rad]
  double mu_required = 0;      // least μ whose cone holds T1/T2 (capstan: |ln(T1/T2)|/ψ)
  physics::ConeMargins margins{};  // of the static cone [N] (BottomStop: only `up` applies)
  bool taut = false;           // T1 > 0, T2 > 0
  bool in_range = false;       // s_min <= s <= l − d (the stops allow it)
  bool admissible = false;     // taut, in range, and inside the static cone
  std::string branch;          // "+/+", "−/+": sides of the bead / ball relative to the top (x > 0)
  double residual = 0;         // max |scaled residual|
};
SteadyOrbit describe(const OrbitProblem& pb, const Vec9& X);

// The contact mode in which the simulator holds this orbit (stuck at s, on the bottom stop,
// or sliding with σ = 0 in a model without a stuck mode).
physics::Contact holding_contact(const physics::Model& m, Closure c, double s);

}  // namespace ajx::orbits
