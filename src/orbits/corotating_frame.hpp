// The frame that co-rotates with the motor at constant ω_m: the top sits still at
// a = (R, 0, 0) and a locked circular orbit is an equilibrium. With Ω = ω_m ẑ, lab and frame
// coordinates agree at φ = 0 (q = r, v = q̇ + Ω×q), and Newton's law in the frame reads
//   q̈ = r̈_lab − 2 Ω×q̇ + ω_m² P q,   P = diag(1, 1, 0),
// with r̈_lab from physics::evaluate (the mode's tensions, drag −c_D v on the lab velocity).
#pragma once
#include <Eigen/Core>

#include "numerics/vector.hpp"
#include "physics/drive.hpp"
#include "physics/model.hpp"
#include "physics/state.hpp"

namespace ajx::orbits {

using physics::Vec3;
using Vec12 = Eigen::Matrix<double, 12, 1>;  // (q1, q2, q̇1, q̇2) in the frame [m], [m/s]

// The top at φ = 0 turning at constant ω: a = (R, 0, 0), ȧ = R ω ŷ, ä = −R ω² x̂.
physics::TopKinematics corotating_top(double drive_radius, double omega);

// The lab state (layout of physics::idx, work integrals zero) of frame coordinates z at φ = 0,
// in a vector of length dim (the tie's χ, χ̇ beyond idx::dim left zero).
numerics::Vec lab_state(const Vec12& z, double omega, int dim = physics::idx::dim);

// dz/dt in the frame turning at ω from the lab accelerations r̈1, r̈2 at z:
//   q̈ = r̈ − 2 Ω×q̇ + ω² P q.
Vec12 frame_derivative(const Vec12& z, const Vec3& acc1, const Vec3& acc2, double omega);

// Frame coordinates of a lab state taken at motor phase φ: q = Rz(−φ) r, q̇ = Rz(−φ) v − Ω×q.
Vec12 frame_state(const numerics::Vec& y, double phi, double omega);

// dz/dt in the frame, in the contact mode c (autonomous: a pure function of z).
Vec12 corotating_rhs(const physics::Model& m, double omega, const physics::Contact& c, const Vec12& z);

}  // namespace ajx::orbits
