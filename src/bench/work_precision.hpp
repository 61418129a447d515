// Work-precision measurements: run one scene with one method at one tolerance (or fixed step),
// measure the CPU time (median of repeats) and the ACHIEVED error against a reference, the
// constraint drift and the energy-balance residual. The reference is DOP853 at rtol 1e-13
// (a templated long-double RHS would touch all of physics/); it is checked against a second
// method (Dormand-Prince at rtol 1e-12), and their difference is the floor below which
// errors are not resolved. Knows nothing of files: the application loads scenes and writes.
#pragma once
#include <limits>
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
// the product's default axes (rotating), or with the suffix "/lab" in the lab axes, "/auto" in
// the axes the state picks (sim::Axes::Auto).
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

// Separation of nearby runs: the scene and a copy whose bead got a velocity kick of 1e-9 m/s
// at t0 (projected onto the constraints), both DOP853 at rtol 1e-13 in the lab axes, their
// velocity separation δ(t) = max(|Δv1|, |Δv2|) sampled `samples` times over the horizon.
// The finite-time Lyapunov exponent λ is the least-squares slope of ln δ over the last three
// quarters of the horizon (the first quarter lets the kick align with the growing direction),
// using only samples below saturation (δ < 0.1 m/s, a tenth of the balls' speeds).
// Regular motion (a limit cycle, a quasi-periodic flower) separates at most linearly,
// δ ∝ t, whose log-slope over [T/4, T] is at most ln 4 / (3T/4); chaos is declared when λ is
// three times that, i.e. when δ grows 64x over the window where linear growth gives 4x.
struct Separation {
  double amplification = 0.0;  // δ(horizon)/δ(0)
  double lyapunov = 0.0;       // λ [1/s]
  double threshold = 0.0;      // λ above which the scene is chaotic [1/s]
  int fitted = 0;              // samples in the fit
  bool chaotic() const { return fitted >= 4 && lyapunov > threshold; }
};
Separation separation(const Scene& scene, int samples = 40);

struct Reference {
  Outcome run;              // DOP853 at rtol 1e-13 (lab axes)
  double floor = 0.0;       // |reference - DOPRI5 at rtol 1e-12 (rotating axes)| in position [m]
  // Sensitivity (see Separation). A chaotic scene's pointwise errors grow like e^{λT} from any
  // method's round-off: no method reaches them, and statistics (orbit class, mean radius,
  // ω_ball over the horizon) are the measure.
  Separation sep;
  double amplification = 0.0;  // sep.amplification
  bool chaotic() const { return sep.chaotic(); }
};
Reference reference(const Scene& scene);

// Statistics of one run over the horizon (sampled 200 times per second), the measure of a
// chaotic scene: the orbit class of sweep::classify_orbit over the horizon, the mean
// horizontal radius of the two balls, and ω_ball (the classifier's least-squares slope).
struct Statistics {
  std::string orbit_class;
  double mean_radius = 0.0;  // [m]
  double omega_ball = 0.0;   // [rad/s]
};
Statistics statistics(const Scene& scene, const Setting& setting);

// One row of the work-precision table (also written by the peers' driver, same columns).
struct Row {
  std::string scene, method, param_kind;  // param_kind: "rtol" or "step"
  double param = 0.0;
  Outcome out;
  Errors err;
  double omega_ball_error = 0.0;  // |ω_ball - ω_ball of the reference| [rad/s]
  // Chaotic scenes only (NaN / empty otherwise): the statistics against the reference's.
  std::string orbit_class;
  bool same_class = true;
  double mean_radius_error = std::numeric_limits<double>::quiet_NaN();  // [m]
};
std::string csv_header();
std::string csv_line(const Row& r, const Reference& ref);

}  // namespace ajx::bench

namespace ajx::bench {

// The fall of the bead on a ramp down (ω_fall, docs/guide/thresholds.md): the first landing on
// the bottom ball.
// Samples every sample_dt; the landing time is extrapolated from the last sample before it,
// t = t_k + (L2 - d)/(-L̇2) (error O(sample_dt² L̈2/L̇2)), and ω_fall = ω_m there.
struct Fall {
  bool found = false;
  double t = 0.0;      // [s]
  double omega = 0.0;  // ω_m at the landing [rad/s]
};
Fall first_fall(const Scene& scene, const Setting& setting, double sample_dt);

// The loss of the lock on a ramp up (ω1, docs/guide/thresholds.md): the balls fall half a turn
// behind the motor.
// With the lag λ(t) = φ(t) − (θ1 + θ2)/2 (θ_i the balls' unwrapped lab azimuths, from samples
// every sample_dt), the lock is lost where λ − λ(t0) first reaches π; t is interpolated linearly
// between the samples that bracket it (error O(sample_dt² λ̈)), and ω1 = ω_m there.
Fall lock_loss(const Scene& scene, const Setting& setting, double sample_dt);

}  // namespace ajx::bench
