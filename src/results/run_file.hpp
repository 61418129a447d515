// The file of `astrojax run`: the sampled trajectory with units and descriptions, the run's
// summary (energy ledger, counters, the violations of omitted layers) and the provenance.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "io/hdf5_file.hpp"
#include "physics/drive.hpp"
#include "sim/paper_scheme.hpp"
#include "sim/simulation.hpp"

namespace ajx::results {

// Columns of the sampled trajectory, in memory until the run ends.
struct Trajectory {
  // Bytes a sample takes in memory and in the file: 29 doubles and the mode.
  static constexpr double kBytesPerSample = 29 * sizeof(double) + sizeof(std::int32_t);

  std::vector<double> t, r1, r2, v1, v2, T1, T2, contact, L1, psi, omega_m, phi, chi, energy, tie_energy;
  std::vector<double> motor_work, string_work, clutch_loss, drag_loss, friction_loss, impact_loss;
  std::vector<std::int32_t> mode;

  // One sample; the schedule gives the motor's phase φ (the sample's top is the tie's, at χ).
  void add(const sim::Sample& s, const physics::Parameters& p, const physics::MotorSchedule& schedule);
  void write(io::Group& g) const;  // one dataset per quantity, with units and a description
};

// A run's output could not be made or written (disk full, no permission, I/O error).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The run's file: made as "<path>.part" before the run, so that an output that cannot be
// written is refused before any work; written and renamed to <path> after it. Destroyed
// without write(), or when write() fails, it leaves nothing behind.
class RunFile {
 public:
  explicit RunFile(const std::filesystem::path& out);  // throws OutputError
  // write_run below; throws OutputError (the .part is removed).
  void write(const std::string& command_line, const config::RunConfig& cfg, const physics::MotorSchedule& schedule,
             const Trajectory& traj, const sim::RunSummary& sum, const physics::State& state, double wall,
             std::optional<double> start_projection, const std::optional<sim::PairStart>& raw_pair);

 private:
  io::File f_;
};

// The /summary attributes every run file has, a replayed window's too: status, t_end, the
// motor's work, the string's and the clutch's share, and the counts of steps and events.
void write_summary_common(io::Group& sg, const sim::RunSummary& sum);

// The trajectory, the summary and the provenance into the run's file, then committed.
// `start_projection`: with the paper's scheme, |L1 + L2 - l| of its starting pair before
// projection; `raw_pair`: a two-step start's pair as given, before projection.
void write_run(io::File& f, const std::string& command_line, const config::RunConfig& cfg,
               const physics::MotorSchedule& schedule, const Trajectory& traj, const sim::RunSummary& sum,
               const physics::State& state, double wall, std::optional<double> start_projection,
               const std::optional<sim::PairStart>& raw_pair);

}  // namespace ajx::results
