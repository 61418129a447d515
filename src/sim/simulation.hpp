// One trajectory of the hybrid system: integrate the current mode with its events, switch
// modes (impacts included), project onto the constraints, and hand samples to an observer.
#pragma once
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "numerics/integrate.hpp"
#include "physics/astrojax_system.hpp"
#include "physics/energy.hpp"

namespace ajx::sim {

using physics::Contact;
using physics::Mode;
using physics::State;

// The axes the integrator sees (physics/rotating_axes.hpp). Rotating: the lab state expressed
// in axes turning with the motor, where a locked orbit is a fixed point (measured faster at
// equal accuracy: docs/reports/accuracy-and-speed.md); the run's input, output and samples stay lab.
// Auto: decided at the start of each run (each sweep window) from the state, see
// corotates() (sim/step_bound.hpp).
enum class Axes { Lab, Rotating, Auto };

struct RunOptions {
  std::string method = "dop853";       // the measured recommendation (docs/reports/accuracy-and-speed.md)
  Axes axes = Axes::Rotating;          // the measured recommendation, as method
  // [integrator] max_step = "auto": adaptive steps also bounded by h <= (k + 1)/Ω (k = integ.
  // event_samples guard samples inside each step), Ω the fastest rate
  // of the guards at the step's end state (sim/step_bound.hpp), so that a guard's excursion past
  // zero is not hidden inside one step. Then the fixed bound h_max is only a 10 s ceiling, as a
  // config file's "auto" sets it; a fixed max_step turns the guard bound off.
  bool guard_step_bound = true;
  numerics::IntegrateOptions integ = [] {  // tolerances, fixed step, bounds
    numerics::IntegrateOptions o;
    o.h_max = 10.0;
    // Three guard samples inside each step, so "auto" allows h <= 4/Ω: the fewest at which the
    // evaluations of every work-precision scene stop falling, to rtol 1e-2 (docs/reports/
    // accuracy-and-speed.md, "Guard samples inside the step").
    o.event_samples = 3;
    return o;
  }();
  double projection_tol = 1e-12;       // project when |C| exceeds this [m] (or [m/s] for J v - b)
  long max_events = 1'000'000;         // bound on mode switches and impacts per run
  double rest_speed = 1e-3;            // re-taut impacts slower than this are plastic [m/s]
  int chatter_switches = 50;           // this many switches ...
  double chatter_window = 1e-3;        // ... within this time [s] is chattering
  double omega_window = 10.0;          // ω_ball is averaged over the last window [s]
  // The summary's statistics over samples and steps: max_sample_drift, min_tension,
  // min_friction_power and omega_ball. Off (a sweep: its classifier measures the windows from
  // the samples), the observer skips their cost and they are NaN.
  bool run_statistics = true;
  // Sample only at grid times inside these half-open spans [begin, end), sorted and disjoint
  // (empty: every grid time). A sweep task keeps the samples of its windows only; each sample
  // elsewhere would cost the dense output and an evaluate for nothing.
  std::vector<std::pair<double, double>> sample_spans;
  // Held, unmeasured stretches [begin, end), sorted and disjoint, that end as soon as their
  // orbit is a fixed point or a periodic orbit of the frame turning with the top, to within settle_tolerance × l
  // (sim/settle_watch.hpp); empty: every stretch runs its full length.
  std::vector<std::pair<double, double>> settle_spans;
  double settle_tolerance = 1e-4;  // ε, relative to the string length l
};

// One sample of the trajectory with the quantities derived from it.
struct Sample {
  double t;                        // [s]
  const Contact& contact;
  const numerics::Vec& y;          // state in the layout of physics::idx
  const physics::Dynamics& dyn;    // tensions, L1, powers
  const physics::TopKinematics& top;
  double impact_loss;              // cumulative [J]
};
using SampleObserver = std::function<void(const Sample&)>;

// An assumption of an omitted layer that the run found violated (docs/physics/layers.md).
struct Violation {
  std::string what;          // e.g. "negative tension without the slack layer"
  long count = 0;            // times the run entered the violation
  double first_time = -1.0;  // [s]
  double worst = 0.0;        // the largest excess, in `unit`
  std::string unit;
};

struct RunSummary {
  numerics::IntegrateStatus status = numerics::IntegrateStatus::Reached;
  std::string failure;             // empty when the run reached its end
  double t_end = 0.0;              // time reached [s]
  long steps = 0, rejected = 0, rhs_evals = 0;
  long mode_switches = 0, impacts = 0, projections = 0;
  long sticks = 0;                 // times the bead stuck to the string (ṡ = 0 inside the cone)
  double first_stick = -1.0;       // time of the first [s], -1 if none
  long slack_phases = 0;           // times the string went slack
  long tie_slips = 0;              // times the tie slipped on the rod (tie-clutch layer)
  double first_tie_slip = -1.0;    // time of the first [s], -1 if none
  long chatter = 0;                // chattering episodes detected (many switches in a short time)
  double first_chatter = -1.0;     // [s]
  std::vector<Violation> violations;  // assumptions of omitted layers that did not hold
  double max_drift = 0.0;          // largest |C| after any accepted step, before projection [m]
  double max_sample_drift = 0.0;   // largest |C| over the delivered samples [m]
  physics::EnergyBalance energy{};
  double omega_ball = 0.0;         // mean dθ/dt of the two balls over the last window [rad/s]
  double min_tension = 0.0;        // smallest of T1, T2 seen at samples [N]
  double min_friction_power = 0.0; // smallest (T1 - T2) ṡ seen at samples [W]
  double skipped = 0.0;            // simulated seconds of settle spans not integrated [s]
  long settle_stops = 0;           // settle spans ended early
  bool ok() const { return failure.empty(); }
};

class Simulation {
 public:
  Simulation(const physics::Model& model, const physics::MotorSchedule& schedule, RunOptions opt);

  // Integrate s from s.t to t_end, sampling every sample_dt (sample_dt <= 0: none) on the grid
  // sample_origin + k sample_dt from s.t on (the default origin is s.t). s is advanced in
  // place; on failure it holds the last good state.
  RunSummary run(State& s, double t_end, double sample_dt, const SampleObserver& on_sample = {},
                 double sample_origin = std::numeric_limits<double>::quiet_NaN());

  const physics::Model& model() const { return model_; }
  const physics::MotorSchedule& schedule() const { return schedule_; }

 private:
  const physics::Model& model_;
  const physics::MotorSchedule& schedule_;
  RunOptions opt_;
};

// Both balls hanging at rest below the top, the bead on the bottom stop (L2 = d).
State hanging_at_rest(const physics::Model& model, const physics::MotorSchedule& schedule,
                      double t0 = 0.0);

// An explicit state, projected onto the mode's constraints. Throws std::invalid_argument when
// it is too far from them (|L1 + L2 - l| > tol_length; for a slack start L1 + L2 > l) or
// below the bottom stop. With the tie clutch and a finite tie_slip_rate, the tie starts
// slipping at χ = φ(t0), χ̇ = tie_slip_rate (else held at χ = φ).
State explicit_state(const physics::Model& model, const physics::MotorSchedule& schedule,
                     const physics::Vec3& r1, const physics::Vec3& r2, const physics::Vec3& v1,
                     const physics::Vec3& v2, Mode mode, double t0 = 0.0,
                     double tol_length = 1e-6,
                     double tie_slip_rate = std::numeric_limits<double>::quiet_NaN());

}  // namespace ajx::sim
