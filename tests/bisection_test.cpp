// Thresholds by bisection on held levels (sweep/bisection.hpp): the count of probes, the
// carry's codec, bad specs, and the physics: an ω_fall bracketed by bisection at the documented
// set holds the locked orbit's cone exit downwards (orbits/threshold_curves.hpp, the
// continuation's ω_fall) at the bead's stuck position of the bracket's known side.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "map_bench_spec.hpp"
#include "orbits/threshold_curves.hpp"
#include "sweep/bisection.hpp"
#include "sweep/probe_verdict.hpp"

using namespace ajx;
using namespace ajx::sweep;

namespace {

constexpr double kPi = std::numbers::pi;

physics::Model documented() {
  physics::Model m;
  m.p.drive_radius = 0.015;   // R [m], sweeps/paper.toml
  m.p.contact_distance = 0.035;  // d [m]
  return m;
}

sim::RunOptions run_options() {
  sim::RunOptions r;
  r.method = "dop853";
  r.integ.tol.rtol = 1e-9;  // as sweeps/paper.toml
  r.integ.tol.atol = 1e-11;
  return r;
}

BisectSpec fall_spec(double width) {
  BisectSpec b;
  b.threshold = Threshold::Fall;
  b.start_seed = "circular_high";
  b.start_omega = b.from = 4 * kPi;
  b.to = 2.5 * kPi;
  b.width = width;
  return b;
}

// A synthetic sample of the verdict's blocks: the bead at L1 in `mode`, both balls at rest in
// the turning frame (φ = 0).
struct FakeSample {
  physics::Contact contact;
  numerics::Vec y = numerics::Vec::Zero(physics::idx::dim);
  physics::Dynamics dyn{};
  physics::TopKinematics top{};
  FakeSample(physics::Mode mode, double L1) : contact(mode) {
    dyn.g.L1 = L1;
    y(physics::idx::r1 + 2) = -L1;
    y(physics::idx::r2 + 2) = -0.826;
  }
  sim::Sample at(double t) const { return {t, contact, y, dyn, top, 0.0}; }
};

// Every probe of one chain in order, each from the carry the previous left.
std::vector<Probe> bisect(const BisectSpec& spec, const physics::Model& m) {
  std::vector<Probe> out;
  BisectCarry carry;
  for (int k = 0; k < probe_count(spec); ++k) {
    out.push_back(run_probe(spec, m, run_options(), 50.0, k, carry));
    carry = out.back().next;
  }
  return out;
}

}  // namespace

TEST(Bisection, ProbeCountIsTwoPlusTheHalvingsToTheWidth) {
  BisectSpec b = fall_spec(0.05 * kPi);
  // Δ = 1.5π: 1.5/0.05 = 30 ≤ 2^5, so 5 halvings; the fixed 0.05π ladder has 31 levels.
  EXPECT_EQ(probe_count(b), 7);
  b.width = 1.5 * kPi / 32;  // exactly 5 halvings
  EXPECT_EQ(probe_count(b), 7);
  b.width = 1.5 * kPi / 32 * (1 - 1e-12);
  EXPECT_EQ(probe_count(b), 8);
}

TEST(Bisection, MinimumWidthIsAQuarterTurnOverTheWindow) {
  BisectSpec b = fall_spec(0.05 * kPi);
  b.measure = 20.0;
  // w_min T_m = 2π / 4: over the window two levels w_min apart drift a quarter turn apart.
  EXPECT_DOUBLE_EQ(min_width(b) * b.measure, kPi / 2);
}

TEST(Bisection, CarryRoundTripsExactly) {
  BisectCarry c;
  c.known.t = 123.456;
  c.known.y.setLinSpaced(physics::idx::dim, 0.1, 1.5);
  c.known.contact = physics::Contact(physics::Mode::Stuck, 1, 0.4589);
  c.history = {{12.5, 12.5, 60.0}, {12.5, 11.0, 15.0}};
  c.known_omega = 11.0;
  c.other_omega = 10.2;
  c.known_class = 1;
  c.other_class = 0;
  c.status = BisectStatus::Running;
  const BisectCarry d = decode_carry(encode(c));
  EXPECT_EQ(d.known.t, c.known.t);
  EXPECT_EQ(d.known.y, c.known.y);
  EXPECT_EQ(d.known.contact.s_star, c.known.contact.s_star);
  ASSERT_EQ(d.history.size(), 2u);
  EXPECT_EQ(d.history[1].omega_end, 11.0);
  EXPECT_EQ(d.known_omega, c.known_omega);
  EXPECT_EQ(d.other_omega, c.other_omega);
  EXPECT_EQ(d.status, c.status);
}

TEST(Bisection, KnownSidePerThreshold) {
  EXPECT_TRUE(on_known_side(Threshold::Fall, OrbitClass::NotSettled));  // still falling: not yet fallen
  EXPECT_FALSE(on_known_side(Threshold::Fall, OrbitClass::Fallen));
  EXPECT_TRUE(on_known_side(Threshold::Omega2, OrbitClass::LaggingCircular));
  EXPECT_FALSE(on_known_side(Threshold::Omega1, OrbitClass::LaggingCircular));
  EXPECT_TRUE(on_known_side(Threshold::Rise, OrbitClass::Fallen));
}

// The bracket halves with every probe; each midpoint probe restarts from the known side.
TEST(Bisection, FallBracketAtTheDocumentedSetHoldsTheContinuationsConeExit) {
  const physics::Model m = documented();
  const BisectSpec spec = fall_spec(0.05 * kPi);
  const std::vector<Probe> probes = bisect(spec, m);
  const BisectCarry& end = probes.back().next;
  ASSERT_EQ(end.status, BisectStatus::Converged);
  EXPECT_LE(end.width(), spec.width);
  EXPECT_EQ(OrbitClass(end.other_class), OrbitClass::Fallen);
  for (std::size_t k = 2; k < probes.size(); ++k)
    if (probes[k].ran) EXPECT_NEAR(probes[k].omega, 0.5 * (probes[k - 1].next.known_omega + probes[k - 1].next.other_omega), 1e-12);
  // Held at the known side the bead is stuck at s*; the stuck orbit there leaves its friction cone
  // downwards at ω_cd(s*) (the continuation's cone_down point at s*). Held above the bracket the
  // orbit stays, held below it falls, so ω_cd(s*) lies in the bracket, to within the bracket's
  // width w (the probe below starts from the state above, whose bead is at s* only to the
  // classifier's resolution).
  ASSERT_EQ(end.known.contact.mode, physics::Mode::Stuck);
  const double s = end.known.contact.s_star;
  orbits::CurveOptions opt;
  const auto starts = orbits::curve_starts(m, orbits::CurveKind::ConeDown, s, opt);
  ASSERT_FALSE(starts.empty());
  double nearest = starts.front().omega;
  for (const auto& st : starts)
    if (std::abs(st.omega - end.known_omega) < std::abs(nearest - end.known_omega)) nearest = st.omega;
  RecordProperty("s_star", std::to_string(s));
  RecordProperty("cone_down_pi", std::to_string(nearest / kPi));
  EXPECT_GE(nearest, end.other_omega - spec.width) << "s* = " << s << ", ω_cd = " << nearest / kPi << "π";
  EXPECT_LE(nearest, end.known_omega + spec.width) << "s* = " << s << ", ω_cd = " << nearest / kPi << "π";
}

// A probe stopped once its class is decided (sweep/probe_verdict.hpp) decides what the probe held
// through its window decides: both thresholds of sweeps/maps/example.toml at two of its grid
// points, bisected with and without the early verdicts, end in the same brackets with the same
// classes on either side, and the early verdicts integrate fewer steps.
TEST(Bisection, ProbesDecidedEarlyGiveTheBracketsOfFullProbes) {
  long steps[2] = {0, 0};
  for (const double R : {0.01, 0.02}) {
    physics::Model m;
    m.p.drive_radius = R;
    m.p.contact_distance = 0.03;
    for (const Threshold th : {Threshold::Fall, Threshold::Omega1}) {
      BisectSpec spec = map_bench_spec(th, 0.1 * kPi);
      BisectCarry ends[2];
      for (int early = 0; early < 2; ++early) {
        spec.decide_early = early == 1;
        const std::vector<Probe> probes = bisect(spec, m);
        ends[early] = probes.back().next;
        for (const Probe& p : probes) steps[early] += p.out.steps;
        if (early == 0)
          for (const Probe& p : probes) EXPECT_FALSE(p.decided);
      }
      // A lock is decided at the third whole 5 s block held at the level at the earliest: the
      // level is reached |Δω|/step_rate after the probe's start, the known side's state.
      // (probe 0: the seed at t = 0 and start_omega).
      BisectCarry in;
      in.known_omega = spec.start_omega;
      for (const Probe& p : bisect(spec, m)) {
        if (p.decided && p.classification.cls == OrbitClass::LockedCircular) {
          const double t_hold = in.known.t + std::abs(p.omega - in.known_omega) / spec.step_rate;
          EXPECT_GE(p.decided_at, t_hold + 3 * ProbeVerdict::kBlock - 1e-9) << p.omega / kPi << "π";
        }
        in = p.next;
      }
      const std::string at = "R = " + std::to_string(R) + ", " + std::string(to_string(th));
      ASSERT_EQ(ends[0].status, BisectStatus::Converged) << at;
      EXPECT_EQ(ends[1].status, ends[0].status) << at;
      EXPECT_EQ(ends[1].known_omega, ends[0].known_omega) << at;
      EXPECT_EQ(ends[1].other_omega, ends[0].other_omega) << at;
      EXPECT_EQ(ends[1].known_class, ends[0].known_class) << at;
      EXPECT_EQ(ends[1].other_class, ends[0].other_class) << at;
    }
  }
  RecordProperty("steps_full", std::to_string(steps[0]));
  RecordProperty("steps_early", std::to_string(steps[1]));
  EXPECT_LT(steps[1], steps[0] / 2);
}

// The fallen verdict counts B = 5 s on the ball from the landing's first sample, not from the
// block grid: a bead landing at 2.3 s is decided at the sample of 7.3 s (the block after the
// landing ends there, fall_due), a bead that leaves the ball on the way starts again, and a
// flower touching the ball for less than B is never decided fallen.
TEST(ProbeVerdict, FallenFiveSecondsAfterTheLandingNotOnTheGrid) {
  const physics::Model m = documented();
  const double l = m.p.string_length, d = m.p.contact_distance;
  const FakeSample up(physics::Mode::Sliding, 0.5), down(physics::Mode::BottomStop, l - d);
  const double dt = ProbeVerdict::kSampleStep;
  ProbeVerdict v(Threshold::Fall, m, ClassifierSettings{}, 0.0);
  for (int k = 0; k <= 50; ++k) v.add((k < 23 ? up : down).at(k * dt));
  EXPECT_FALSE(v.close_block(0.0, 5.0));
  EXPECT_NEAR(v.fall_due(), 2.3 + ProbeVerdict::kBlock + 0.5 * dt, 1e-9);
  for (int k = 50; k <= 72; ++k) v.add(down.at(k * dt));
  EXPECT_FALSE(v.close_block(5.0, 7.2));  // 4.9 s on the ball
  v.add(down.at(7.3));
  const auto c = v.close_block(7.2, 7.35);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->cls, OrbitClass::Fallen);

  for (const double off : {4.0, 6.0}) {  // off the ball at one sample: 5.9 s since, or 3.9 s
    ProbeVerdict bounce(Threshold::Omega1, m, ClassifierSettings{}, 0.0);
    for (int k = 0; k <= 100; ++k) bounce.add((k == std::lround(off / dt) ? up : down).at(k * dt));
    EXPECT_NEAR(bounce.fall_due(), off + dt + ProbeVerdict::kBlock + 0.5 * dt, 1e-9);
    EXPECT_EQ(bounce.close_block(0.0, 10.0).has_value(), off == 4.0) << off;
  }
  ProbeVerdict flower(Threshold::Fall, m, ClassifierSettings{}, 0.0);
  for (int k = 0; k <= 100; ++k) flower.add((k % 40 < 30 ? up : down).at(k * dt));  // 1 s on the ball in 4
  EXPECT_FALSE(flower.close_block(0.0, 10.0));
  ProbeVerdict rise(Threshold::Rise, m, ClassifierSettings{}, 0.0);  // ω_rise's probes are never decided
  for (int k = 0; k <= 50; ++k) rise.add(down.at(k * dt));
  EXPECT_FALSE(rise.close_block(0.0, 5.0));
  EXPECT_EQ(rise.fall_due(), std::numeric_limits<double>::infinity());
}

// The lock verdict reads held blocks only: a stuck orbit at a fixed point of the turning frame
// from t = 0 is decided locked at the third whole block held at the level, when the level is
// reached at t_hold = 12 s (blocks from 15 s: decided at 30 s), whatever the blocks before.
TEST(ProbeVerdict, LockedOnlyAfterThreeWholeBlocksHeld) {
  const physics::Model m = documented();
  const FakeSample stuck(physics::Mode::Stuck, 0.45);
  const double dt = ProbeVerdict::kSampleStep, B = ProbeVerdict::kBlock;
  ProbeVerdict v(Threshold::Fall, m, ClassifierSettings{}, 12.0);
  double decided = -1.0;
  for (int b = 0; b < 10 && decided < 0.0; ++b) {
    for (int k = 0; k <= 50; ++k) v.add(stuck.at(b * B + k * dt));
    if (const auto c = v.close_block(b * B, (b + 1) * B)) {
      EXPECT_EQ(c->cls, OrbitClass::LockedCircular);
      decided = (b + 1) * B;
    }
  }
  EXPECT_DOUBLE_EQ(decided, 30.0);
}

// A probe's window after a carried history of t0 = 50 s: the ramp from 4π to 3.5π at 0.1 rad/s²
// ends at t_settle = t0 + 0.5π/0.1, the hold's start, from which the lock verdict reads blocks
// (it read every block when t_settle was left at the ramp's end measured from 0), the window
// after settle, and the schedule's motor at t_settle is at the level.
TEST(Bisection, ProbeChainHoldsFromTheEndOfItsRampAfterTheHistory) {
  BisectSpec spec = fall_spec(0.05 * kPi);
  const std::vector<physics::DriveSegment> history = {{4 * kPi, 4 * kPi, 50.0}};
  const ChainSetup c = probe_chain(spec, documented(), run_options(), 50.0, history, 4 * kPi, 3.5 * kPi);
  ASSERT_EQ(c.protocol.windows.size(), 1u);
  const Window& w = c.protocol.windows.front();
  EXPECT_NEAR(w.t_settle, 50.0 + 0.5 * kPi / spec.step_rate, 1e-9);
  EXPECT_NEAR(w.t_begin, w.t_settle + spec.settle, 1e-9);
  EXPECT_NEAR(w.t_end, w.t_begin + spec.measure, 1e-9);
  const physics::MotorSchedule motor = c.motor();
  EXPECT_NEAR(motor.top(w.t_settle).omega, 3.5 * kPi, 1e-9);
  EXPECT_NEAR(motor.top(w.t_settle - 1.0).omega, 3.5 * kPi + spec.step_rate, 1e-9);  // still ramping
}

namespace {
// A guided chain on the lattice of 2^n cells, its far end unheld, against an oracle that says
// whether index j lies on the known side: the middles it runs before the bracket is one cell
// wide (the far end's probe counted as probe_count counts it).
template <class KnownSide>
int guided_probes(int n, double g, KnownSide known) {
  std::int64_t K = 0, O = std::int64_t(1) << n;
  bool other_held = false;
  int probes = 1;  // probe 0
  while (O - K > 1) {
    const std::int64_t j = guided_index(K, O, g);
    EXPECT_GT(j, K);
    EXPECT_LT(j, O);
    ++probes;
    if (known(j)) K = j; else O = j, other_held = true;
  }
  return probes + (other_held ? 0 : 1);
}
// The most probes any sequence of outcomes costs from the bracket [K, O] (the outcomes need not
// be monotone: a held orbit's class depends on its history).
int worst_probes(std::int64_t K, std::int64_t O, double g, std::map<std::pair<std::int64_t, std::int64_t>, int>& memo) {
  if (O - K <= 1) return 0;
  const auto key = std::make_pair(K, O);
  if (const auto it = memo.find(key); it != memo.end()) return it->second;
  const std::int64_t j = guided_index(K, O, g);
  return memo[key] = 1 + std::max(worst_probes(j, O, g, memo), worst_probes(K, j, g, memo));
}
}  // namespace

// The guided bisection's count (bisection.hpp, guided_index): a chain never needs more probes
// than probe_count gives it (2n + 2, reached for n >= 3), whatever the outcomes and the
// prediction; a prediction in the threshold's own cell closes the bracket with two middles, and
// one k cells off with at most 2 ⌈log2(k + 1)⌉ + 2.
TEST(Bisection, GuidedProbesStayWithinTheirCountAndTwoWhenThePredictionIsRight) {
  for (int n = 1; n <= 7; ++n) {
    BisectSpec b = fall_spec(1.5 * kPi / std::ldexp(1.0, n));
    b.guide = BisectSpec::Guide::HeldOrbit;
    ASSERT_EQ(halvings(b), n);
    const std::int64_t cells = std::int64_t(1) << n;
    std::vector<double> guesses = {std::numeric_limits<double>::quiet_NaN(), -3.0, double(cells) + 3.0};
    for (std::int64_t i = 0; i <= 4 * cells; ++i) guesses.push_back(0.25 * double(i) + 0.01);
    int worst = 0;
    for (const double g : guesses) {
      std::map<std::pair<std::int64_t, std::int64_t>, int> memo;
      // probe 0, the middles, the far end
      worst = std::max(worst, 1 + worst_probes(0, cells, g, memo) + 1);
      EXPECT_LE(worst, probe_count(b)) << "n = " << n << ", g = " << g;
      for (std::int64_t t = 1; t <= cells; ++t) {  // known below index t, other from t (t = cells: the far end)
        const int p = guided_probes(n, g, [t](std::int64_t j) { return j < t; });
        EXPECT_LE(p, probe_count(b));
        if (g > double(t - 1) && g < double(t) && t < cells) EXPECT_LE(p, 3) << "n = " << n << ", g = " << g << ", t = " << t;
        const double off = std::abs(g - (double(t) - 0.5));
        if (off >= 1 && t < cells && !std::isnan(g)) EXPECT_LE(p, 3 + 2 * int(std::ceil(std::log2(off + 1)))) << n << " " << g << " " << t;
      }
    }
    if (n >= 3) EXPECT_EQ(worst, probe_count(b)) << "n = " << n << ": the count is the bound, not more";
  }
}

// Guided by the start level's own orbit at the documented set: the same kind of bracket as the
// middles' (converged, one lattice cell wide, fallen beyond), the prediction is the
// continuation's cone exit downwards at the bead's s* of probe 0 (the curve's start polished on
// its extended system, orbits/threshold_curves.hpp), and fewer probes run.
TEST(Bisection, GuidedByTheHeldOrbitBracketsTheFallWithFewerProbes) {
  const physics::Model m = documented();
  BisectSpec spec = fall_spec(0.05 * kPi);
  spec.guide = BisectSpec::Guide::HeldOrbit;
  const std::vector<Probe> guided = bisect(spec, m);
  const BisectCarry& end = guided.back().next;
  ASSERT_EQ(end.status, BisectStatus::Converged);
  EXPECT_LE(end.width(), spec.width);
  EXPECT_EQ(OrbitClass(end.other_class), OrbitClass::Fallen);
  ASSERT_FALSE(std::isnan(end.guide));
  const BisectCarry& start = guided.front().next;
  ASSERT_EQ(start.known.contact.mode, physics::Mode::Stuck);
  const auto starts = orbits::curve_starts(m, orbits::CurveKind::ConeDown, start.known.contact.s_star, {});
  ASSERT_FALSE(starts.empty());
  double nearest = starts.front().omega;
  for (const auto& st : starts)
    if (std::abs(st.omega - end.guide) < std::abs(nearest - end.guide)) nearest = st.omega;
  // Both solve the locked orbit's equations at s* to the round-off floor 8ε(1 + ω²l/g) (scaled);
  // the guide's point is bisected 40 times on a segment of at most 0.05 √(g/l) in ω. 1e-9 rad/s
  // allows a margin whose slope in ω is 10^3 times below its scale.
  EXPECT_NEAR(end.guide, nearest, 1e-9);
  // The held orbit above the bracket keeps its s*, so the bracket holds the prediction to
  // within its width (the probes below start from the state above, whose bead is at s* only to
  // the classifier's resolution), as the middles' bracket does (the test above).
  EXPECT_GE(end.guide, end.other_omega - spec.width);
  EXPECT_LE(end.guide, end.known_omega + spec.width);
  spec.guide = BisectSpec::Guide::Middle;
  int ran[2] = {0, 0};
  for (const Probe& p : guided) ran[0] += p.ran;
  for (const Probe& p : bisect(spec, m)) ran[1] += p.ran;
  RecordProperty("probes_guided", ran[0]);
  RecordProperty("probes_middle", ran[1]);
  EXPECT_LT(ran[0], ran[1]);
}

TEST(Bisection, GuidedCarryRoundTripsAndAnUnguidedOneKeepsItsBytes) {
  BisectCarry c;
  c.known.contact = physics::Contact(physics::Mode::Stuck, 1, 0.4589);
  c.known_omega = 11.0;
  c.other_omega = 10.2;
  const std::vector<std::byte> plain = encode(c);
  c.guide = 10.7;
  const std::vector<std::byte> guided = encode(c);
  EXPECT_EQ(guided.size(), plain.size() + sizeof(double));
  EXPECT_TRUE(std::equal(plain.begin(), plain.end(), guided.begin()));
  EXPECT_EQ(decode_carry(guided).guide, 10.7);
  EXPECT_TRUE(std::isnan(decode_carry(plain).guide));
}
