// astrojax orbits --map PARAM: the curves that predict the thresholds (orbits/threshold_curves.hpp)
// followed in the plane of ω_m and PARAM; tables on stdout, CSV and HDF5 on request.
#pragma once
#include <vector>

#include "app/commands.hpp"
#include "config/config.hpp"

namespace ajx::app {

// Throws config::ConfigError on a --map request that cannot run (before any work).
void check_map_args(const OrbitsArgs& args, const config::OrbitsConfig& cfg);

// Runs the request (omegas: where the one-parameter branches are picked up, used when --omega
// was given); returns the exit code.
int orbits_map(const config::OrbitsConfig& cfg, const std::vector<double>& omegas, const OrbitsArgs& args);

}  // namespace ajx::app
