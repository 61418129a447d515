// The measured thresholds of one chain, found from its sequence of window classes along the
// protocol (docs/guide/thresholds.md). Each is a bracket: the two ω_m between which
// the class changed (the mean ω_m of the last window before and of the first window after).
//   ω_rise  rising ω_m: the first window that is no longer fallen after fallen ones (the bead
//           starts to climb);
//   ω_fall  falling ω_m: the first fallen window after a circular one (locked or lagging),
//           not-settled windows in between allowed (the fall itself takes time);
//   ω1      rising ω_m: the last locked-circular window followed by one that is not locked;
//   ω2      rising ω_m: the last steady circular window (locked or lagging) followed by one
//           that is neither (flower or not settled).
// Windows with failed integrations end the search on their side.
#pragma once
#include <array>
#include <optional>
#include <string_view>
#include <vector>

#include "sweep/orbit_classifier.hpp"

namespace ajx::sweep {

struct ClassedWindow {
  double omega_begin, omega_end;  // ω_m at the window's ends [rad/s]
  int direction;                  // +1 rising, -1 falling, 0 a single held level
  OrbitClass cls;
  int index = -1;                 // the window's index in its chain
  double omega_mean() const { return 0.5 * (omega_begin + omega_end); }
};

struct Bracket {
  double before;  // mean ω_m of the last window of the old class [rad/s]
  double after;   // mean ω_m of the first window of the new class [rad/s]
  int window_before = -1, window_after = -1;  // their indices in the chain
  double mid() const { return 0.5 * (before + after); }
};

enum class Threshold { Rise, Fall, Omega1, Omega2 };
inline constexpr std::array<Threshold, 4> kThresholds{Threshold::Rise, Threshold::Fall, Threshold::Omega1,
                                                      Threshold::Omega2};
std::string_view to_string(Threshold t);     // "omega_rise", "omega_fall", "omega_1", "omega_2"
double paper_value(Threshold t);             // the paper's measured value [rad/s]

// Windows in protocol order (unclassified ones left out by the caller).
std::optional<Bracket> find_threshold(Threshold t, const std::vector<ClassedWindow>& windows);

}  // namespace ajx::sweep
