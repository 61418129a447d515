// Where fixed-step methods fail: the largest step that still gives an acceptable run of a
// scene held at ω_m, and what goes wrong above it (blow-up, the wrong final contact mode,
// energy injected against the drag).
#pragma once
#include <string>
#include <vector>

#include "bench/work_precision.hpp"

namespace ajx::bench {

// A run is acceptable when it finishes, ends in the reference's contact mode, and its
// energy-balance residual (spurious energy: injected by the method, or lost) stays below
// energy_tol of the largest energy term.
struct StabilityCriteria {
  double energy_tol = 1e-2;
};

struct StabilityRow {
  double omega = 0.0;  // ω_m held [rad/s]
  std::string method;
  double step = 0.0;   // [s]
  Outcome out;
  Errors err;
  bool pass = false;
};

// The scene with its schedule replaced by ω_m held over the horizon.
Scene held_at(const Scene& base, double omega);

bool acceptable(const Outcome& o, const Errors& e, const StabilityCriteria& c);

// Scans h = h_max 2^(-k/2) downwards (k = 0, 1, ..., while h >= h_min) and returns the first
// step that passes together with the next two smaller ones (robust to a lucky pass above the
// limit), or 0 if none. Every run is appended to rows.
double largest_stable_step(const Scene& scene, const std::string& method, const Reference& ref,
                           const StabilityCriteria& c, double h_max, double h_min, std::vector<StabilityRow>& rows);

}  // namespace ajx::bench
