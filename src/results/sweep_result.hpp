// What a worker sends back for one task, what the journal keeps and what the master writes
// into the sweep file: the task's summary and, per window, its class with the statistics of
// one /windows row and its samples as HDF5 chunks already compressed. The worker classifies
// and compresses, so the master (the farm's one serial stage) only writes.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "sweep/orbit_classifier.hpp"
#include "sweep/task.hpp"

namespace ajx::results {

// The per-window statistics of /windows: name, units, description.
inline constexpr const char* kStats[][3] = {
    {"confidence", "1", "confidence of the class, in [0, 1]"},
    {"omega_ball", "rad/s", "mean ω_ball of the balls with a reliable azimuth"},
    {"omega_ball_bead", "rad/s", "ω_ball of the bead (NaN when unreliable)"},
    {"omega_ball_bottom", "rad/s", "ω_ball of the bottom ball (NaN when unreliable)"},
    {"rotation_number", "1", "ω_ball / mean ω_m"},
    {"radius_bead_mean", "m", "mean horizontal radius of the bead"},
    {"radius_bead_std", "m", "its standard deviation"},
    {"radius_bottom_mean", "m", "mean horizontal radius of the bottom ball"},
    {"radius_bottom_std", "m", "its standard deviation"},
    {"height_bead_mean", "m", "mean height of the bead"},
    {"height_bottom_mean", "m", "mean height of the bottom ball"},
    {"L1_mean", "m", "mean bead position s = L1"},
    {"L1_std", "m", "its standard deviation"},
    {"L1_min", "m", "smallest L1"},
    {"L1_max", "m", "largest L1"},
    {"T1_mean", "N", "mean tension above the bead"},
    {"T2_mean", "N", "mean tension below the bead"},
};
inline constexpr std::size_t kNumStats = sizeof(kStats) / sizeof(kStats[0]);
// The window's energy account (sweep::window_powers), also in /windows; not the classifier's,
// so `astrojax classify` leaves them as the integration wrote them.
inline constexpr const char* kPowers[][3] = {
    {"motor_power", "W", "mean power the motor does at its rod over the window, <τ_rod ω_m> (format 4; format 2 held "
                         "string_power here); = string_power + clutch_power + the tie's d(½ I_a χ̇²)/dt"},
    {"drag_power", "W", "mean power drag takes"},
    {"friction_impact_power", "W", "mean power friction and impacts take"},
    {"energy_rate", "W", "dE/dt over the window: about 0 for an orbit the motor sustains, negative for a decaying transient"},
    {"string_power", "W", "mean power the top passes into the string (= motor_power for a rigid tie) = drag_power + "
                          "friction_impact_power + energy_rate"},
    {"clutch_power", "W", "mean power the tie clutch dissipates, <τ_c (ω_m − χ̇)> (0 for a rigid tie)"},
};
inline constexpr std::size_t kNumPowers = sizeof(kPowers) / sizeof(kPowers[0]);

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
  std::array<double, 5> mode_fraction{};
};
WindowRow window_row(const sweep::OrbitClassification& c);

struct WindowResult {
  std::int32_t index = 0;  // the window's index in its chain
  std::int32_t count = 0;  // samples stored, at most the file's samples per window
  WindowRow row;
  std::array<double, kNumPowers> powers{};     // in the order of kPowers [W]
  std::vector<std::vector<std::byte>> chunks;  // per kSampleColumns; none when count == 0
};

struct TaskResult {
  sweep::TaskOutput summary;  // the task's outcome, its windows' samples left out
  std::vector<WindowResult> windows;
};

// On the worker: round the samples to the precision the file stores, classify the windows
// from them (so that astrojax classify reproduces /windows from the file), and compress them
// into chunks of `cap` samples (padded with NaN), as the file stores them.
TaskResult make_result(const sweep::ChainSetup& chain, sweep::TaskOutput out, std::size_t cap);

std::vector<std::byte> encode(const TaskResult& r);
TaskResult decode_result(std::span<const std::byte> bytes);

}  // namespace ajx::results
