// The paper's own discretisation (its eqs. 12-31), as a simulation path of its own: a two-step
// method that does not fit the one-step Stepper interface.
//
//   m_i (q_i^(k+1) - 2 q_i^(k) + q_i^(k-1)) / h² = F_i^(k) + s c_D (q_i^(k) - q_i^(k-1)) / h - m_i g ẑ
//
// with F^(k) the string's forces along the segment directions at step k (-T1 u1 + T2 u2 on the
// bead, -T2 u2 on the bottom ball), T1 = κ T2 from the kinetic friction law at the deflection ψ^(k)
// and the sliding sense sgn(L1^(k) - L1^(k-1)), and T2 the one unknown chosen so that q^(k+1) lies
// on L1 + L2 = l (eq. 29). The drag sign s: +1 as printed in eq. (15) (anti-damping), -1 as in
// eq. (8). The scheme integrates in the lab frame with a fixed step h; it has no slack string, no
// stops, no stuck bead and no tie clutch (their violations are reported, as for omitted layers).
#pragma once
#include <optional>
#include <string_view>

#include "physics/drive.hpp"
#include "physics/model.hpp"
#include "sim/simulation.hpp"

namespace ajx::sim {

// The drag's sign in eq. (15): as printed (+c_D ẋ, energy injected) or as in eq. (8).
enum class PaperDrag { Printed, Corrected };

// "paper" -> Printed, "paper_corrected" -> Corrected, anything else -> none.
std::optional<PaperDrag> paper_variant(std::string_view method);

// The start of the two-step method: positions at t0 and at t0 + h.
struct PairStart {
  double t0 = 0.0;
  physics::Vec3 r1_0, r2_0;  // q^(0) [m]
  physics::Vec3 r1_1, r2_1;  // q^(1) [m]
};

// One step of the recurrence for one ball of mass m, without the constraint force:
//   q^(k+1) = 2 q^(k) - q^(k-1) + (h²/m) (f + s c (q^(k) - q^(k-1))/h),
// s = +1 printed, -1 corrected. f: the other forces at step k (gravity, the known string part).
physics::Vec3 central_step(const physics::Vec3& q, const physics::Vec3& q_prev, const physics::Vec3& f,
                           double m, double c, double h, PaperDrag drag);

// Each position of the pair moved onto L1 + L2 = l at its own time (the mass-weighted
// projection of the taut sliding mode); returns the largest |L1 + L2 - l| before [m].
double project_pair(const physics::Model& model, const physics::MotorSchedule& schedule, double h,
                    PairStart& pair);

// The state a one-step integrator starts from: q^(0) with the velocity (q^(1) - q^(0))/h,
// taut (projected, sliding) when L1 + L2 >= l - tol, else slack.
physics::State state_from_pair(const physics::Model& model, const physics::MotorSchedule& schedule,
                               const PairStart& pair, double h, double tol = 1e-6);

// The model's layers the scheme cannot honour, as (key, what the scheme needs); empty if none.
std::vector<std::pair<std::string, std::string>> paper_scheme_conflicts(const physics::Model& model);

// Runs the scheme from the pair to t_end with step h. Samples (on the grid t0 + j sample_dt,
// each at the first step at or after it; the first at t0 + h, where the first velocity exists)
// carry the central velocity (q^(k+1) - q^(k-1))/(2h), the tensions of step k and the work
// integrals (trapezoidal sums of the powers at the steps). `end` receives the last sampled state.
RunSummary run_paper_scheme(const physics::Model& model, const physics::MotorSchedule& schedule, PaperDrag drag,
                            double h, const PairStart& pair, double t_end, double sample_dt,
                            const SampleObserver& on_sample, physics::State& end, double omega_window = 10.0);

}  // namespace ajx::sim
