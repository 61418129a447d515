// Basin sampling: a chain group whose start is a distribution instead of a seed. At every
// ω_m level N initial conditions are drawn, each held at its level (settle, then one measured
// window) and classified as any window is, so that the fraction of starts ending on each orbit
// estimates the size of its basin under that distribution. Three families of starts:
//   hanging  both balls hanging below the top, the bead at s ~ U[s_lo, s_hi] along the string,
//            each segment swung from the vertical by an angle ~ U[0, θ_max] in a uniform
//            azimuth, released at rest; the motor at the level from t = 0;
//   hand     the hanging rest state (bead on the bottom ball); a hand holds the top and moves it
//            along a random planar path for T (physics/hand.hpp: x_top = a + sin²(πt/T) h, h of K
//            Fourier modes with amplitudes in the disc of radius A/2K), then hands it over to the
//            motor, which ramps from rest at `step_rate` from t = 0 to the level and holds it;
//   cloud    an orbit (a seed of seeds.hpp at the level: locked_orbit or circular_high, or a state
//            stored in a sweep file: the end of one of its windows, `state`) with each
//            ball moved across the string by a displacement uniform in a disc of radius ε (s and
//            l − s kept, so the stops are kept) and each velocity component moved by ε ω_m × U[−1, 1].
// Every draw comes from a counter-based generator keyed by (family, seed, level, sample): the
// same start on any number of ranks, any platform, in any order.
#pragma once
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "physics/drive.hpp"
#include "physics/model.hpp"
#include "physics/state.hpp"

namespace ajx::sweep {

struct CompiledProtocol;

enum class BasinFamily { Hanging, Hand, Cloud };
inline constexpr const char* kBasinFamilyNames[] = {"hanging", "hand", "cloud"};
std::string_view to_string(BasinFamily f);
std::optional<BasinFamily> parse_basin_family(std::string_view name);

// The state a cloud surrounds when it is read from a sweep file (basin.state = {file, chain,
// window}): the end of that window (its task's stored final state), a point on the orbit the
// window measured; the balls relative to the top, turned about the motor axis so that the top
// sits at azimuth 0.
struct StoredOrbit {
  std::string file;                 // the sweep file it was read from
  long chain = -1, window = -1;     // its chain and window there
  physics::Vec3 r1, r2, v1, v2;     // [m], [m/s]
  physics::Mode mode = physics::Mode::Sliding;
  double string_length = 0.0;       // l of the stored chain's model [m]
  double drive_radius = 0.0;        // R of the stored chain's model [m]
  double omega_m = 0.0;             // the window's ω_m at its end [rad/s]
};

// [basin] of a sweep or of a [[group]]: the levels, the samples per level and the family.
struct BasinSpec {
  std::vector<double> omega;       // ω_m levels [rad/s]
  int samples = 100;               // N starts per level, >= 1
  BasinFamily family = BasinFamily::Hanging;
  std::uint64_t seed = 1;          // the draws' stream; another seed, other starts
  double settle = 60.0;            // held before the measured window [s]
  double measure = 10.0;           // the measured window [s]
  double step_rate = 5.0;          // hand: the motor's ramp to the level [rad/s²]
  // hanging
  double s_lo = 0.0, s_hi = 0.0;   // bead position range [m]; both 0: l − d (on the bottom ball)
  double swing = 0.3;              // θ_max from the vertical [rad], hanging
  // hand
  double hand_amplitude = 0.1;     // A, |x_top − a| <= A [m]
  double hand_duration = 3.0;      // T [s]
  int hand_modes = 3;              // K
  // cloud
  std::string orbit = "locked_orbit";
  std::optional<StoredOrbit> stored;  // basin.state: the orbit read from a sweep file instead
  double epsilon = 0.01;           // ε [m]
};

// A basin that cannot be run (a draw that can leave the model's bounds, no orbit to surround);
// the message names the file and the key.
class BasinError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// The bead's allowed positions s in the model: [s_min or 0, l − d or l].
struct StopRange {
  double lo, hi;  // [m]
};
StopRange stop_range(const physics::Model& m);

// Checks that every draw of the family stays inside the model's bounds; throws BasinError
// naming `source_name` and the key ("basin.s", ...).
void check_basin(const physics::Model& m, const BasinSpec& b, std::string_view source_name);

// The chain's protocol: held at `omega` from t = 0 (hanging, cloud), or a ramp from rest to
// `omega` with the hand holding the top for T (hand: the schedule has a breakpoint at T); one
// measured window at the end.
CompiledProtocol basin_protocol(const BasinSpec& b, double omega, int level, int sample);

// The orbit a cloud surrounds at omega, on a chain's schedule (the stored state as it is, turned to
// the schedule's top at t = 0, when the spec has one); throws BasinError when there is none.
physics::State basin_orbit(const physics::Model& m, const physics::MotorSchedule& schedule, const BasinSpec& b,
                           double omega);

// The start of sample `sample` of level `level` (at ω_m = omega), on the chain's schedule; a
// cloud's `orbit` from basin_orbit (the same for every sample of a level: found once).
physics::State basin_start(const physics::Model& m, const physics::MotorSchedule& schedule, const BasinSpec& b,
                           double omega, int level, int sample, const physics::State* orbit = nullptr);

// The draws' generator: uniform doubles in [0, 1) from a 64-bit key by SplitMix64 (Steele,
// Lea, Flood 2014), whose output depends on nothing but the key and the counter.
class BasinDraws {
 public:
  BasinDraws(const BasinSpec& b, int level, int sample);
  double uniform();                       // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

 private:
  std::uint64_t state_;
};

// The 95 % Wilson score interval of k successes in n trials (z = 1.959963984540054):
// centre (k + z²/2)/(n + z²), half-width z √(k(n−k)/n + z²/4)/(n + z²). NaN for n = 0.
struct Interval {
  double lo, hi;
};
Interval wilson_interval(long k, long n);

}  // namespace ajx::sweep
