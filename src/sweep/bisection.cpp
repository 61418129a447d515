#include "sweep/bisection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "orbits/predicted_thresholds.hpp"
#include "physics/state_row.hpp"
#include "physics/tie.hpp"
#include "sweep/codec.hpp"
#include "sweep/probe_verdict.hpp"
#include "sweep/protocol.hpp"
#include "sweep/seeds.hpp"

namespace ajx::sweep {

namespace {
constexpr double nan = std::numeric_limits<double>::quiet_NaN();
}

bool on_known_side(Threshold t, OrbitClass c) {
  switch (t) {
    case Threshold::Rise: return c == OrbitClass::Fallen;
    case Threshold::Fall: return c != OrbitClass::Fallen && c != OrbitClass::Failed;  // not-settled: still falling
    case Threshold::Omega1: return c == OrbitClass::LockedCircular;
    case Threshold::Omega2: return circular(c);
  }
  return false;
}

bool far_end_last(Threshold t) { return t == Threshold::Fall || t == Threshold::Omega1; }

int bisect_direction(Threshold t) { return t == Threshold::Fall ? -1 : +1; }

int halvings(const BisectSpec& s) {
  // Halvings of Δ = |to − from| down to w (counted, not log2, so that rounding cannot leave one out).
  int m = 0;
  for (double d = std::abs(s.to - s.from); d > s.width && m < 60; d *= 0.5) ++m;
  return m;
}

int probe_count(const BisectSpec& s) {
  const int n = halvings(s);
  return s.guide == BisectSpec::Guide::HeldOrbit ? 2 * n + 2 : 2 + n;
}

std::int64_t guided_index(std::int64_t K, std::int64_t O, double g) {
  using I = std::int64_t;
  const I mid = K + (O - K) / 2;
  if (std::isnan(g)) return mid;  // no prediction: the middle, K < mid < O
  I j = mid;
  if (g <= K) {  // the threshold lies further than predicted: gallop from the known side
    j = std::min(K + std::max<I>(1, I(std::ceil(K - g))), mid);
  } else if (g >= O) {  // nearer than predicted: gallop back from the other side
    j = std::max(O - std::max<I>(1, I(std::ceil(g - O))), mid);
  } else if (std::floor(g) > K) {
    j = I(std::floor(g));  // expected on the known side
  } else {
    j = I(std::ceil(g));   // K <= g < K + 1: the point past it
  }
  return std::clamp(j, K + 1, O - 1);
}

double min_width(const BisectSpec& s, const ClassifierSettings& settings) {
  return 2.0 * std::numbers::pi / (settings.min_samples_per_turn * s.measure);
}

std::string_view to_string(BisectStatus s) {
  switch (s) {
    case BisectStatus::Running: return "running";
    case BisectStatus::Converged: return "converged";
    case BisectStatus::StartOffSide: return "start not on the known side";
    case BisectStatus::NoCrossing: return "no crossing in the range";
    case BisectStatus::Failed: return "a probe failed";
  }
  return "?";
}

std::vector<std::byte> encode(const BisectCarry& c) {
  ByteWriter w;
  w.put_vector(physics::state_row(c.known));
  w.put_vector(c.history);
  w.put(c.known_omega);
  w.put(c.other_omega);
  w.put(c.known_class);
  w.put(c.other_class);
  w.put(std::int32_t(c.status));
  if (!std::isnan(c.guide)) w.put(c.guide);  // only a guided chain's: the others' bytes as before
  return w.take();
}

BisectCarry decode_carry(const std::vector<std::byte>& bytes) {
  ByteReader r(bytes.data(), bytes.size());
  BisectCarry c;
  const auto row = r.get_vector<double>();
  if (row.size() != physics::kStateCols) throw std::runtime_error("bisection carry: wrong number of state columns");
  c.known = physics::state_from_row(row);
  c.history = r.get_vector<physics::DriveSegment>();
  c.known_omega = r.get<double>();
  c.other_omega = r.get<double>();
  c.known_class = r.get<std::int32_t>();
  c.other_class = r.get<std::int32_t>();
  const auto status = r.get<std::int32_t>();
  if (status < 0 || status > kMaxBisectStatus) throw std::runtime_error("bisection carry: bad status");
  c.status = BisectStatus(status);
  if (!r.done()) c.guide = r.get<double>();
  if (!r.done()) throw std::runtime_error("bisection carry: trailing bytes");
  return c;
}

ChainSetup probe_chain(const BisectSpec& spec, const physics::Model& model, const sim::RunOptions& run,
                       double sample_rate, const std::vector<physics::DriveSegment>& history, double omega0,
                       double level) {
  const Steps hold{level, level, 1, spec.settle, spec.measure, spec.step_rate};
  const CompiledProtocol tail = compile({Segment{Segment::Kind::Steps, {}, hold}}, omega0);
  double t0 = 0.0;
  for (const physics::DriveSegment& s : history) t0 += s.duration;  // as MotorSchedule sums them
  ChainSetup c;
  c.model = model;
  c.run = run;
  c.sample_rate = sample_rate;
  c.protocol.schedule = history;
  c.protocol.schedule.insert(c.protocol.schedule.end(), tail.schedule.begin(), tail.schedule.end());
  Window w = tail.windows.front();
  w.t_settle += t0;  // the hold's start: the lock verdict tests held blocks only
  w.t_begin += t0;
  w.t_end += t0;
  c.protocol.windows = {w};
  c.protocol.duration = t0 + tail.duration;
  return c;
}

namespace {

// The motor schedule from t = 0 to t: the segments before it, the one it falls in cut there.
std::vector<physics::DriveSegment> schedule_until(const std::vector<physics::DriveSegment>& schedule, double t) {
  std::vector<physics::DriveSegment> out;
  double t0 = 0.0;
  for (const physics::DriveSegment& s : schedule) {
    if (t <= t0) break;
    physics::DriveSegment cut = s;
    if (t < t0 + s.duration) {  // ω_m linear over the segment
      cut.duration = t - t0;
      cut.omega_end = s.omega_begin + (s.omega_end - s.omega_begin) * cut.duration / s.duration;
    }
    out.push_back(cut);
    t0 += s.duration;
  }
  return out;
}

}  // namespace

Probe run_probe(const BisectSpec& spec, const physics::Model& model, const sim::RunOptions& run, double sample_rate,
                int k, const BisectCarry& in, const ClassifierSettings& settings) {
  Probe p;
  BisectCarry c = k == 0 ? BisectCarry{} : in;
  // Guided probes lie on the middles' lattice, from + (to − from) j/2^n, j = 0 .. 2^n.
  const bool guided = spec.guide == BisectSpec::Guide::HeldOrbit;
  const double cells = std::ldexp(1.0, halvings(spec));
  const auto index = [&](double w) { return std::int64_t(std::llround((w - spec.from) / (spec.to - spec.from) * cells)); };
  const auto narrow = [&](const BisectCarry& b) {
    return guided ? index(b.other_omega) - index(b.known_omega) <= 1 : b.width() <= spec.width;
  };
  // The far end is assumed on the other side (other_class −1) until it is held: first (probe 1),
  // or, for ω_fall and ω1, once the bracket has shrunk to w with every middle on the known side.
  const bool unheld = k >= 1 && c.status == BisectStatus::Running && c.other_class < 0;
  const bool at_far_end = unheld && (far_end_last(spec.threshold) ? narrow(c) : k == 1);
  if (k >= 1 && c.status == BisectStatus::Running && narrow(c) && !at_far_end)
    c.status = BisectStatus::Converged;
  if (c.status != BisectStatus::Running) {  // settled before this probe: nothing to integrate
    p.omega = nan;
    p.out.final_state = c.known;
    p.next = std::move(c);
    return p;
  }
  p.ran = true;
  if (k == 0 || at_far_end) {
    p.omega = k == 0 ? spec.from : spec.to;
  } else if (guided) {
    const double g = (c.guide - spec.from) / (spec.to - spec.from) * cells;  // NaN without a guide
    p.omega = spec.from + (spec.to - spec.from) * (double(guided_index(index(c.known_omega), index(c.other_omega), g)) / cells);
  } else {
    p.omega = 0.5 * (c.known_omega + c.other_omega);
  }
  const ChainSetup chain = probe_chain(spec, model, run, sample_rate, k == 0 ? std::vector<physics::DriveSegment>{} : c.history,
                                       k == 0 ? spec.start_omega : c.known_omega, p.omega);
  const physics::State start =
      k == 0 ? seed_state(model, chain.motor(), spec.start_seed, spec.start_omega, 0, 0.0)
             : c.known;
  if (spec.decide_early) {
    ProbePath path = run_probe_path(chain, start, spec.threshold, settings);
    p.out = std::move(path.out);
    if ((p.decided = path.decided.has_value())) {
      p.classification = std::move(*path.decided);
      p.decided_at = path.decided_at;
    }
  } else {
    p.out = run_task(chain, TaskSpan{start.t, chain.protocol.duration, 0, 1}, start);
  }
  if (!p.decided) p.classification = classify_windows(chain, p.out, settings).front();
  const auto cls = std::int32_t(p.classification.cls);
  if (!p.out.ok) {
    c.status = BisectStatus::Failed;
    p.next = std::move(c);
    return p;
  }
  p.known_side = on_known_side(spec.threshold, p.classification.cls);
  const auto take_known = [&] {
    c.known = p.out.final_state;
    c.history = p.decided ? schedule_until(chain.protocol.schedule, p.decided_at) : chain.protocol.schedule;
    c.known_omega = p.omega;
    c.known_class = cls;
  };
  if (k == 0) {
    c.known = start;
    c.known_omega = nan;
    c.other_omega = p.omega;
    c.other_class = cls;
    if (p.known_side) {
      take_known();
      c.other_omega = spec.to;  // assumed, not yet held
      c.other_class = -1;
      // Only a locked start has a locked orbit to continue (a lagging one turns slower than ω_m).
      if (guided && p.classification.cls == OrbitClass::LockedCircular && c.known.contact.mode == physics::Mode::Stuck) {
        const physics::TopKinematics top =
            physics::top_kinematics(model, chain.motor(), c.known.contact, c.known.t, c.known.y);
        c.guide = orbits::held_orbit_end(model, spec.from, c.known.contact.s_star, c.known.y, top.phi, spec.to);
      }
    } else {
      c.status = BisectStatus::StartOffSide;
    }
  } else if (p.known_side) {
    take_known();
    if (at_far_end) {
      c.status = BisectStatus::NoCrossing;
      c.other_omega = nan;
    }
  } else {
    c.other_omega = p.omega;
    c.other_class = cls;
  }
  if (c.status == BisectStatus::Running && c.other_class >= 0 && narrow(c))
    c.status = BisectStatus::Converged;
  p.next = std::move(c);
  return p;
}

}  // namespace ajx::sweep
