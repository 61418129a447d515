// The hand-written peer's model: the Astrojax equations in the axes turning with the motor,
// written from the equations alone as a user of an ODE library would write them (12 doubles,
// fixed-size vectors, no calls into the project's physics). The project's default model only:
// capstan stick-slip friction, the bottom and top stops; a slack string ends the run.
//
// State y = (r1, r2, v1, v2): positions in the rotating axes, velocities the lab velocities
// written in the rotating axes. The top sits at a = (R, 0, 0) with ȧ = (0, Rω, 0) and
// ä = (−Rω², Rω̇, 0); ṙ = v − ω ẑ×r and v̇ = acc − ω ẑ×v.
// Forces: d1 = r1 − a, d2 = r2 − r1, u_i = d_i/L_i, w1 = v1 − ȧ, w2 = v2 − v1,
// q_i = (|w_i|² − (u_i·w_i)²)/L_i, c = u1·u2, f_i = −c_D v_i − m_i g ẑ.
//  - held (stuck, on the bottom ball, at the top): L1 and L2 fixed, the net pulls F1, F2 from
//    [1/m1, −c/m1; −c/m1, 1/m1 + 1/m2] F = (u1·f1/m1 − u1·ä + q1, u2·f2/m2 − u2·f1/m1 + q2);
//  - sliding in direction σ (+1 down the string): T1 = κ T2, κ = exp(μ_k ψ σ), ψ = angle(u1, u2),
//    T2 = (u1·(f1/m1 − ä) + u2·(f2/m2 − f1/m1) + q1 + q2) / ((1 − c)(1 + κ)/m1 + 1/m2).
//  acc1 = (−F1 u1 + F2 u2 + f1)/m1, acc2 = (−F2 u2 + f2)/m2.
#pragma once
#include <Eigen/Core>
#include <array>
#include <vector>

namespace ajx::hand {

using Y = std::array<double, 12>;
using V3 = Eigen::Vector3d;

struct Params {
  double l, m1, m2, cD, mu_s, mu_k, g, R, d, s_min;
  // ω_m(t): segments starting at t_begin with ω_begin and rate ω̇; past the last, ω held.
  struct Segment {
    double t_begin, omega_begin, rate, duration;
  };
  std::vector<Segment> drive;
  void omega(double t, double& w, double& wd) const;
};

enum class Mode { Sliding, Bottom, Stuck, Top };

struct Contact {
  Mode mode = Mode::Stuck;
  int sigma = 0;       // sliding direction (+1: L1 grows)
  double s_star = 0;   // L1 while stuck
};

// The forces of a mode at (t, y): what the RHS and the guards need.
struct Forces {
  V3 u1, u2;
  double L1, L2, L1_dot, psi, F1, F2;  // F: the net pulls of the links on the bead
  double T1, T2;                       // tensions (differ from F at a stop)
  double margin_up, margin_down;       // the μ_s cone: T1 − e^{−μ_s ψ} T2, e^{μ_s ψ} T2 − T1
  V3 acc1, acc2;
  double omega;
};
Forces forces(const Params& p, const Contact& c, double t, const double* y, bool cone);

// ẏ in the rotating axes; counts nothing, allocates nothing.
void rhs(const Params& p, const Contact& c, double t, const double* y, double* dydt);

// The guards of a mode, each falling through zero at its switch (the project's: LandBottom,
// LandTop, Rest, SlipUp, SlipDown, Slacken). Returns how many; g[i] the values.
int guards(const Params& p, const Contact& c, double t, const double* y, double* g);

// The mode after guard i of c fired at (t, y): the bead slips, lands (an inelastic impact on
// the ball, applied to y) or comes to rest (stuck if the μ_s cone holds it). Returns false on a
// slack string (not modelled).
bool switch_mode(const Params& p, Contact& c, int guard, double t, double* y);

// The rate Ω of the guards (the project's step bound h ≤ (k+1)/Ω): the top turning about the
// balls and the swing of the shorter link.
double guard_rate(const Params& p, double t, const double* y);

// Newton projection of positions onto the mode's constraints, then of the velocities, along
// M⁻¹Jᵀ (skipped when |C| < tol).
void project(const Params& p, const Contact& c, double t, double* y, double tol);

}  // namespace ajx::hand
