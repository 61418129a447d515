// The orbit classifier: one measurement window of a sweep in, one orbit class out.
// The classes and their exact criteria: docs/physics/orbit-classes.md.
#pragma once
#include <array>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <vector>
#include <string_view>

#include "sweep/orbit_classes.hpp"

namespace ajx::physics {
struct Parameters;
}

namespace ajx::sweep {


// The samples of one window, borrowed (no copies). N samples at a fixed rate; r1 and r2 are
// row-major N×3 (x0, y0, z0, x1, ...). T1, T2 and mode may be empty: their statistics are
// then NaN, and "on the ball" is judged from L1 alone. Mode codes: 0 sliding, 1 bead on the
// bottom ball, 2 stuck, 3 top stop, 4 slack (physics::Mode); other codes count in no mode.
struct OrbitWindow {
  std::span<const double> t;        // [s], increasing
  std::span<const double> omega_m;  // motor frequency [rad/s]
  std::span<const double> r1, r2;   // bead and bottom ball [m], 3N values each
  std::span<const double> L1;       // bead distance from the top along the string [m]
  std::span<const double> T1, T2;   // tensions above and below the bead [N]
  std::span<const int> mode;        // contact mode code
  bool failed = false;              // the integration failed in or before this window
  std::string_view failure;         // the caller's reason, quoted in the result
};

// The model's scales the criteria are relative to.
struct OrbitScales {
  double string_length = 0.826;                // l [m]
  double contact_distance = 0.03;              // d [m]: L2 = l − L1 ≥ d
  double gravity = 9.81;                       // g [m/s²]
  double drag_rate = 1.7245e-3 / (2 * 0.018);  // γ = c_D/(m1 + m2) [1/s]
  double pendulum_rate() const;                // √(g/l) [rad/s]
};
OrbitScales orbit_scales(const physics::Parameters& p);

struct ClassifierSettings {
  // reliability
  int min_samples = 16;                        // fewer: not-settled, confidence 0
  double radius_floor = 2e-3;                  // [m] mean radius below which ω_ball is NaN
  double min_samples_per_turn = 4.0;           // azimuth steps above 2π/this are under-sampled
  double max_undersampled_fraction = 0.01;     // ... ω_ball unreliable when more steps are
  double ambiguous_step = 0.9 * std::numbers::pi;  // [rad] any larger step: unreliable
  // the bead on the bottom ball
  double on_ball_tol = 0.02;                   // |l − L1 − d| ≤ this·d counts as on the ball
  double fallen_fraction = 0.5;                // fallen when on the ball this much of each half
  double on_ball_change_tol = 0.25;            // largest change of the on-ball fraction
  // steadiness (changes between halves)
  double radius_drift_tol = 0.05;              // |Δρ̄|/ρ̄
  double omega_drift_tol = 0.02;               // min(|Δω_ball|/|ω_ball|, |Δν|/|ν|)
  double L1_drift_tol = 0.01;                  // |ΔL̄1|/l
  double spread_drift_tol = 0.10;              // flower: |Δσ_ρ|/σ_ρ
  double min_cycles = 4.0;                     // oscillation cycles per window for the allowance and for a flower
  double max_rate_in_drag_units = 0.5;         // circular: |ρ̇/ρ| ≤ this·γ
  // shape and rotation
  double circular_max_rel_amplitude = 0.10;    // a/ρ̄ of a circular orbit
  double locked_tol = 0.02;                    // |ν − 1| of a locked orbit
  double free_swing_band = 0.25;               // |ω_ball/√(g/l) − 1| of a free swing
  // confidence
  double single_ball_penalty = 0.7;
  double no_orbit_confidence = 0.3;
};

// Mean, standard deviation (population), extremes; NaN when there are no samples.
struct Moments {
  double mean = std::numeric_limits<double>::quiet_NaN();
  double std = std::numeric_limits<double>::quiet_NaN();
  double min = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();
};

struct BallStats {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  double omega = nan;             // ω_ball [rad/s], least-squares slope; NaN when unreliable
  double omega_raw = nan;         // the slope whatever its reliability [rad/s]
  double omega_first = nan;       // slope over the first half [rad/s] (raw)
  double omega_second = nan;      // slope over the second half [rad/s] (raw)
  bool radius_ok = false;         // mean radius ≥ radius_floor
  bool unwrap_ok = false;         // azimuth sampled finely enough
  bool omega_reliable = false;    // radius_ok && unwrap_ok
  double max_azimuth_step = nan;  // largest |Δθ| between samples [rad]
  double undersampled_fraction = nan;  // steps above 2π/min_samples_per_turn
  Moments rho;                    // horizontal radius [m]
  Moments z;                      // height [m]
  double rho_amplitude = nan;     // a: √2 × std of ρ about its linear trend [m]
  double rho_rel_amplitude = nan; // a/ρ̄
  double rho_cycles = nan;        // radius oscillation cycles in the window
  double rho_trend = nan;         // (dρ/dt)/ρ̄, least squares [1/s]
  double rho_half_change = nan;   // (ρ̄₂ − ρ̄₁)/ρ̄
  double rho_half_allowance = nan;    // oscillation allowance for it (relative)
  double rho_std_half_change = nan;   // (σ₂ − σ₁)/σ̄ of ρ
  double omega_half_change = nan;     // (ω₂ − ω₁)/|ω_raw|
  double rotation_half_change = nan;  // (ν₂ − ν₁)/|ν|
  double omega_half_allowance = nan;  // oscillation allowance for both (relative)
};

struct OrbitStats {
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  long samples = 0;
  double t_begin = nan, t_end = nan;   // [s]
  Moments omega_m;                     // [rad/s]
  std::array<BallStats, 2> ball;       // bead, bottom ball
  double omega_ball = nan;             // mean ω_ball of the reliable balls [rad/s]
  double rotation_number = nan;        // ν = omega_ball / mean ω_m
  double omega_pendulum = nan;         // √(g/l) [rad/s], for reference
  bool free_swing_like = false;        // decays at a drag-like rate near √(g/l) (rule 7)
  Moments L1;                          // [m]
  double L1_half_change = nan;         // (L̄1₂ − L̄1₁)/l
  double L1_half_allowance = nan;      // relative to l
  Moments T1, T2;                      // [N]
  std::array<double, 5> mode_fraction{nan, nan, nan, nan, nan};  // occupancy of modes 0..4
  double on_ball_fraction = nan;       // the bead on the bottom ball (mode 1 or L2 ≈ d)
  double on_ball_first = nan, on_ball_second = nan;  // ... in each half
};

struct OrbitClassification {
  OrbitClass cls = OrbitClass::NotSettled;
  double confidence = 0.0;  // in [0, 1]; see the header comment
  std::string reason;       // one line, ASCII
  OrbitStats stats;
};

// Settings from "name=value" strings, by the names of the tunable fields above (the
// tolerances and floors; values > 0). Throws std::invalid_argument naming the string and the
// allowed names.
ClassifierSettings parse_classifier_settings(const std::vector<std::string>& name_values);

// The settings --set classifier.NAME=value may change: name, field, unit, meaning.
struct ClassifierSettingInfo {
  std::string_view name;
  double ClassifierSettings::*field;
  std::string_view unit, doc;
};
std::span<const ClassifierSettingInfo> classifier_setting_table();

// Pure: no I/O, no state. Throws std::invalid_argument when the array sizes disagree
// (r1, r2: 3N; omega_m, L1: N; T1, T2, mode: N or empty).
OrbitClassification classify_orbit(const OrbitWindow& w, const OrbitScales& scales,
                                   const ClassifierSettings& settings = {});

}  // namespace ajx::sweep
