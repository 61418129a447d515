// A threshold found by bisection on held levels, one farm task per probe (docs/guide/maps.md).
//
// A chain of a [bisect] sweep brackets one threshold at one grid point. Probe 0 holds the
// start level `from` (reached from the seed at start_omega), which must lie on the
// threshold's known side; the far end `to` is taken to lie on the other side, and every later
// probe holds the middle of the bracket [known, other]. Each probe restarts from the state left
// by the last probe on the known side (the staircase's own history up to there: its motor
// schedule is carried along), ramps ω_m to its level at step_rate, settles and measures one
// window, classified as every sweep window is, or stops as soon as its class is decided
// (sweep/probe_verdict.hpp). The bracket halves with every probe, so a range Δ is brought to
// a width w in 2 + ceil(log2(Δ/w)) probes instead of Δ/step levels of a ladder, one of them at
// `to`. For ω_fall and ω1 the probe at `to` runs last, and only when every middle fell on the
// known side (it tells a crossing in the last width from none in the range); for ω2 and ω_rise
// it runs first (far_end_last). The middles are those of [from, to] either way, so the order
// moves no bracket; holding it last saves the far end's probe, a fall or a loss of lock and the
// most expensive of a chain, wherever a middle finds the other side. With Guide::HeldOrbit
// (ω_fall, ω1) the later probes go instead to the middles' lattice next to the threshold probe
// 0's locked orbit predicts (orbits::held_orbit_end, guided_index): the bracket is still two
// held probes, reached by another history.
//
// The known side, per threshold (the definitions of thresholds.hpp on held levels):
//   ω_rise  (rising)   fallen;       ω_fall (falling)  not fallen;
//   ω1      (rising)   locked;       ω2     (rising)   circular (locked or lagging).
// A probe carries everything the next needs (BisectCarry), so the farm, which knows no
// physics, runs a bisection as it runs any chain: in order, on any rank, and a resumed sweep
// goes on from the carry the last finished probe left.
#pragma once
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "physics/drive.hpp"
#include "physics/model.hpp"
#include "physics/state.hpp"
#include "sim/simulation.hpp"
#include "sweep/orbit_classifier.hpp"
#include "sweep/task.hpp"
#include "sweep/thresholds.hpp"

namespace ajx::sweep {

struct BisectSpec {
  Threshold threshold = Threshold::Fall;
  std::string start_seed = "circular_high";  // the state at t = 0: a seed of seeds.hpp at start_omega
  double start_omega = 0.0;  // ω_m of the seed [rad/s]
  double from = 0.0;         // the first level, on the known side [rad/s]
  double to = 0.0;           // the far end of the range, past the threshold [rad/s]
  double width = 0.0;        // the bracket's width at the end, w [rad/s]
  double settle = 100.0;     // transient at each level, not measured [s]
  double measure = 20.0;     // the classified window at each level [s]
  double step_rate = 0.1;    // |dω_m/dt| on the way to a level [rad/s²]
  // Stop a probe once its class is decided (sweep/probe_verdict.hpp); false: every probe runs
  // through its window.
  bool decide_early = true;
  // Where the probes go: Middle, the middle of every bracket; HeldOrbit (ω_fall, ω1), next to
  // the threshold the start level's own orbit predicts (guided_index below).
  enum class Guide : std::int32_t { Middle = 0, HeldOrbit = 1 } guide = Guide::Middle;
};

// Whether a held level's class is on the threshold's known side.
bool on_known_side(Threshold t, OrbitClass c);
// Whether the far end is held last (ω_fall, ω1: past them a probe falls or loses its lock, the
// costly side, and before them it locks, decided early) or first (ω2, ω_rise: where the range
// often holds no crossing, which the far end tells in one probe).
bool far_end_last(Threshold t);
// +1: the threshold is found with rising ω_m (from < to), −1 falling.
int bisect_direction(Threshold t);
// The halvings n that bring |to − from| to at most w: the probes' lattice has 2^n cells.
int halvings(const BisectSpec& s);
// Probes per chain, at most: 2 + n with the middles; 2n + 2 guided (guided_index's bound,
// tests/bisection_guide_test.cpp checks it over every order of outcomes).
int probe_count(const BisectSpec& s);
// The guided probe between lattice indices K (known side) < O (other side), O − K >= 2, given
// the predicted threshold at index g (NaN: none): the lattice point next to g on the known side
// of it, then the one past it; once g lies outside [K, O] (the prediction was wrong), steps
// from the end nearest g that double with the distance to g (K + ⌈K − g⌉ ...), at most to the
// middle: a bracket the prediction holds is closed in two probes, and any other in at most
// about twice the middles' count.
std::int64_t guided_index(std::int64_t K, std::int64_t O, double g);
// The narrowest bracket a window resolves: two levels w apart drift apart in phase by w·T_m over
// the window T_m; below 2π/min_samples_per_turn (the classifier's largest azimuth step, a quarter
// turn by default) one window cannot tell their orbits apart. w_min = 2π/(n_turn T_m) [rad/s].
double min_width(const BisectSpec& s, const ClassifierSettings& settings = {});

enum class BisectStatus : std::int32_t {
  Running = 0,       // the bracket is still wider than w
  Converged = 1,     // known and other at most w apart
  StartOffSide = 2,  // the start level is not on the known side: no bracket
  NoCrossing = 3,    // the far end is still on the known side: the threshold lies beyond the range
  Failed = 4,        // a probe's integration failed
};
inline constexpr std::int32_t kMaxBisectStatus = 4;
inline constexpr const char* kBisectStatusNames =
    "0 running,1 converged,2 start not on the known side,3 no crossing in the range,4 a probe failed";
std::string_view to_string(BisectStatus s);

// What a probe hands the next: the bracket and the state on its known side.
struct BisectCarry {
  physics::State known;                        // at the end of the last probe on the known side
  std::vector<physics::DriveSegment> history;  // the motor schedule from t = 0 to known.t
  double known_omega = 0.0, other_omega = 0.0;  // the bracket [rad/s]
  std::int32_t known_class = -1, other_class = -1;  // the classes measured there (-1: none yet)
  BisectStatus status = BisectStatus::Running;
  // The threshold the start level's orbit predicts [rad/s] (BisectSpec::Guide::HeldOrbit; NaN:
  // none or not asked): orbits::held_orbit_end from probe 0's state.
  double guide = std::numeric_limits<double>::quiet_NaN();
  double width() const { return other_omega > known_omega ? other_omega - known_omega : known_omega - other_omega; }
};
std::vector<std::byte> encode(const BisectCarry& c);
BisectCarry decode_carry(const std::vector<std::byte>& bytes);

struct Probe {
  bool ran = false;          // false: the bracket was settled before this probe (nothing integrated)
  bool decided = false;      // the class decided before the window, which was not integrated
  double decided_at = std::numeric_limits<double>::quiet_NaN();  // when [s]
  double omega = 0.0;        // the held level [rad/s] (NaN when not run)
  TaskOutput out;            // the integration; out.windows holds the measured window
  OrbitClassification classification;
  bool known_side = false;
  BisectCarry next;          // the bracket after this probe
};

// The probe's chain: the carried history (from t = 0 to t0, the sum of its durations), then ω_m
// ramped from omega0 to `level` at step_rate, held for settle from t_settle = t0 + |level −
// omega0|/step_rate, and one window of measure.
ChainSetup probe_chain(const BisectSpec& spec, const physics::Model& model, const sim::RunOptions& run,
                       double sample_rate, const std::vector<physics::DriveSegment>& history, double omega0,
                       double level);

// Probe k (0, 1, ...) of a chain at `model`, from the carry probe k − 1 left (ignored for k = 0,
// which starts from the seed).
Probe run_probe(const BisectSpec& spec, const physics::Model& model, const sim::RunOptions& run, double sample_rate,
                int k, const BisectCarry& in, const ClassifierSettings& settings = {});

}  // namespace ajx::sweep
