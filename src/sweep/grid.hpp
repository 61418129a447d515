// What a sweep asks for, before it is planned: the protocol every chain runs, where the chains
// start, and the grid of parameter values (or the held ω_m values) that makes them several.
// The configuration layer reads these from TOML; expand_grid turns a grid into chains.
#pragma once
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "physics/model.hpp"
#include "sweep/basin.hpp"
#include "sweep/bisection.hpp"
#include "sweep/protocol.hpp"

namespace ajx::sweep {

// A grid point or a grid value that cannot be run; the message names the file and the key.
class GridError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// One axis of [grid]: a model parameter the parameter table marks as a grid axis (or its alias
// "mass"), or "ramp_rate", which sets the rate of every ramp of the protocol.
struct GridAxis {
  std::string key;
  std::vector<double> values;  // in SI units
};

inline constexpr std::string_view kRampRateAxis = "ramp_rate";
bool is_grid_axis(std::string_view key);
std::vector<std::string> grid_axis_keys();  // the parameters, then ramp_rate

// The hold mode: every ω_m of a list held fixed, from several seed states each, to find which
// orbits coexist at one ω_m without ramping. Replaces the protocol when present.
struct HoldSpec {
  std::vector<double> omega;                // ω_m values [rad/s]
  double settle = 60.0;                     // transient before measuring [s]
  double measure = 10.0;                    // the measured window [s]
  std::vector<std::string> seeds{"hanging"};  // "hanging", "circular_high", "locked_orbit"
  int perturbations = 0;                    // extra copies of each seed with random velocity kicks
  double perturbation = 0.01;               // size of a kick [m/s]
};

// The sweep-specific part of a sweep's description (the model and integrator are beside it).
struct SweepSpec {
  std::vector<Segment> protocol;
  double start_omega = 0.0;            // ω_m at t = 0 [rad/s]
  std::string start_seed = "hanging";  // the state at t = 0: a seed of sweep/seeds.hpp at start_omega
  int windows_per_task = 10;           // granularity of the farm's tasks
  double sample_rate = 100.0;          // samples per second stored for every window [1/s]
  // Settling that stops once its orbit is a fixed point or a periodic orbit of the frame turning
  // with the top, converging at a measured rate, to within early_stop_tolerance × l
  // (sim/settle_watch.hpp). [protocol] and [hold] turn it on unless their early_stop = false
  // (config.cpp); a chain group without that key ([basin], [bisect]) settles in full.
  bool early_stop = false;
  // ε: a hundredth of the classifier's tightest drift tolerance, L1_drift_tol (a tenth moved the
  // main job's ω2: docs/reports/early-stop-and-every-core.md).
  double early_stop_tolerance = 1e-4;
  std::vector<GridAxis> grid;
  std::optional<HoldSpec> hold;
  std::optional<BasinSpec> basin;  // basin sampling (sweep/basin.hpp); replaces the protocol when present
  std::optional<BisectSpec> bisect;    // [bisect]: a threshold by bisection, instead of the protocol
};

// One chain of a sweep: its parameters and protocol.
struct GridPoint {
  std::vector<double> values;  // one per grid axis, in the order of SweepSpec::grid
  physics::Model model;
  std::vector<Segment> protocol;
};

// The Cartesian product of the axes over `base` (the first axis varies slowest, the last
// fastest); one point if there is no grid. Every point is validated; a GridError names
// `source_name`, the parameter and the grid indices.
std::vector<GridPoint> expand_grid(const physics::Model& base, const SweepSpec& spec, std::string_view source_name);

}  // namespace ajx::sweep
