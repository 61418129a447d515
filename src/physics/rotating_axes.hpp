// The equations in axes turning with the motor (docs/physics/model.md, "Drive"): each vector of the lab
// state is expressed in axes rotated by the motor phase φ(t) about z,
//   r' = Rz(−φ) r,   v' = Rz(−φ) v   (v the lab velocity, not the velocity seen in the frame).
// The top then sits at a' = (R, 0, 0), ȧ' = R ω ŷ, ä' = R ω̇ ŷ − R ω² x̂: no sin/cos, and a
// locked circular orbit is a fixed point, so an adaptive method takes steps set by the slow
// dynamics about the orbit rather than by the drive period. With Ω = ω_m ẑ,
//   ṙ' = v' − Ω×r',   v̇' = r̈'_lab − Ω×v',
// where r̈'_lab is physics::evaluate at the rotated top (gravity along z, drag on v, the string
// and the friction law are all invariant under rotations about z). Guards, projections and
// energies therefore take (top', y') unchanged. Only ω and ω̇ depend on t.
#pragma once
#include "numerics/vector.hpp"
#include "physics/astrojax_system.hpp"

namespace ajx::physics {

// The top at time t seen in the turning axes: phi = 0, a' = (R, 0, 0).
TopKinematics top_in_rotating_axes(const MotorSchedule& schedule, double t);

// dy'/dt for the state in turning axes (layout of idx; the three work integrals are the lab
// ones, which are invariant).
void rhs_in_rotating_axes(const Model& m, const MotorSchedule& schedule, const Contact& c, double t,
                          const numerics::Vec& y, numerics::Vec& dydt);

// y <- Rz(angle) y on the positions and velocities of both balls (the work integrals stay).
// Lab to turning axes: angle = −φ(t); back: angle = +φ(t).
void rotate_about_z(numerics::Vec& y, double angle);

}  // namespace ajx::physics
