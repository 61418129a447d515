// Contact modes of the string and bead: the geometry of the two segments, the tensions
// solved from the acceleration-level constraints, projection onto the constraint manifold,
// plastic impacts, and the conditions that end a mode (docs/physics/model.md, "String, bead and
// forces").
#pragma once
#include <Eigen/Core>

#include "physics/drive.hpp"
#include "physics/model.hpp"
#include "physics/state.hpp"

namespace ajx::physics {

// The two string segments d1 = r1 - a, d2 = r2 - r1 and their rates.
struct Geometry {
  double L1, L2;      // segment lengths [m]; s = L1
  Vec3 u1, u2;        // unit vectors along d1, d2
  Vec3 w1, w2;        // ḋ1 = v1 - ȧ, ḋ2 = v2 - v1 [m/s]
  double L1_dot;      // ṡ = u1·w1 [m/s]
  double L2_dot;      // u2·w2 [m/s]
  double q1, q2;      // |w⊥|²/L: the velocity part of L̈1, L̈2 [m/s²]
  double cos_psi;     // u1·u2
  double psi;         // ψ, deflection of the string at the bead [rad] (NaN when not asked for)
};
// with_psi = false skips ψ (an atan2): the equations of motion of the two-link modes do not
// need it, only their friction cones do.
Geometry geometry(const TopKinematics& top, const Vec3& r1, const Vec3& r2, const Vec3& v1,
                  const Vec3& v2, bool with_psi = true);

// Applied forces other than the string: f_i = -c_D v_i - m_i g ẑ.
struct AppliedForces {
  Vec3 f1, f2;  // [N]
};
AppliedForces applied_forces(const Parameters& p, const Vec3& v1, const Vec3& v2);

// Taut, sliding: T1 = κ T2 and L̈1 + L̈2 = 0 give
//   T2 [(1 - cos ψ)(1 + κ)/m1 + 1/m2] = u1·(f1/m1 - ä) + u2·(f2/m2 - f1/m1) + q1 + q2.
// The bracket is positive for κ > -1: the solve is well posed for every ψ.
double sliding_tension_T2(const Parameters& p, const Geometry& g, const AppliedForces& f,
                          const Vec3& a_ddot, double kappa);

// Two rigid links (bead on the bottom stop, or stuck on the string): L̈1 = L̈2 = 0 give
//   [ 1/m1      -cos ψ/m1     ] [T1]   [ u1·f1/m1 - u1·ä + q1      ]
//   [ -cos ψ/m1  1/m1 + 1/m2  ] [F2] = [ u2·f2/m2 - u2·f1/m1 + q2  ]
// with F2 the net pull of link 2 (its tension minus any contact push). det > 0 always.
Eigen::Vector2d two_link_forces(const Parameters& p, const Geometry& g, const AppliedForces& f,
                                const Vec3& a_ddot);

// Margins of the friction cone κ_lo <= T1/T2 <= κ_hi, written without division:
//   up   = T1 - κ_lo T2   (< 0: the bead slips up, ṡ < 0)
//   down = κ_hi T2 - T1   (< 0: the bead slips down, ṡ > 0)
// At the bottom stop only `up` applies, with T2 the link force F2 (the cone is one-sided).
struct ConeMargins {
  double up;    // [N]
  double down;  // [N]
};
ConeMargins cone_margins(const Model& m, const Geometry& g, double T1, double T2);

// L1 held fixed by a two-link mode: l - d on the bottom ball, s_min at the top, s* stuck.
double held_length(const Model& m, const Contact& c);

// Position and velocity constraints of a mode, C(r) = 0 and J v = b (b from the moving top).
struct Constraints {
  int n = 0;                          // number of active constraints (0 slack, 1 sliding, 2)
  Eigen::Matrix<double, 2, 6> J;      // ∂C/∂(r1, r2)
  Eigen::Vector2d C;                  // position residual [m]
  Eigen::Vector2d b;                  // J v must equal b [m/s]
};
Constraints constraints(const Model& m, const Contact& c, const TopKinematics& top, const numerics::Vec& y);

// Largest position and velocity residual of the mode's constraints.
struct Drift {
  double position;  // [m]
  double velocity;  // [m/s]
};
Drift constraint_drift(const Model& m, const Contact& c, const TopKinematics& top, const numerics::Vec& y);

// Mass-weighted projection of positions (Newton iterations) and then velocities onto the
// mode's constraint manifold: Δx = -M⁻¹Jᵀ (J M⁻¹ Jᵀ)⁻¹ C. The velocity part is also the
// impact onto a new constraint set: the impulse M Δv = -Jᵀλ, λ = (1 + e)(JM⁻¹Jᵀ)⁻¹(J v - b),
// reverses the approach velocity J v - b times the restitution e (0: plastic).
struct ProjectionEnergy {
  double dissipated = 0.0;   // energy lost in the impact, ½(1 - e²)(Jv-b)ᵀA⁻¹(Jv-b) [J]
  double motor_work = 0.0;   // -λᵀ b, work done by the moving top during the impulse [J]
};
void project_positions(const Model& m, const Contact& c, const TopKinematics& top, numerics::Vec& y);
ProjectionEnergy project_velocities(const Model& m, const Contact& c, const TopKinematics& top,
                                    numerics::Vec& y, double restitution = 0.0);

// Collisions of a slack string's bead, as one-constraint impacts with restitution e:
// with the bottom ball along u2 (L̇2 reversed), or with the top along u1 (L̇1 reversed).
ProjectionEnergy collide_with_ball(const Model& m, numerics::Vec& y, double restitution);
ProjectionEnergy collide_with_top(const Model& m, const TopKinematics& top, numerics::Vec& y,
                                  double restitution);

}  // namespace ajx::physics
