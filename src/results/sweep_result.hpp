// What a worker sends back for one task, what the journal keeps and what the master writes
// into the sweep file: the task's summary and, per window, its class with the statistics of
// one /windows row and its samples as HDF5 chunks already compressed. The worker classifies
// and compresses, so the master (the farm's one serial stage) only writes.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "sweep/bisection.hpp"
#include "sweep/orbit_classifier.hpp"
#include "sweep/task.hpp"

namespace ajx::results {

// The per-window statistics of /windows, declared once: each is one row (its dataset's name,
// units and description, and how it is read off the window's classification), from which the
// writer, window_row, astrojax classify and verify, the reader and the reference page follow.
// A new statistic is one row here (plus, if new, the field the classifier computes).
using Classification = sweep::OrbitClassification;
struct WindowStat {
  const char* name;
  const char* units;
  const char* description;
  double (*of)(const Classification&);
};
inline constexpr WindowStat kStats[] = {
    {"confidence", "1", "confidence of the class, in [0, 1]", [](const Classification& c) { return c.confidence; }},
    {"omega_ball", "rad/s", "mean ω_ball of the balls with a reliable azimuth",
     [](const Classification& c) { return c.stats.omega_ball; }},
    {"omega_ball_bead", "rad/s", "ω_ball of the bead (NaN when unreliable)",
     [](const Classification& c) { return c.stats.ball[0].omega; }},
    {"omega_ball_bottom", "rad/s", "ω_ball of the bottom ball (NaN when unreliable)",
     [](const Classification& c) { return c.stats.ball[1].omega; }},
    {"rotation_number", "1", "ω_ball / mean ω_m", [](const Classification& c) { return c.stats.rotation_number; }},
    {"radius_bead_mean", "m", "mean horizontal radius of the bead",
     [](const Classification& c) { return c.stats.ball[0].rho.mean; }},
    {"radius_bead_std", "m", "its standard deviation", [](const Classification& c) { return c.stats.ball[0].rho.std; }},
    {"radius_bottom_mean", "m", "mean horizontal radius of the bottom ball",
     [](const Classification& c) { return c.stats.ball[1].rho.mean; }},
    {"radius_bottom_std", "m", "its standard deviation", [](const Classification& c) { return c.stats.ball[1].rho.std; }},
    {"height_bead_mean", "m", "mean height of the bead", [](const Classification& c) { return c.stats.ball[0].z.mean; }},
    {"height_bottom_mean", "m", "mean height of the bottom ball",
     [](const Classification& c) { return c.stats.ball[1].z.mean; }},
    {"L1_mean", "m", "mean bead position s = L1", [](const Classification& c) { return c.stats.L1.mean; }},
    {"L1_std", "m", "its standard deviation", [](const Classification& c) { return c.stats.L1.std; }},
    {"L1_min", "m", "smallest L1", [](const Classification& c) { return c.stats.L1.min; }},
    {"L1_max", "m", "largest L1", [](const Classification& c) { return c.stats.L1.max; }},
    {"T1_mean", "N", "mean tension above the bead", [](const Classification& c) { return c.stats.T1.mean; }},
    {"T2_mean", "N", "mean tension below the bead", [](const Classification& c) { return c.stats.T2.mean; }},
};
inline constexpr std::size_t kNumStats = std::size(kStats);

// The window's energy account (sweep::window_powers), also in /windows; not the classifier's,
// so `astrojax classify` leaves them as the integration wrote them. One row each, as kStats.
struct WindowPower {
  const char* name;
  const char* units;
  const char* description;
  double (*of)(const sweep::WindowPowers&);
  std::int64_t since = 2;  // the first file format that always holds it (format 1 may lack the account)
};
inline constexpr WindowPower kPowers[] = {
    {"motor_power", "W",
     "mean power the motor does at its rod over the window, <τ_rod ω_m> (format 4; formats 1-3 held string_power "
     "here); = string_power + clutch_power + the tie's d(½ I_a χ̇²)/dt",
     [](const sweep::WindowPowers& p) { return p.motor; }},
    {"drag_power", "W", "mean power drag takes", [](const sweep::WindowPowers& p) { return p.drag; }},
    {"friction_impact_power", "W", "mean power friction and impacts take",
     [](const sweep::WindowPowers& p) { return p.other; }},
    {"energy_rate", "W",
     "dE/dt over the window: about 0 for an orbit the motor sustains, negative for a decaying transient",
     [](const sweep::WindowPowers& p) { return p.energy_rate; }},
    {"string_power", "W",
     "mean power the top passes into the string (= motor_power for a rigid tie) = drag_power + "
     "friction_impact_power + energy_rate",
     [](const sweep::WindowPowers& p) { return p.string; }, 4},
    {"clutch_power", "W", "mean power the tie clutch dissipates, <τ_c (ω_m − χ̇)> (0 for a rigid tie)",
     [](const sweep::WindowPowers& p) { return p.clutch; }, 4},
};
inline constexpr std::size_t kNumPowers = std::size(kPowers);

// The per-window mode fractions, /windows/mode_fraction's last axis (physics::Mode's order).
inline constexpr std::size_t kNumModes = 5;

// The sample datasets of /samples, in chunk order: six scalars, then r1 and r2 (3 per sample).
inline constexpr const char* kSampleColumns[] = {"t", "omega_m", "L1", "T1", "T2", "mode", "r1", "r2"};
inline constexpr std::size_t kNumSampleColumns = sizeof(kSampleColumns) / sizeof(kSampleColumns[0]);
// Stored as float32 except t: 6e-8 relative is far below what the classifier and the plots
// resolve, while t (to 1e4 s on a 0.01 s grid) would lose its grid to float32's 1e-3 s.
inline constexpr bool kSampleFloat32[kNumSampleColumns] = {false, true, true, true, true, true, true, true};
inline constexpr int kSampleDeflate = 1;  // deflate level of the sample chunks (measured fastest, 2.5x smaller)
// Version of the /samples layout, its "format_version" attribute: 1 (no attribute) all
// float64, 2 float32 as kSampleFloat32.
inline constexpr int kSampleFormatVersion = 2;

// One row of /windows.
struct WindowRow {
  std::int32_t cls = -1;
  std::array<double, kNumStats> stats{};
  std::array<double, kNumModes> mode_fraction{};
};
WindowRow window_row(const sweep::OrbitClassification& c);

struct WindowResult {
  std::int32_t index = 0;  // the window's index in its chain
  std::int32_t count = 0;  // samples stored, at most the file's samples per window
  WindowRow row;
  std::array<double, kNumPowers> powers{};     // in the order of kPowers [W]
  std::vector<std::vector<std::byte>> chunks;  // per kSampleColumns; none when count == 0
};

// A bisection probe's result (sweep/bisection.hpp): the held level, its window's class and
// statistics (one row of /brackets/probes; its samples are not stored), and the bracket after it.
struct ProbeRecord {
  std::int32_t ran = 0;       // 0: the bracket was settled before this probe
  double omega = std::numeric_limits<double>::quiet_NaN();  // the held level [rad/s]
  std::int32_t known_side = 0;
  WindowRow row;                               // class and kStats of the measured window
  std::array<double, kNumPowers> powers{};     // its energy account [W]
  double known_omega = 0.0, other_omega = 0.0;  // the bracket after the probe [rad/s]
  std::int32_t known_class = -1, other_class = -1, status = 0;
  std::vector<std::byte> carry;                // the encoded BisectCarry the next probe starts from
};

struct TaskResult {
  sweep::TaskOutput summary;  // the task's outcome, its windows' samples left out
  std::vector<WindowResult> windows;
  std::optional<ProbeRecord> probe;  // a bisection's task; encoded only when present
};

// A probe's result: no window rows, the probe's row, and the known-side state as the task's
// final state (what the next probe starts from).
TaskResult probe_result(sweep::Probe p);

// The stored precision in memory: each float32 column's values rounded to float (what the
// classifier of a sweep reads, and astrojax replay with it).
void round_to_stored(sweep::WindowRecord& rec);

// On the worker: round the samples to the precision the file stores, classify the windows
// from them (so that astrojax classify reproduces /windows from the file), and compress them
// into chunks of `cap` samples (padded with NaN), as the file stores them.
TaskResult make_result(const sweep::ChainSetup& chain, sweep::TaskOutput out, std::size_t cap);

std::vector<std::byte> encode(const TaskResult& r);
TaskResult decode_result(std::span<const std::byte> bytes);

}  // namespace ajx::results
