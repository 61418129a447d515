// The orbit classifier: one measurement window of a sweep in, one orbit class out.
//
// ## Orbit classification (what `classify_orbit` decides, and how)
//
// Input: the samples of one window at a fixed rate (t, ω_m, r1, r2, L1, T1, T2, mode), the
// model scales l (string length), d (contact distance), g and the drag rate γ = c_D/(m1+m2)
// (the amplitude decay rate of a free swing: ≈ 0.048/s for the paper's balls), and settings.
// z is up and the motor axis is x = y = 0. Every default below is a field of
// `ClassifierSettings`.
//
// Per ball: horizontal radius ρ = √(x² + y²); azimuth θ = atan2(y, x), unwrapped by taking
// each step between samples in (−π, π]. ω_ball is the least-squares slope of θ(t) over the
// window (not the endpoint difference); for a steady orbit it is the mean angular velocity,
// for a flower the rotation rate of the pattern. The rotation number is ν = ω̄_ball / ω̄_m,
// with ω̄_ball the mean over the balls whose ω_ball is reliable and ω̄_m the window mean.
// The window is split in two halves at its middle time; "changes between halves" compare
// the statistics of the two halves.
//
// Reliability of ω_ball (per ball). ω_ball is reported as NaN (its raw slope stays in
// `omega_raw`) and is not used for a decision when
//   - the mean radius is below radius_floor = 2 mm: the azimuth of a ball that hangs on the
//     axis is noise; or
//   - the azimuth is under-sampled: any step exceeds 0.9π (ambiguous), or more than 1 % of
//     the steps exceed 2π/min_samples_per_turn = π/2, i.e. fewer than 4 samples per turn.
// With ω_ball unreliable for both balls no window is classified locked or lagging.
//
// Oscillation allowance. A quasi-periodic signal of amplitude a with n cycles per half
// biases each half's mean by at most a/(π n) and each half's least-squares slope by at
// most 6a/(π n τ) (τ the half's duration). The half-change tolerances below are widened by
// twice these bounds (two halves) when the window holds at least min_cycles = 4 cycles;
// a is √2 × the standard deviation of the signal about its linear trend, and the cycles are
// counted as sign changes of that residual with a hysteresis of half its standard deviation.
//
// Decisions, in order (the first that applies wins):
//  1. failed: the caller says the integration failed (`OrbitWindow::failed`), or a sample is
//     not finite.
//  2. not-settled, confidence 0: fewer than min_samples = 16 samples, or zero duration.
//  3. fallen: the bead is on the bottom ball for at least fallen_fraction = 50 % of each
//     half. On the ball means mode 1 (bottom stop), or |l − L1 − d| ≤ on_ball_tol·d with
//     on_ball_tol = 0.02. A fallen pendulum is fallen whatever it does: a small driven
//     circle, hanging still below the radius floor, or a decaying free swing. The free swing
//     is the transient of the spherical pendulum the fallen Astrojax is; the class is decided
//     by where the bead is, and the reason names the swing.
//     If only one half has the bead on the ball, it fell onto (or rose from) the ball inside
//     the window: not-settled.
//  4. not-settled when a statistic drifts between halves beyond its tolerance:
//     - the on-ball fraction changes by more than on_ball_change_tol = 0.25;
//     - the mean of L1 changes by more than L1_drift_tol·l = 0.01 l (+ allowance);
//     - for each ball above the radius floor: the mean radius changes by more than
//       radius_drift_tol = 5 % of the mean radius (+ allowance);
//     - for each ball with a reliable ω_ball: ω_ball changes by more than
//       omega_drift_tol = 2 % both in the lab frame (|Δω_ball|/|ω_ball|) and in the motor's
//       frame (|Δν|/|ν|), + allowance. Steady in either frame suffices: during a slow ramp a
//       locked orbit follows ω_m and a lagging one keeps its ω_ball.
//  5. not-settled (confidence no_orbit_confidence = 0.3) when both balls are below the
//     radius floor with the bead off the bottom ball: no orbit to measure. A still pendulum
//     with the bead off the ball is no steady state: a straight string cannot hold the bead
//     by friction (zero deflection, zero normal force), so it slides down to the ball.
//  6. Shape: the relative radius oscillation A_rel = a/ρ̄ (a as above, for each ball above
//     the floor; the larger of the two decides). Circular when A_rel ≤
//     circular_max_rel_amplitude = 0.10.
//  7. A circular orbit must not decay or grow: |ρ̇/ρ| ≤ max_rate_in_drag_units·γ = 0.5 γ
//     (ρ̇/ρ the least-squares slope of ρ over the mean radius). This rejects the lightly
//     damped free swing a resonance leaves behind, whose amplitude decays at about γ and
//     whose ω_ball sits near √(g/l) ≈ 3.4 rad/s whatever ω_m is, even in a window too short
//     for rule 4 to see the decay: not-settled, and `free_swing_like` is set when also
//     |ω_ball/√(g/l) − 1| ≤ free_swing_band = 0.25.
//  8. Circular and steady, ω_ball reliable, ν defined (ω̄_m ≠ 0):
//     - locked-circular when |ν − 1| ≤ locked_tol = 0.02;
//     - lagging-circular when 0 < ν < 1 − locked_tol (the bead off the ball by rule 3);
//     - otherwise not-settled: a steady driven orbit cannot lead the motor or turn against it.
//     Without a reliable ω_ball: not-settled with confidence 0 (cannot judge the rotation).
//  9. Not circular and steady: flower when the radius oscillation is quasi-periodic (at
//     least min_cycles = 4 cycles in the window; fewer: not-settled, confidence 0) and its
//     size is stationary: the radius standard deviation changes between halves by at most
//     spread_drift_tol = 10 % (+ 1/(π n) for n cycles in the window). Otherwise not-settled. A
//     flower without a reliable ω_ball (the pattern passes over the axis) keeps its class
//     with half the confidence.
//
// Confidence, in [0, 1]. Each criterion that supports the class compares a measured value
// q with its threshold X. Its margin is 0 at the threshold and grows linearly to 1 when q
// clears X by half of X (q ≤ X/2 for an upper bound, q ≥ 1.5 X for a lower one, |ν − 1| ≤
// 0.01 for locked, 1 − ν ≥ 0.03 for lagging). For fallen the criterion is the on-ball
// fraction of the worse half ≥ 0.5 (margin 1 from 0.75). For locked, lagging and flower
// the criteria are the shape, the rotation, each steadiness test of rule 4, the decay rate
// (circular only), the spread test of rule 9 (flower only) and "bead off the ball"
// (on-ball fraction ≤ 0.5, margin 1 at ≤ 0.25).
// For not-settled, the margin is how far the deciding statistic exceeds its tolerance (the
// worst half-change, the decay rate, ν − 1 when leading, the change of the on-ball fraction
// when the bead fell or rose): 0 at the tolerance, 1 at 1.5× it; a retrograde orbit has
// margin 1. The confidence is the smallest margin,
// multiplied by single_ball_penalty = 0.7 when only one ball has a usable radius or
// ω_ball, and by 0.5 for a flower without a reliable ω_ball. Confidence 0 marks a window
// the classifier could not judge; failed has confidence 1.
#pragma once
#include <array>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <vector>
#include <string_view>

namespace ajx::physics {
struct Parameters;
}

namespace ajx::sweep {

enum class OrbitClass { Fallen, LockedCircular, LaggingCircular, Flower, NotSettled, Failed };

// "fallen", "locked-circular", "lagging-circular", "flower", "not-settled", "failed".
std::string_view to_string(OrbitClass c);
std::optional<OrbitClass> parse_orbit_class(std::string_view name);

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

// Pure: no I/O, no state. Throws std::invalid_argument when the array sizes disagree
// (r1, r2: 3N; omega_m, L1: N; T1, T2, mode: N or empty).
OrbitClassification classify_orbit(const OrbitWindow& w, const OrbitScales& scales,
                                   const ClassifierSettings& settings = {});

}  // namespace ajx::sweep
