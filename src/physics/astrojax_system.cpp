#include "physics/astrojax_system.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "physics/pair_couple.hpp"
#include "physics/string_friction.hpp"
#include "physics/tie.hpp"

namespace ajx::physics {

// flatten: the kernels of the other concept files are inlined into one body (the folder is one
// translation unit, src/physics/CMakeLists.txt), which lets their divisions and square roots overlap.
[[gnu::flatten]] Dynamics evaluate(const Model& m, const TopKinematics& top, const Contact& c,
                                   const numerics::Vec& y, bool motion_only) {
  const Parameters& p = m.p;
  const Vec3 r1 = y.segment<3>(idx::r1), r2 = y.segment<3>(idx::r2);
  const Vec3 v1 = y.segment<3>(idx::v1), v2 = y.segment<3>(idx::v2);
  constexpr double inf = std::numeric_limits<double>::infinity();
  Dynamics d;
  // ψ enters the motion only through the sliding law.
  const bool need_cone = !motion_only || c.mode == Mode::Sliding;
  d.g = geometry(top, r1, r2, v1, v2, need_cone);
  AppliedForces f = applied_forces(p, v1, v2);
  // The diagnostic pair couple (zero unless its layer is on) joins f_i in every mode, so the
  // tensions, the stops' pushes and the guards all see it.
  d.couple_power = d.couple_loss = 0.0;
  if (m.layers.pair_couple != PairCouple::None) {
    const PairCoupleForces couple = pair_couple_forces(m, top.motor_omega, r1, r2, v1, v2);
    f.f1 += couple.f1;
    f.f2 += couple.f2;
    d.couple_power = couple.power;
    d.couple_loss = couple.loss;
  }

  // F1, F2: the net pulls of the two links on the bead (tension minus any contact push).
  double F1 = 0.0, F2 = 0.0;
  d.contact = 0.0;
  d.margins = {inf, inf};
  switch (c.mode) {
    case Mode::Sliding: {
      // T1 = κ(ψ, σ) T2 with the mode's sliding direction σ and μ_k, or with μ(|ṡ|) tanh(ṡ/ε)
      // when regularised.
      const bool smooth = regularised(m);
      const double sigma = smooth ? regularised_sigma(m, d.g.L1_dot) : double(c.sigma);
      const double mu = smooth ? regularised_mu(m, d.g.L1_dot) : sliding_mu(m);
      const double kappa = tension_ratio(m.layers.friction_law, mu, d.g.psi, sigma);
      d.T2 = F2 = sliding_tension_T2(p, d.g, f, top.a_ddot, kappa);
      d.T1 = F1 = kappa * d.T2;
      break;
    }
    case Mode::Stuck:
    case Mode::BottomStop:
    case Mode::TopStop: {
      const Eigen::Vector2d tf = two_link_forces(p, d.g, f, top.a_ddot);
      F1 = tf(0);
      F2 = tf(1);
      if (!need_cone) {  // the motion needs the net pulls only
        d.T1 = F1;
        d.T2 = F2;
        d.margins = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
        break;
      }
      const FrictionCone cone = friction_cone(m.layers.friction_law, sticking_mu(m), d.g.psi);
      const ConeMargins both = cone_margins(m, d.g, F1, F2);
      if (c.mode == Mode::Stuck) {
        d.T1 = F1;
        d.T2 = F2;
        d.margins = both;
      } else if (c.mode == Mode::BottomStop) {
        // The ball pushes the bead up with N_c = T2 - F2 >= 0. Friction at rest leaves T2
        // anywhere in T1/κ_hi <= T2 <= T1/κ_lo: report the one closest to F2 (least push).
        // One-sided cone: the bead climbs off when T1 - κ_lo F2 < 0.
        d.T1 = F1;
        const double T2_max = cone.lo > 0.0 ? F1 / cone.lo : inf;
        d.T2 = std::max(std::min(F2, T2_max), F1 / cone.hi);
        d.contact = d.T2 - F2;
        d.margins.up = both.up;
      } else {
        // The top pushes the bead down with N_t = T1 - F1 >= 0, T1 within κ_lo T2... κ_hi T2.
        // One-sided cone: the bead slides down when κ_hi F2 - F1 < 0.
        d.T2 = F2;
        d.T1 = std::max(std::min(F1, cone.hi * F2), cone.lo * F2);
        d.contact = d.T1 - F1;
        d.margins.down = both.down;
      }
      break;
    }
    case Mode::Slack:
      d.T1 = d.T2 = 0.0;
      break;
  }
  d.pull = F1;
  d.acc1 = (-F1 * d.g.u1 + F2 * d.g.u2 + f.f1) / p.bead_mass;
  d.acc2 = (-F2 * d.g.u2 + f.f2) / p.ball_mass;
  d.motor_power = -F1 * d.g.u1.dot(top.a_dot);  // the top pulls link 1 (the stop's push included)
  d.drag_power = p.drag * (v1.squaredNorm() + v2.squaredNorm());
  d.friction_power = c.mode == Mode::Sliding ? (d.T1 - d.T2) * d.g.L1_dot : 0.0;
  return d;
}

void ledger_rates(const Model& m, const TopKinematics& top, const Contact& c, const Dynamics& d,
                  const numerics::Vec& y, numerics::Vec& dydt) {
  // The motor's power reaches the string through the tie (physics/tie.hpp) and the balls through
  // the couple: W_m counts both at the motor, W_c both clutches' slip.
  double rod = d.motor_power, clutch = 0.0;
  if (has_tie(y)) {
    const TiePowers tie = tie_powers(m, top, c, d);
    rod = tie.rod;
    clutch = tie.clutch;
    dydt(idx::chi) = top.omega;  // χ̇ and χ̈ of the top (ω_m and ω̇_m while it is held)
    dydt(idx::chi_dot) = top.omega_dot;
  }
  dydt(idx::rod_work) = rod + d.couple_power + d.couple_loss;
  dydt(idx::clutch_loss) = clutch + d.couple_loss;
}

[[gnu::flatten]] void rhs(const Model& m, const MotorSchedule& schedule, const Contact& c, double t,
                          const numerics::Vec& y, numerics::Vec& dydt) {
  const TopKinematics top = top_kinematics(m, schedule, c, t, y);
  const Dynamics d = evaluate(m, top, c, y, true);
  dydt.resize(y.size());
  dydt.segment<3>(idx::r1) = y.segment<3>(idx::v1);
  dydt.segment<3>(idx::r2) = y.segment<3>(idx::v2);
  dydt.segment<3>(idx::v1) = d.acc1;
  dydt.segment<3>(idx::v2) = d.acc2;
  dydt(idx::motor_work) = d.motor_power + d.couple_power;  // the couple's power comes from the motor
  dydt(idx::drag_loss) = d.drag_power;
  dydt(idx::friction_loss) = d.friction_power;
  if (y.size() > idx::dim) ledger_rates(m, top, c, d, y, dydt);
}

}  // namespace ajx::physics
