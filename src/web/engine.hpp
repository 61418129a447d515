// The live engine behind the browser page (build/web/, docs/live/): the project's model,
// integrator and orbit classifier driven interactively, as mj_step is MuJoCo's one call.
// Plain C++: compiled natively for the comparison test (tests/web/) and to WebAssembly with
// the embind bindings of bindings.cpp. No physics here; it wires config, sim and sweep.
//
// Time: the motor command (hold, ramp) can change at any moment. Each change starts a new
// MotorSchedule at the state's phase φ_c and speed ω_c, and the state's clock restarts at 0
// (time() adds the elapsed offset), so φ and ω_m stay continuous across commands.
#pragma once
#include <deque>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "physics/drive.hpp"
#include "physics/model.hpp"
#include "physics/state.hpp"
#include "sim/simulation.hpp"

namespace ajx::web {

// The run file the page starts from (sweeps/live.toml), embedded at build time.
extern const char* const kLiveSceneName;
extern const char* const kLiveSceneText;

// What the classifier said about the last window.
struct Verdict {
  std::string cls = "not-settled";  // sweep::to_string(OrbitClass), or "none" before a full window
  double omega_ball = 0.0;          // ω_ball [rad/s] (NaN when unreliable)
  double omega_m = 0.0;             // mean ω_m over the window [rad/s]
  double confidence = 0.0;
  double t_end = 0.0;               // end of the window [s]
  std::string reason;
};

// The energy ledger since the last start or model change [J]: W_m = ΔE + losses.
struct Energies {
  double kinetic, potential;        // ½ m |v|², m g z of both balls (z = 0 at the top)
  double motor_work, drag_loss, friction_loss, impact_loss;
  double delta_energy, residual;    // ΔE of the mechanical energy, W_m − ΔE − losses
};

class Engine {
 public:
  // The scene text is a run file (its [model], [layers], [integrator] are read; [initial] and
  // [[schedule]] are replaced by start() and the motor commands).
  Engine(std::string scene_text = kLiveSceneText, std::string scene_name = kLiveSceneName);

  // The scene with these overrides ("model.drive_radius=0.02", as --set takes them). "" when
  // accepted; else the command line's error text, and the running model and state are kept.
  // Accepted, the motion goes on from the current positions and velocities where the new
  // model admits them (projected onto its constraints; slack when the new string is longer
  // than L1 + L2), else from the last start.
  std::string configure(const std::vector<std::string>& overrides);
  // A seed of the sweeps (sweep/seeds.hpp) with the motor held at ω [rad/s]: "hanging" (at
  // rest, the bead on the bottom ball), "circular_high" (the paper's Table 1 positions turning
  // rigidly at ω) or "locked_orbit" (the locked orbit at ω, an equilibrium of the co-rotating
  // frame). The ledger restarts. An error text when the seed does not exist at ω.
  std::string start(const std::string& seed, double omega);
  void hold();                                  // ω_m stays where it is
  // |dω_m/dt| = rate [rad/s²] to the target, then hold; an error text for a rate <= 0 or a
  // target below 0 (nothing changes then).
  std::string ramp(double omega_target, double rate);

  // Integrate dt seconds of simulated time. False when the integration failed (failure() says
  // why; the state is the last good one and further calls do nothing until a start()).
  bool advance(double dt);

  double time() const { return t_offset_ + state_.t; }  // [s] since the last start
  double omega_m() const;                                // the motor's ω_m now [rad/s]
  double omega_target() const { return omega_target_; }
  int mode() const { return int(state_.contact.mode); }  // physics::Mode
  bool tie_slipping() const { return state_.contact.tie.slip; }
  // a, r1, r2 [m] (9 values): the top of the string and both balls.
  std::vector<double> positions() const;
  Energies energies() const;
  // Samples taken during the last advance(), 9 values each: t, ω_m, r1 (3), r2 (3), mode.
  const std::vector<double>& recent_samples() const { return recent_; }
  // The classifier on the last `window` seconds of samples (the sweeps' criteria).
  Verdict classify() const;
  const std::string& failure() const { return failure_; }
  const physics::Model& model() const { return config_.model; }
  const sim::RunSummary& totals() const { return totals_; }  // counts summed over advances
  const std::string& scene_name() const { return scene_name_; }

  static constexpr double kSampleInterval = 0.01;  // [s]: ≥ 4 samples a turn up to 50 rad/s
  static constexpr double kWindow = 5.0;           // the classified window [s], as sweeps/table1.toml

 private:
  void new_schedule(double omega_begin, double omega_end, double rate);
  void add_totals(const sim::RunSummary& r);

  std::string scene_text_, scene_name_;
  config::RunConfig config_;
  physics::MotorSchedule schedule_;
  physics::State state_, begin_;                 // now; at the start of the ledger
  double t_offset_ = 0.0;                        // time of the schedule's t = 0 [s]
  double omega_target_ = 0.0;
  double rate_ = 0.0;                            // of the ramp to omega_target_ [rad/s²]
  std::string seed_ = "hanging";
  double seed_omega_ = 0.0;
  std::string failure_;
  sim::RunSummary totals_;
  std::vector<double> recent_;
  struct Row { double t, omega_m, r1[3], r2[3], L1, T1, T2; int mode; };
  std::deque<Row> window_;
};

// The comparison scenes (tests/web/): the same script run by the native build and by the
// WebAssembly module, printed with every double in hexadecimal (%a), one line per sample.
// "locked", "climb", "slack". Throws std::invalid_argument for another name.
std::string scene_report(const std::string& name);

}  // namespace ajx::web
