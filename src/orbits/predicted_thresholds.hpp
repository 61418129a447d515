// Thresholds predicted from the branches of locked orbits, against the paper's ramps
// (docs/guide/thresholds.md). A locked orbit with the bead high is a stuck orbit that
// is admissible (taut, inside the static cone, between the stops) and linearly stable. For
// each bead position s of a grid, every stuck branch found at a few starting ω_m is continued
// in ω_m; the intervals where it is admissible and stable are collected, with the event that
// ends each interval (fold, loss of stability, cone exit).
//   ω1      the highest ω_m with a stable admissible stuck orbit (any s): above it none is
//           left, the locked orbit is lost; compared with the measured 4.80π.
//   ω_fall  the lowest such ω_m: ramping down below it, no stuck orbit holds, the bead
//           slides; typically a cone exit downwards (the bead slides towards the ball);
//           compared with the measured 3.24π.
//   ω_rise  ramping up from hanging, the pair follows an orbit on the bottom stop, jumping at
//           folds to one that coexists; the first end that is not a fold: a loss of stability
//           ("omega_rise") or, stability ignored, the bead's cone letting it climb off the
//           ball ("omega_rise_cone"); compared with the measured 12.63π.
#pragma once
#include <string>
#include <vector>

#include "orbits/continuation.hpp"

namespace ajx::orbits {

struct LockedInterval {
  double s = 0.0;               // bead position [m]
  std::string branch;           // sides of bead / ball at the interval's start
  double omega_lo = 0.0, omega_hi = 0.0;  // [rad/s]
  std::string ends_lo, ends_hi; // the event at each end ("fold", "cone_exit_down", "range", ...)
};

struct ThresholdPrediction {
  std::string symbol;      // "omega_rise", "omega_rise_cone", "omega_fall", "omega1"
  double predicted = 0.0;  // [rad/s], NaN when the branches give none in the range
  double measured = 0.0;   // the paper's [rad/s]
  std::string mechanism;   // which event, at which s and on which branch
};

struct PredictionOptions {
  int s_points = 21;                       // bead positions from the top stop to the bottom stop
  std::vector<double> start_omega;         // where branches are picked up (default 3π, 5π, 8π, 12π)
  double omega_lo = 1.0, omega_hi = 0.0;   // continuation range [rad/s] (omega_hi 0: 20π)
};

struct Predictions {
  std::vector<LockedInterval> intervals;
  std::vector<ThresholdPrediction> thresholds;
};
Predictions predict_thresholds(const physics::Model& m, const PredictionOptions& opt = {});

// The end of the locked interval through one held orbit: the stuck orbit at ω0 with the bead
// at s*, found by Newton from a lab state y that settled there (its frame coordinates at the
// top's azimuth φ, the pulls from each ball's balance), continued in ω_m towards `limit` until it
// is no longer admissible and stable (a cone exit, a fold, a loss of stability). What a held
// orbit with its bead at s* predicts for ω_fall (limit below ω0) or ω1 (above): the
// continuation's cone_down and cone_up points at that s*. NaN when Newton does not converge
// within l/10 of the state, when the orbit is not locked at ω0, or when it stays locked
// up to `limit`.
double held_orbit_end(const physics::Model& m, double omega0, double s_star, const numerics::Vec& y, double phi,
                      double limit);

}  // namespace ajx::orbits
