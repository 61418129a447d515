// Work-precision measurements: run one scene with one method at one tolerance (or fixed step),
// measure the CPU time (median of repeats) and the ACHIEVED error against a reference, the
// constraint drift and the energy-balance residual. The reference is DOP853 at rtol 1e-13
// (a templated long-double RHS would touch all of physics/); it is checked against a second
// method (Dormand-Prince at rtol 1e-12), and their difference is the floor below which
// errors are not resolved. Knows nothing of files: the application loads scenes and writes.
#pragma once
#include <string>
#include <vector>

#include "physics/drive.hpp"
#include "physics/model.hpp"
#include "physics/state.hpp"
#include "sim/simulation.hpp"

namespace ajx::bench {

// CPU time of this process [s]: what the benchmarks time (not wall time on a shared machine).
double cpu_seconds();

// A scene: a model, a motor schedule, an initial state, run options and a horizon.
struct Scene {
  std::string name;
  physics::Model model;
  physics::MotorSchedule schedule;
  physics::State initial;
  sim::RunOptions run;  // projection, event bounds, ...; method and tolerances set per point
  double horizon = 10.0;  // the error is measured at initial.t + horizon [s]
};

// A method as the benchmarks name it: a stepper name (numerics::make_stepper) integrated in
// the product's default axes (rotating), or with the suffix "/lab" in the lab axes.
std::string_view stepper_name(std::string_view method);
sim::Axes axes_of(std::string_view method);

// One point of a diagram: a method with either rtol (adaptive, atol = 1e-3 rtol) or a
// fixed step h.
struct Setting {
  std::string method;
  double rtol = 0.0;  // adaptive methods
  double step = 0.0;  // fixed-step methods [s]
};

// A finished run of the hybrid simulation (sim::Simulation, the product's own path).
struct Outcome {
  std::string status = "ok";     // or why the run failed
  int repeats = 0;               // runs timed
  double cpu_median = 0.0;       // [s] CPU time of one run, median over the repeats
  double cpu_min = 0.0;          // [s]
  long steps = 0, rejected = 0, rhs_evals = 0, mode_switches = 0;
  double max_drift = 0.0;        // largest |C| after a step, before projection [m]
  double energy_residual = 0.0;  // relative energy-balance residual over the run
  double omega_ball = 0.0;       // ω_ball over the last window [rad/s] (a statistic for chaotic scenes)
  physics::State final;          // state at the horizon
};

// Runs the scene with the setting `repeats` times (fewer once `cpu_budget` seconds are spent,
// at least once) and keeps the median CPU time (CLOCK_PROCESS_CPUTIME_ID).
Outcome run_point(const Scene& scene, const Setting& setting, int repeats, double cpu_budget);

// Achieved error of a final state against the reference: max over both balls.
struct Errors {
  double position = 0.0;  // max(|Δr1|, |Δr2|) [m]
  double velocity = 0.0;  // max(|Δv1|, |Δv2|) [m/s]
  bool same_mode = true;  // the contact mode at the horizon agrees
};
Errors compare(const physics::State& s, const physics::State& ref);

struct Reference {
  Outcome run;              // DOP853 at rtol 1e-13
  double floor = 0.0;       // |reference - DOPRI5 at rtol 1e-12| in position [m]
  // Sensitivity: a velocity kick of 1e-9 m/s on the bead at t0 (projected onto the
  // constraints) grows to `amplification` x 1e-9 in velocity at the horizon. Above 1e6 the
  // scene is chaotic over the horizon: pointwise errors below ~1e-16 x amplification cannot
  // be reached by any method, and statistics (ω_ball, the orbit class) are the measure.
  double amplification = 0.0;
  bool chaotic() const { return amplification > 1e6; }
};
Reference reference(const Scene& scene);

// One row of the work-precision table (also written by the peers' driver, same columns).
struct Row {
  std::string scene, method, param_kind;  // param_kind: "rtol" or "step"
  double param = 0.0;
  Outcome out;
  Errors err;
  double omega_ball_error = 0.0;  // |ω_ball - ω_ball of the reference| [rad/s]
};
std::string csv_header();
std::string csv_line(const Row& r, const Reference& ref);

}  // namespace ajx::bench

namespace ajx::bench {

// The fall of the bead on a ramp down (ω_fall, model.md): the first landing on the bottom ball.
// Samples every sample_dt; the landing time is extrapolated from the last sample before it,
// t = t_k + (L2 - d)/(-L̇2) (error O(sample_dt² L̈2/L̇2)), and ω_fall = ω_m there.
struct Fall {
  bool found = false;
  double t = 0.0;      // [s]
  double omega = 0.0;  // ω_m at the landing [rad/s]
};
Fall first_fall(const Scene& scene, const Setting& setting, double sample_dt);

}  // namespace ajx::bench
