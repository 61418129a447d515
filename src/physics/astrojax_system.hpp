// The equations of motion in one mode: r̈1 = (-T1 u1 + F2 u2 + f1)/m1, r̈2 = (-F2 u2 + f2)/m2,
// with the tensions from the mode's acceleration-level constraints; f_i are drag, gravity and
// the pair couple's forces when its layer is on. A pure function of
// (model, schedule, mode, t, y): no I/O, no globals.
#pragma once
#include "numerics/vector.hpp"
#include "physics/contact_modes.hpp"
#include "physics/drive.hpp"
#include "physics/model.hpp"
#include "physics/state.hpp"

namespace ajx::physics {

struct Dynamics {
  Geometry g;
  double T1;              // tension above the bead [N]
  double T2;              // tension below the bead [N]
  double pull;            // F1, the net pull of the upper link on the top (tension minus a top-stop push) [N]
  double contact;         // push of the stop on the bead (bottom ball or top), >= 0 [N]
  ConeMargins margins;    // friction-cone margins of the stuck or resting bead (+inf while sliding)
  Vec3 acc1, acc2;        // r̈1, r̈2 [m/s²]
  double motor_power;     // P_motor = -F1 u1·ȧ, F1 the net pull of link 1 [W]
  double drag_power;      // c_D (|v1|² + |v2|²) [W]
  double friction_power;  // (T1 - T2) ṡ [W], >= 0 whenever the tensions are
  double couple_power;    // F2·(v2 − v1) of the pair couple (physics/pair_couple.hpp), 0 without it [W];
                          // the string's side of the ledger integrates motor_power + couple_power
  double couple_loss;     // the couple's slip loss (physics/pair_couple.hpp), 0 without it [W]
};

// motion_only: what the equations of motion need (accelerations and powers); in the two-link
// modes the tensions are then the net pulls F1, F2, and ψ and the cone margins are NaN.
Dynamics evaluate(const Model& m, const TopKinematics& top, const Contact& c, const numerics::Vec& y,
                  bool motion_only = false);

// The motor's ledger rates beyond idx::dim (W_m, W_c; the tie's χ̇, χ̈ where y has them) at the
// top `top` with the dynamics `d` evaluated there.
void ledger_rates(const Model& m, const TopKinematics& top, const Contact& c, const Dynamics& d,
                  const numerics::Vec& y, numerics::Vec& dydt);

// dy/dt in the layout of idx (accelerations and the power quadratures).
void rhs(const Model& m, const MotorSchedule& schedule, const Contact& c, double t,
         const numerics::Vec& y, numerics::Vec& dydt);

}  // namespace ajx::physics
