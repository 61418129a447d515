#include "sweep/basin.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "physics/drive.hpp"
#include "sim/simulation.hpp"
#include "sweep/protocol.hpp"
#include "sweep/seeds.hpp"

namespace ajx::sweep {

std::string_view to_string(BasinFamily f) { return kBasinFamilyNames[int(f)]; }

std::optional<BasinFamily> parse_basin_family(std::string_view name) {
  for (int k = 0; k < 3; ++k)
    if (name == kBasinFamilyNames[k]) return BasinFamily(k);
  return std::nullopt;
}

StopRange stop_range(const physics::Model& m) {
  const physics::Parameters& p = m.p;
  return {m.layers.top_stop ? p.top_stop : 0.0, m.layers.bottom_stop ? p.string_length - p.contact_distance : p.string_length};
}

namespace {

// SplitMix64's finaliser: a bijection of 64-bit words that mixes every input bit into every output bit.
std::uint64_t mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

using physics::Vec3;

// A unit vector at polar angle θ from −ẑ (straight down) and azimuth α.
Vec3 hanging_direction(double theta, double alpha) {
  return {std::sin(theta) * std::cos(alpha), std::sin(theta) * std::sin(alpha), -std::cos(theta)};
}

// A point uniform in the disc of radius ε perpendicular to the unit vector u.
Vec3 across(const Vec3& u, double eps, BasinDraws& d) {
  const Vec3 e1 = u.unitOrthogonal(), e2 = u.cross(e1);
  const double r = eps * std::sqrt(d.uniform()), a = 2.0 * std::numbers::pi * d.uniform();
  return r * (std::cos(a) * e1 + std::sin(a) * e2);
}

physics::State hanging_start(const physics::Model& m, const physics::MotorSchedule& schedule, const BasinSpec& b,
                             BasinDraws& d) {
  const StopRange stops = stop_range(m);
  const double l = m.p.string_length;
  const bool on_ball = b.s_lo == 0.0 && b.s_hi == 0.0;
  const double s = on_ball ? stops.hi : d.uniform(b.s_lo, b.s_hi);
  const double two_pi = 2.0 * std::numbers::pi;
  const Vec3 u1 = hanging_direction(d.uniform(0.0, b.swing), d.uniform(0.0, two_pi));
  const Vec3 u2 = hanging_direction(d.uniform(0.0, b.swing), d.uniform(0.0, two_pi));
  const Vec3 a = schedule.top(0.0).a;
  const Vec3 r1 = a + s * u1, r2 = r1 + (l - s) * u2;
  physics::Mode mode = physics::Mode::Sliding;
  if (m.layers.bottom_stop && s >= stops.hi) mode = physics::Mode::BottomStop;
  if (m.layers.top_stop && s <= stops.lo) mode = physics::Mode::TopStop;
  return sim::explicit_state(m, schedule, r1, r2, Vec3::Zero(), Vec3::Zero(), mode);
}

physics::State cloud_start(const physics::Model& m, const physics::MotorSchedule& schedule, const BasinSpec& b,
                           double omega, const physics::State& o, BasinDraws& d) {
  const Vec3 a = schedule.top(0.0).a;
  const Vec3 r1 = o.r1(), r2 = o.r2();
  const double L1 = (r1 - a).norm(), L2 = (r2 - r1).norm();
  // Each ball moved across its segment, the segment's length kept: s and l − s stay where the orbit has them.
  const Vec3 q1 = a + L1 * (r1 + across((r1 - a) / L1, b.epsilon, d) - a).normalized();
  const Vec3 q2 = q1 + L2 * (r2 + across((r2 - r1) / L2, b.epsilon, d) - q1).normalized();
  const double dv = b.epsilon * omega;  // [m/s]
  Vec3 w1 = o.v1(), w2 = o.v2();
  for (int k = 0; k < 3; ++k) w1(k) += d.uniform(-dv, dv);
  for (int k = 0; k < 3; ++k) w2(k) += d.uniform(-dv, dv);
  return sim::explicit_state(m, schedule, q1, q2, w1, w2, o.contact.mode);
}

}  // namespace

BasinDraws::BasinDraws(const BasinSpec& b, int level, int sample) {
  std::uint64_t h = 1469598103934665603ULL;  // FNV-1a of the family's name
  for (unsigned char ch : to_string(b.family)) h = (h ^ ch) * 1099511628211ULL;
  state_ = mix(mix(mix(h ^ b.seed) ^ std::uint64_t(level)) ^ std::uint64_t(sample));
}

double BasinDraws::uniform() {
  state_ += 0x9e3779b97f4a7c15ULL;
  return double(mix(state_) >> 11) * 0x1.0p-53;
}

void check_basin(const physics::Model& m, const BasinSpec& b, std::string_view source_name) {
  const auto fail = [&](std::string_view key, const std::string& what) {
    throw BasinError(fmt::format("{}: key 'basin.{}': {}", source_name, key, what));
  };
  const StopRange stops = stop_range(m);
  if (b.family == BasinFamily::Hanging && !(b.s_lo == 0.0 && b.s_hi == 0.0)) {
    if (!(b.s_lo <= b.s_hi))
      fail("s", fmt::format("[{}, {}] is not a range (lo > hi)", b.s_lo, b.s_hi));
    if (b.s_lo < stops.lo || b.s_hi > stops.hi)
      fail("s", fmt::format("draws in [{}, {}] m can leave the bead's range; allowed within [{}, {}] m (the stops: "
                            "s_min{}, l − d = {} − {})",
                            b.s_lo, b.s_hi, stops.lo, stops.hi, m.layers.top_stop ? "" : " off", m.p.string_length,
                            m.p.contact_distance));
  }
  if (b.family == BasinFamily::Hand) {
    // The hand moves the top about the pair hanging a string's length below it: beyond l it
    // throws the pair rather than starting it.
    if (b.hand_amplitude > m.p.string_length)
      fail("hand_amplitude", fmt::format("{} m is out of range; allowed (0, {}] m (the string's length l)", b.hand_amplitude,
                                         m.p.string_length));
    if (!(b.hand_duration < b.settle))
      fail("hand_duration", fmt::format("{} s is out of range; allowed (0, {}) s: the hand must let go before the "
                                        "measured window (settle = {} s)", b.hand_duration, b.settle, b.settle));
    // A held tie stays held while the hand holds the top: the rod turns only the tie, τ = I_a ω̇_m <= τ_s.
    if (m.layers.tie_clutch && m.p.tie_inertia * b.step_rate > m.p.tie_static_torque)
      fail("step_rate", fmt::format("{} rad/s² would make the tie slip on the rod while the hand holds the top "
                                    "(I_a ω̇_m > τ_s); allowed (0, {}] rad/s²", b.step_rate,
                                    m.p.tie_static_torque / m.p.tie_inertia));
  }
  if (b.family == BasinFamily::Cloud && b.epsilon > 0.1 * m.p.string_length)
    fail("epsilon", fmt::format("{} m is out of range; allowed (0, {}] m (a tenth of the string)", b.epsilon,
                                0.1 * m.p.string_length));
}

CompiledProtocol basin_protocol(const BasinSpec& b, double omega, int level, int sample) {
  const Segment hold{Segment::Kind::Steps, {}, {omega, omega, 1, b.settle, b.measure, b.step_rate}};
  if (b.family != BasinFamily::Hand) return compile({hold}, omega);
  // The motor ramps from rest from t = 0; the hand holds the top until T, a breakpoint.
  CompiledProtocol p = compile({hold}, 0.0);
  const double T = b.hand_duration;
  std::vector<physics::DriveSegment> split;
  double t = 0.0;
  for (const physics::DriveSegment& s : p.schedule) {
    if (t < T && T < t + s.duration) {
      const double w = s.omega_begin + (s.omega_end - s.omega_begin) * (T - t) / s.duration;
      split.push_back({s.omega_begin, w, T - t});
      split.push_back({w, s.omega_end, t + s.duration - T});
    } else {
      split.push_back(s);
    }
    t += s.duration;
  }
  p.schedule = std::move(split);
  // h's modes: p_k, q_k uniform in the horizontal disc of radius A/(2K), so |h| <= A.
  BasinDraws d(b, level, sample);
  physics::HandPath hand{T, {}, {}};
  const double r = b.hand_amplitude / (2.0 * b.hand_modes);
  const auto disc = [&] {
    const double rho = r * std::sqrt(d.uniform()), a = 2.0 * std::numbers::pi * d.uniform();
    return Vec3(rho * std::cos(a), rho * std::sin(a), 0.0);
  };
  for (int k = 0; k < b.hand_modes; ++k) {
    hand.p.push_back(disc());
    hand.q.push_back(disc());
  }
  p.hand = std::move(hand);
  return p;
}

physics::State basin_orbit(const physics::Model& m, const physics::MotorSchedule& schedule, const BasinSpec& b,
                           double omega) {
  if (b.stored) {  // the balls turned with the top from azimuth 0 to the schedule's φ(0)
    const StoredOrbit& o = *b.stored;
    const double phi = schedule.top(0.0).phi, c = std::cos(phi), s = std::sin(phi);
    const auto turn = [&](const Vec3& x) { return Vec3(c * x.x() - s * x.y(), s * x.x() + c * x.y(), x.z()); };
    try {
      return sim::explicit_state(m, schedule, turn(o.r1), turn(o.r2), turn(o.v1), turn(o.v2), o.mode);
    } catch (const std::invalid_argument& e) {
      throw BasinError(e.what());
    }
  }
  try {
    return seed_state(m, schedule, b.orbit, omega, 0, 0.0);
  } catch (const std::invalid_argument& e) {
    throw BasinError(e.what());
  }
}

physics::State basin_start(const physics::Model& m, const physics::MotorSchedule& schedule, const BasinSpec& b,
                           double omega, int level, int sample, const physics::State* orbit) {
  BasinDraws d(b, level, sample);
  switch (b.family) {
    case BasinFamily::Hanging: return hanging_start(m, schedule, b, d);
    case BasinFamily::Hand: return sim::hanging_at_rest(m, schedule);
    case BasinFamily::Cloud: return cloud_start(m, schedule, b, omega, orbit ? *orbit : basin_orbit(m, schedule, b, omega), d);
  }
  return {};
}

Interval wilson_interval(long k, long n) {
  if (n <= 0) return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  constexpr double z = 1.959963984540054, z2 = z * z;
  const double N = double(n), K = double(k);
  const double centre = (K + z2 / 2.0) / (N + z2);
  const double half = z / (N + z2) * std::sqrt(K * (N - K) / N + z2 / 4.0);
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

}  // namespace ajx::sweep
