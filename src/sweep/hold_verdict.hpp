// Telling a bifurcation from a time limit. A ramp's threshold is a bracket between two windows
// of different class. It is a bifurcation of the driven orbits when the orbit before it is one
// the motor sustains at fixed ω_m and the orbit after it is a different one; it is a time
// limit when the orbit before it is a transient that only the ramp's finite duration kept
// alive: then the "threshold" moves with the ramp rate and dwell time, and must not be fitted.
// Between the two, an excursion: the orbit before is sustained, but the change after it does
// not persist at fixed ω_m (the bead climbs and falls back).
//
// The test: restart the chain from its stored state, follow its own motor schedule to the
// middle of the bracket's window before the change (ω_m = the bracket's `before`) and hold ω_m
// there for a time T; the same to the middle of the window after the change (`after`). Both
// holds are classified in windows as the sweep classifies, and the energy account of each
// window kept (sweep/task.hpp, window_powers).
//
// Energy: with P_drag = c_D (|v1|² + |v2|²) = 2 c_D (K1/m1 + K2/m2) and the balance
// P_motor = P_drag + P_other + dE/dt, an orbit the motor sustains has dE/dt ≈ 0, and one the
// motor feeds nothing decays with dE/dt = −P_other − P_drag, r = (dE/dt)/P_drag ≈ −1
// (measured: a free whirl of the bottom ball decays at exactly that rate). An orbit with ratio
// r loses energy at the rate |r| P_drag ≤ |r| (2 c_D/m_min) K, so it e-folds no sooner than
// m_min/(2 c_D |r|). It counts as sustained over the hold when that is longer than T:
//   |r| ≤ r_tol = m_min / (2 c_D T)
// (0.1 for T = 5 m/c_D, a tenth of the free decay's |r| = 1), widened to twice the standard
// error of the per-window ratios r_k when the orbit's own energy oscillation makes them scatter
// (a window that is not a whole number of the orbit's periods, or a slow beat between the
// driven orbit and a free swing). A uniform decay has r_k all equal, so this widening does not
// hide it. When the widening reaches 1/2, r can no longer tell a sustained orbit (r = 0) from
// a free decay (r = −1) at two standard errors each: the side is undetermined (hold longer).
//
// Default T = 5 max(m1, m2)/c_D (52 s for the paper's balls), and r is measured over the last
// half of the hold: the transient the hold's start excites (the ramp stops) has then decayed
// by e^{−(2 c_D/m)(T/2)} = e^{−5} in energy, and the measured half is 2.5 drag times long.
#pragma once
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "physics/model.hpp"
#include "physics/state.hpp"
#include "sweep/orbit_classifier.hpp"
#include "sweep/task.hpp"

namespace ajx::sweep {

// The slowest drag time of the balls, max(m1, m2)/c_D [s] (infinite without drag).
double drag_time(const physics::Parameters& p);
// r_tol = m_min/(2 c_D T) for a hold of T seconds (infinite without drag).
double sustain_tolerance(const physics::Parameters& p, double hold);

// The chain driven along its own schedule until t_cut, then ω_m held at its value there for
// n_windows windows of `window` seconds each (direction 0, as the hold mode's).
// Throws std::invalid_argument for t_cut outside the schedule, n_windows < 1 or window <= 0.
ChainSetup held_chain(const ChainSetup& chain, double t_cut, int n_windows, double window);

struct HoldSide {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  double omega = nan;                  // the held ω_m [rad/s]
  double t_cut = nan;                  // chain time at which the hold starts [s]
  double hold = 0.0;                   // its duration, a whole number of windows [s]
  std::vector<OrbitClass> classes;     // per hold window
  std::vector<WindowPowers> powers;    // per hold window [W]
  OrbitClass reference = OrbitClass::Failed;  // the sweep's class at this side of the bracket
  OrbitClass final_class = OrbitClass::Failed;  // the class of the hold's last window
  double first_change = nan;           // time into the hold when a window first differs from reference [s]
  int measured = 0;                    // windows of the measured stretch (the last half)
  WindowPowers mean{nan, nan, nan, nan, nan, nan};  // mean powers over the measured stretch [W]
  double ratio = nan;                  // r = (dE/dt)/P_drag over the measured stretch
  double ratio_error = nan;            // standard error of the per-window ratios
  double tolerance = nan;              // the |r| accepted as sustained (see above)
  bool sustained = false;              // |dE/dt| ≤ tolerance · P_drag
  bool determined = false;             // 2 · ratio_error < 1/2: r tells sustained from free decay
  bool ok = true;                      // false: the integration failed (see failure)
  std::string failure;
  double simulated = 0.0;              // seconds integrated [s]
};

// Holds ω_m from t_cut for `hold` seconds (rounded up to whole windows of `window` s, at least
// four) from `start`, a state of the chain no later than t_cut; `reference` is the class the
// sweep found there.
HoldSide hold_side(const ChainSetup& chain, double t_cut, double hold, double window, const physics::State& start,
                   OrbitClass reference, const ClassifierSettings& settings = {});

enum class Verdict { Bifurcation, Excursion, TimeLimited, Undecided };
// "bifurcation", "excursion", "time-limited transient", "undecided"
std::string_view to_string(Verdict v);

struct Judgement {
  Verdict verdict = Verdict::Undecided;
  std::string reason;  // one line, ASCII
};

// With the orbit before the change sustained and keeping the sweep's class when held there:
//   bifurcation  held after the change, the orbit ends in another class;
//   excursion    held after the change, the orbit ends in the old class again: the orbit before
//                the change is sustained, so the onset is not a time limit, but what follows it
//                is a transient, not a new steady orbit (the hold starts from the sweep's state in
//                the middle of the window after the change, so a short excursion may be over
//                before the hold begins).
// Time-limited transient when, held before the change, the orbit changes class or is not
// sustained: the ramp's finite time kept it alive, and the threshold moves with ramp rate and
// dwell. Undecided: a hold failed, or the energy account before the change is undetermined.
Judgement judge(const HoldSide& pre, const HoldSide& post);

}  // namespace ajx::sweep
