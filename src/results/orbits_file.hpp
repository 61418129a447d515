// The HDF5 file of `astrojax orbits -o FILE.h5`: the orbits' table, the continuation's
// branches and their events, the predicted thresholds; or, with --map, the threshold curves
// in the plane of ω_m and a second parameter with their codimension-2 points. Written to a
// temporary file and renamed when complete; lists of names are 1-D string attributes.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "results/table.hpp"

namespace ajx::results {

struct OrbitsOutput {
  Table orbits;  // /orbits
  struct Branches {
    std::string parameter;                 // the continuation parameter
    Table points, events;                  // /branches/points, /branches/events
    std::vector<std::string> event_kinds;  // /branches/events@kinds, one per event
  };
  std::optional<Branches> branches;
  struct Threshold {
    std::string symbol;  // omega_fall, omega_1, ...
    double predicted, measured;  // [rad/s]
    std::string mechanism;
  };
  std::optional<std::vector<Threshold>> thresholds;  // /thresholds/<symbol>
};

struct CurvesOutput {
  std::string parameter, symbol, unit;  // the second parameter: key, symbol, unit
  std::vector<std::string> kinds;       // the curve kinds by code (the column `kind`)
  std::vector<std::string> stop_reasons;  // why each curve ended, one per curve
  Table points, codim2;                 // /curves/points, /curves/codim2
  std::vector<std::string> codim2_names;  // /curves/codim2@names, one per codimension-2 point
};

// Each throws std::runtime_error naming the path when it cannot be written, and leaves no file.
void write_orbits_file(const std::filesystem::path& out, const std::string& command_line,
                       const config::OrbitsConfig& cfg, const OrbitsOutput& o);
void write_curves_file(const std::filesystem::path& out, const std::string& command_line,
                       const config::OrbitsConfig& cfg, const CurvesOutput& c);

}  // namespace ajx::results
