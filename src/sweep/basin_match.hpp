// Attractors of a basin sweep matched across ω_m: each sampled start that ended on an orbit gets
// the label of its attractor, one label per orbit carried along the levels, so that a basin can
// be followed as ω_m changes (as Attractors.jl's global continuation matches attractors).
//
// An orbit is described by four scaled features x = (ln(ω_ball / 1 rad/s), ρ1/l, ρ2/l, s/l):
// the logarithm because a locked orbit's ω_ball moves with ω_m, a lagging one's hardly at all.
// Each feature of each window has a half-width h, what one window resolves of it:
//   h_ρ = (e + δ_ρ ρ̄)/l,  h_s = (e + δ_s l)/l,  h_ω = |ω_bead − ω_bottom|/(2|ω_ball|) + δ_ω,
// e = √2 max(σ_ρ1, σ_ρ2, σ_s) the orbit's extent in the string's configuration (σ a length's
// standard deviation over the window, √2 σ the amplitude of a sinusoidal swing with it: a flower
// sweeps its radii over e while its bead stays stuck, so a bead place within e of another's does
// not tell two flowers apart), ω_bead − ω_bottom the two balls' disagreement on ω_ball, and δ the
// classifier's drift tolerances (a window is called settled while its mean still moves by that
// much between its halves, so its mean is known to no better).
//
// At one level, two starts of one class are the same orbit when every feature's bands x ± h
// overlap, |x_i − x_j| <= h_i + h_j; single linkage makes the attractors. fallen, not-settled and
// failed are one attractor at every level whatever their features (the fallen bead makes a driven
// spherical pendulum whose leftover swing tells starts apart, not orbits; the others are not
// orbits). An attractor's reach r is the union of its members' bands about its centroid c.
//
// From one level to the next (Attractors.jl's matching by distance with a threshold, vanished
// attractors kept): an attractor is compared with every label of its class seen so far in its
// part, where it was last seen, |Δ ln ω_m| away, by
//   q_i = |c_i − c'_i| / (r_i + r'_i + Δ_i),  Δ_ω = |Δ ln ω_m|,  Δ_i = |Δ ln ω_m| max(|c_i|, |c'_i|),
// the two reaches plus the largest change of the feature along one family of orbits, taken as
// proportional to ω_m at most (|d ln y / d ln ω_m| <= 1: a locked orbit's ω_ball meets it with
// equality). max_i q_i <= 1: the same orbit could have moved there; the pairs take labels in
// rising √(Σ q_i²), one to one; an attractor with no label within the bound starts a new one.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "sweep/orbit_classes.hpp"

namespace ajx::sweep {

// Whether a class's orbits are told apart by their features: not fallen, not-settled or failed.
constexpr bool basin_split_class(OrbitClass c) {
  return c != OrbitClass::Fallen && c != OrbitClass::NotSettled && c != OrbitClass::Failed;
}

inline constexpr std::size_t kNumMatchFeatures = 4;
using MatchPoint = std::array<double, kNumMatchFeatures>;

// What one window gives the matching, in physical units.
struct WindowFeatures {
  double omega_ball, omega_bead, omega_bottom;  // ω_ball, each ball's [rad/s] (NaN: unreliable)
  double rho1, rho1_std, rho2, rho2_std;        // mean radii and their deviations [m]
  double s, s_std;                              // bead position L1 and its deviation [m]
};
// The classifier's drift tolerances (relative): ClassifierSettings' radius_, omega_, L1_drift_tol.
struct DriftTolerances {
  double radius, omega, L1;
};

struct MatchSample {
  std::int32_t level = -1;  // its level's row
  std::int32_t cls = -1;    // its class, -1 not computed
  MatchPoint x{}, h{};      // scaled features and their half-widths
};
MatchSample match_sample(std::int32_t level, std::int32_t cls, const WindowFeatures& w, const DriftTolerances& d,
                         double string_length);

// Two samples of one split class at one level are the same orbit.
bool same_orbit(const MatchSample& a, const MatchSample& b);

struct MatchLevel {
  std::int32_t part;  // the (group, variant) part: labels are matched within a part
  double omega;       // ω_m [rad/s]
};

struct Attractor {
  std::int32_t part, cls;
  int letter;        // 0, 1, ...: the attractors of its class in its part, in order of appearance
  std::string name;  // the class's name, with " A", " B" when its class has more than one
};

struct BasinMatch {
  std::vector<std::int32_t> label;  // per sample: its attractor's row, -1 not computed
  std::vector<Attractor> attractors;
};

// `split[c]`: class c's orbits are told apart by their features (else one attractor per level);
// `class_names[c]` its name.
BasinMatch match_attractors(std::span<const MatchLevel> levels, std::span<const MatchSample> samples,
                            std::span<const bool> split, std::span<const std::string> class_names);

}  // namespace ajx::sweep
