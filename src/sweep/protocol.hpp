// A sweep protocol: a chain of motor segments (linear ramps, and step-and-hold staircases)
// compiled into one motor schedule, the measurement windows along it, and its split into
// tasks for the farm. A ramp is history-dependent, so the tasks of one chain run in order,
// each from the final state of the previous one.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "physics/drive.hpp"

namespace ajx::sweep {

// A linear ramp of ω_m from `from` to `to` at |dω_m/dt| = rate, measured in windows of
// `window` seconds along the way.
struct Ramp {
  double from;    // [rad/s]
  double to;      // [rad/s]
  double rate;    // [rad/s²], > 0
  double window;  // [s], > 0
};

// A staircase of `num` levels from `from` to `to` (both included): between levels ω_m ramps
// at `step_rate`, then holds for `settle` (transient, not measured) and `measure` (one window).
struct Steps {
  double from, to;      // [rad/s]
  int num;              // >= 1
  double settle;        // [s], >= 0
  double measure;       // [s], > 0
  double step_rate;     // [rad/s²], > 0
};

struct Segment {
  enum class Kind { Ramp, Steps } kind;
  Ramp ramp{};
  Steps steps{};
};

// One classification window: [t_begin, t_end] of the chain's schedule.
struct Window {
  double t_begin, t_end;        // [s]
  double omega_begin, omega_end;  // ω_m at its ends [rad/s]
  int segment;                  // index of the protocol segment it belongs to
  int direction;                // +1 ω_m rising, -1 falling (ramps and staircases), 0 one held level
  double t_settle = t_begin;    // start of the held, unmeasured stretch before it (t_begin: none) [s]
};

// One piece of a chain for the farm: consecutive windows, integrated from t_begin to t_end.
struct TaskSpan {
  double t_begin, t_end;  // [s]
  int first_window, num_windows;
};

struct CompiledProtocol {
  std::vector<physics::DriveSegment> schedule;  // starts from omega_start at t = 0
  std::optional<physics::HandPath> hand;        // a hand holds the top first (basin family hand)
  std::vector<Window> windows;
  double duration = 0.0;                        // [s]
};

// Compile from a starting ω_m (0 for a start from rest). A segment that starts away from the
// current ω_m is reached by a ramp at its own rate (ramps) or step_rate (steps), unmeasured.
// Throws std::invalid_argument for empty protocols or non-positive rates, windows or times.
CompiledProtocol compile(const std::vector<Segment>& segments, double omega_start = 0.0);

// Split the windows into tasks of at most `windows_per_task` windows; task boundaries fall on
// window boundaries, and a task ends where its last window ends (unmeasured stretches before
// a window belong to the task that measures it).
std::vector<TaskSpan> split(const CompiledProtocol& p, int windows_per_task);

}  // namespace ajx::sweep
