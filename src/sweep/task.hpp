// One task of a sweep chain: integrate the chain's schedule over [t_begin, t_end] from the
// carried state, and record every measurement window's samples at a fixed rate, so that the
// orbit can be classified now and reclassified later without integrating again.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "physics/model.hpp"
#include "physics/state.hpp"
#include "sim/simulation.hpp"
#include "sweep/orbit_classifier.hpp"
#include "sweep/protocol.hpp"

namespace ajx::sweep {

// What every task of a chain shares.
struct ChainSetup {
  physics::Model model;
  CompiledProtocol protocol;
  sim::RunOptions run;
  double sample_rate = 200.0;  // samples per second inside windows [1/s]
  // ε of the windows that stop once their orbit is known (sim/settle_watch.hpp), relative to
  // l; 0: every settle runs its full length.
  double settle_tolerance = 0.0;
  // The chain's motor: its protocol's schedule on the circle of the model's R.
  physics::MotorSchedule motor() const {
    physics::MotorSchedule s(model.p.drive_radius, protocol.schedule);
    if (protocol.hand) s.set_hand(*protocol.hand);
    return s;
  }
};

// The samples of one window, row-major: r1 and r2 are N×3.
// The energy account at one instant: the cumulative work integrals of the state and the
// mechanical energy, to tell an orbit the motor sustains from a decaying transient.
struct EnergyLedger {
  double t = 0.0;             // [s]
  double motor_work = 0.0;    // W_m, the motor's at the rod [J]
  double drag_loss = 0.0;     // [J]
  double other_loss = 0.0;    // friction and impact losses [J]
  double energy = 0.0;        // E = kinetic + potential [J]
  double string_work = 0.0;   // W_s, passed into the string at its top (= W_m for a rigid tie) [J]
  double clutch_loss = 0.0;   // W_c, the tie clutch's loss [J]
  double tie_energy = 0.0;    // ½ I_a χ̇² [J]
};

struct WindowRecord {
  int index = 0;  // window index in the chain
  std::vector<double> t, omega_m, r1, r2, L1, T1, T2;
  std::vector<std::int32_t> mode;
  EnergyLedger first, last;  // at the window's first and last sample
  std::size_t size() const { return t.size(); }
};

// Mean powers over a window from its ledgers [W]: what the motor does at its rod, what the top
// passes into the string, what the tie clutch, drag and friction with impacts take, and the rate
// of change of E. Over any window P_string = P_drag + P_other + dE/dt and P_motor = P_string +
// P_clutch + dE_tie/dt (the energy balance); a sustained orbit has dE/dt ≈ 0,
// a decaying transient dE/dt < 0 of the order of P_drag. NaN with fewer than two samples.
struct WindowPowers {
  double motor, drag, other, energy_rate;
  // With the tie clutch P_motor = P_string + P_clutch + dE_tie/dt and P_string = P_drag + P_other
  // + dE/dt; for a rigid tie P_string = P_motor, P_clutch = 0.
  double string = 0.0, clutch = 0.0;
};
WindowPowers window_powers(const WindowRecord& rec);

struct TaskOutput {
  bool ok = true;
  std::string failure;           // why the integration stopped early
  physics::State final_state;    // the carry for the next task (the last good state on failure)
  std::vector<WindowRecord> windows;
  long steps = 0, rhs_evals = 0, impacts = 0, sticks = 0, slack_phases = 0;
  double simulated = 0.0;        // seconds of the chain's schedule covered [s]
  double skipped = 0.0;          // ... of which settling not integrated, its orbit known [s]
};

// Adds a run's counts (steps, evaluations, impacts, sticks, slack phases, settling skipped) to a
// task's: one task may be several runs (a bisection's probes).
void add_counts(TaskOutput& out, const sim::RunSummary& r);

TaskOutput run_task(const ChainSetup& chain, const TaskSpan& span, physics::State start);
// The held stretches before the span's windows that end once their orbit is known, as run_task
// integrates them (so that a re-run of the task, e.g. astrojax replay, integrates the same way).
void add_settle_spans(const ChainSetup& chain, const TaskSpan& span, sim::RunOptions& run);

// The class of every window a task recorded. A window the failed integration did not finish
// is classified as failed.
std::vector<OrbitClassification> classify_windows(const ChainSetup& chain, const TaskOutput& out,
                                                  const ClassifierSettings& settings = {});

// The carry and the output as bytes for the farm; decode(encode(x)) == x exactly.
std::vector<std::byte> encode(const physics::State& s);
physics::State decode_state(const std::vector<std::byte>& bytes);
std::vector<std::byte> encode(const TaskOutput& out);
TaskOutput decode_output(const std::vector<std::byte>& bytes);

}  // namespace ajx::sweep
