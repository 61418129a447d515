// Run configuration from a TOML file in sweeps/ plus command-line overrides. Every key is
// checked (unknown keys, types, ranges) before any work starts; errors name the file, the
// key and the allowed range.
#pragma once
#include <limits>
#include <stdexcept>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "physics/drive.hpp"
#include "physics/model.hpp"
#include "physics/state.hpp"
#include "sim/simulation.hpp"
#include "sweep/basin.hpp"
#include "sweep/grid.hpp"
#include "sweep/plan.hpp"

namespace ajx::config {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct InitialSpec {
  // "hanging" (at rest on the bottom stop), "explicit", or a two-step start (positions at t = 0
  // and t = integrator.step): "table1" (the paper's Table 1, `orbit`) or "pair" (r1, r2, r1_next, r2_next).
  std::string preset = "hanging";
  std::string orbit;               // "table1": circular1, circular2, flower1 ... flower4
  double orbit_omega = std::numeric_limits<double>::quiet_NaN();  // "table1": θ = ω h [rad/s] (NaN: ω_m(0))
  physics::Vec3 r1_next = physics::Vec3::Zero(), r2_next = physics::Vec3::Zero();  // "pair" [m]
  physics::Vec3 r1 = physics::Vec3::Zero(), r2 = physics::Vec3::Zero();  // [m]
  physics::Vec3 v1 = physics::Vec3::Zero(), v2 = physics::Vec3::Zero();  // [m/s]
  physics::Mode mode = physics::Mode::Sliding;
  double length_tolerance = 1e-6;  // |L1 + L2 - l| accepted before projection [m]
  // With the tie clutch: the tie starts slipping on the rod at χ = φ(0) with this χ̇ [rad/s]
  // (NaN: held, the default).
  double tie_slip_rate = std::numeric_limits<double>::quiet_NaN();
};

struct OutputSpec {
  std::string path = "out/run.h5";
  double sample_interval = 0.01;  // [s]
};

// The sections every command reads: [model], [layers], [integrator], [initial].
struct CommonConfig {
  std::string source_name;               // file name, for messages and provenance
  std::string source_text;               // the file verbatim
  std::vector<std::string> overrides;    // "key=value" as given on the command line
  physics::Model model;
  sim::RunOptions run;
  InitialSpec initial;
};

// astrojax run: plus [[schedule]] and [output].
struct RunConfig : CommonConfig {
  std::vector<physics::DriveSegment> schedule;
  OutputSpec output;
};

// astrojax sweep: plus [protocol] with [[protocol.segment]] (or [hold]), an optional [grid] and
// [output]; the sweep-specific fields are sweep::SweepSpec's. Every grid point runs the whole
// protocol from the initial state: one chain each.
struct SweepConfig : CommonConfig, sweep::SweepSpec {
  // A file with [[group]] tables (chain groups) or [variant.NAME] tables (model variants) is
  // one sweep made of parts: each group runs once per variant it names, each (group, variant)
  // read as a sweep of its own from the file's tables with the variant's and the group's
  // merged over them. `parts` is empty for a plain file; then this config is the only part.
  std::vector<SweepConfig> parts;
  std::string group;            // a part's group name ("" for a plain file)
  std::string group_purpose;    // why its chains are there (the group's `purpose`)
  std::string variant;          // a part's model variant ("" for a plain file)
  std::string variant_label;    // what the variant is, e.g. "the paper's physics (rigid tie)"

  std::string output_path = "out/sweep.h5";
};

// What the planner needs of each part (one for a plain file), in the order of `parts`.
std::vector<sweep::PlanPart> plan_parts(const SweepConfig& c);
// Reads basin.state's window of a sweep file (the end of window `window` of chain `chain`);
// throws with a message naming the file. results/ owns sweep files: the application registers
// its reader (results::read_stored_orbit) before it reads a configuration; unregistered, a
// basin.state is refused.
using StoredOrbitReader = sweep::StoredOrbit (*)(const std::string& file, long chain, long window);
void set_stored_orbit_reader(StoredOrbitReader reader);

inline sweep::SweepPlan make_plan(const SweepConfig& c) { return sweep::make_plan(plan_parts(c)); }

// The most chains a sweep may have: its plan and file layout are held in memory on rank 0
// (about 1 kB a chain), and a grid that multiplies past this is a typing error more often than
// a plan. Checked before the grid is expanded, for each part of a grouped sweep and for all its
// parts together.
inline constexpr std::size_t kMaxChains = 1'000'000;

SweepConfig parse_sweep_config(std::string_view text, std::string_view source_name,
                               const std::vector<std::string>& overrides = {});
SweepConfig load_sweep_config(const std::string& path, const std::vector<std::string>& overrides = {});

// astrojax orbits: the [model] and [layers] of any run or sweep file (their other tables are
// accepted and not read), plus an optional [orbits] table.
struct OrbitsSpec {
  std::vector<double> omega;           // ω_m values [rad/s], in (0, 2000]
  int s_points = 81;                   // the stuck family sampled along the string
  std::string parameter;               // continue in this parameter ("" : no continuation)
  double range_lo = 0.0, range_hi = 0.0;  // the continuation's interval (both 0: a default)
  std::vector<double> s;               // stuck orbits to continue, bead positions [m]
};
struct OrbitsConfig : CommonConfig {
  OrbitsSpec orbits;
};
OrbitsConfig parse_orbits_config(std::string_view text, std::string_view source_name,
                                 const std::vector<std::string>& overrides = {});
OrbitsConfig load_orbits_config(const std::string& path, const std::vector<std::string>& overrides = {});

// Parse and validate. Overrides are "dotted.key=value" with a TOML value (a bare word is
// taken as a string). Throws ConfigError.
RunConfig parse_run_config(std::string_view text, std::string_view source_name,
                           const std::vector<std::string>& overrides = {});
RunConfig load_run_config(const std::string& path, const std::vector<std::string>& overrides = {});

}  // namespace ajx::config
