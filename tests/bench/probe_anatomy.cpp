// Where a bisection probe's integration steps go (issue 28's map target; docs/reports/
// threshold-maps.md, "session 5"). Runs the chains of ω_fall (4π down to 2.5π) and ω1 (4π up to
// 6.5π) of tests/bench/map_bisection.sh's N × N grid of (R, d) by bisection to 0.05π, probes
// decided early, each probe by sweep::run_probe. Then integrates every probe again by the same
// sweep::run_probe_path from the same chain and start (so the same steps: checked against the
// probe's own count), watching its samples and blocks, and splits each block's steps by what its
// samples (every 0.1 s) show:
//   ramp      ω_m still on its way to the level;
//   stuck     held, the bead stuck on the string (and the tie held);
//   moving    held, the bead sliding (or the tie slipping), not on the ball;
//   on ball   held, the bead on the bottom ball (the classifier's test), chatter included;
//   window    a probe not decided early: its window (and what run_task integrates before it).
// A block's steps are shared among its phases in proportion to its samples in each (steps are
// counted per block of 5 s, the probe's own integration, not per sample). Prints each probe and
// the sums per kind of probe. Also runs every probe decided early again from the same start,
// held through its window, and prints any whose class differs (a side decided wrongly); exits 1
// then, or when a replay's steps differ from its probe's.
// Run:  build/tests/bench/probe_anatomy [N] [-v]
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

#include "map_bench_spec.hpp"
#include "sweep/bisection.hpp"
#include "sweep/probe_verdict.hpp"
#include "sweep/protocol.hpp"
#include "sweep/seeds.hpp"

using namespace ajx;
using namespace ajx::sweep;

namespace {

constexpr double kPi = std::numbers::pi;
enum Phase { kRamp, kStuck, kMoving, kOnBall, kWindow, kPhases };
constexpr std::array<const char*, kPhases> kNames = {"ramp", "stuck", "moving", "on ball", "window"};

struct Anatomy {
  std::array<double, kPhases> steps{};  // steps per phase
  double ramp = 0.0, slip = NAN, land = NAN, end = 0.0;  // durations from the hold's start [s]
  long total = 0;
  bool early_lock = false;  // a lock decided before three whole blocks held at the level (see main)
};

// The probe's path again, by run_probe_path itself, with its samples sorted into phases.
// trace: print every fifth sample and every block's steps.
Anatomy dissect(const ChainSetup& chain, const physics::State& start, Threshold th, bool trace = false) {
  const Window& win = chain.protocol.windows.front();
  const double t_hold = win.t_settle;  // when ω_m reaches the level
  const double l = chain.model.p.string_length, d = chain.model.p.contact_distance;
  const ClassifierSettings settings;
  Anatomy a;
  a.ramp = t_hold - start.t;
  std::array<int, kPhases> in_block{};
  const auto watch = [&](const sim::Sample& x) {
    const bool on_ball = x.contact.mode == physics::Mode::BottomStop ||
                         std::abs(l - x.dyn.g.L1 - d) <= settings.on_ball_tol * d;
    const bool stuck = x.contact.mode == physics::Mode::Stuck && !x.contact.tie.slip;
    const Phase p = x.t < t_hold ? kRamp : on_ball ? kOnBall : stuck ? kStuck : kMoving;
    // the first slip and the first landing, on the ramp too (then before the hold: negative)
    if (!stuck && !on_ball && std::isnan(a.slip)) a.slip = x.t - t_hold;
    if (on_ball && std::isnan(a.land)) a.land = x.t - t_hold;
    ++in_block[p];
    if (trace && std::lround(x.t / ProbeVerdict::kSampleStep) % 5 == 0)
      std::printf("    t − t_hold %7.2f s  ω_m %.4fπ  mode %d  L1 %.4f m  s* %.4f m  contact %.4f N  T1 %.4f N  T2 %.4f N\n",
                  x.t - t_hold, x.top.omega / kPi, int(x.contact.mode), x.dyn.g.L1, x.contact.s_star, x.dyn.contact,
                  x.dyn.T1, x.dyn.T2);
  };
  long in_blocks = 0;
  const auto block = [&](double, double t_end, long steps) {
    in_blocks += steps;
    if (trace) std::printf("  block to t − t_hold = %.2f s: %ld steps\n", t_end - t_hold, steps);
    int n = 0;
    for (int c : in_block) n += c;
    for (int p = 0; p < kPhases; ++p) a.steps[p] += n > 0 ? double(steps) * in_block[p] / n : 0.0;
    in_block = {};
  };
  const ProbePath path = run_probe_path(chain, start, th, settings, watch, block);
  a.total = path.out.steps;
  a.steps[kWindow] = double(path.out.steps - in_blocks);  // run_task's: the window and its settle
  if (path.decided) {
    a.end = path.decided_at - t_hold;
    const double first_held =
        start.t + std::ceil((t_hold - start.t) / ProbeVerdict::kBlock - 1e-9) * ProbeVerdict::kBlock;
    a.early_lock = path.decided->cls == OrbitClass::LockedCircular &&
                   path.decided_at < first_held + 3 * ProbeVerdict::kBlock - 1e-6;
  } else {
    a.end = win.t_end - t_hold;
  }
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 4;
  const bool verbose = argc > 2 && std::strcmp(argv[2], "-v") == 0;
  // --trace i j fall|omega1 k: every sample of probe k of that chain at grid point (i, j).
  const bool tracing = argc > 6 && std::strcmp(argv[2], "--trace") == 0;
  const int ti = tracing ? std::atoi(argv[3]) : -1, tj = tracing ? std::atoi(argv[4]) : -1;
  const int tk = tracing ? std::atoi(argv[6]) : -1;
  const Threshold tth = tracing && std::strcmp(argv[5], "fall") == 0 ? Threshold::Fall : Threshold::Omega1;
  sim::RunOptions run;  // as the benchmark's [integrator]
  run.method = "dop853";
  run.integ.tol.rtol = 1e-9;
  run.integ.tol.atol = 1e-11;
  // Sums per kind of probe: 0 the start (probe 0), 1 known side, 2 fallen, 3 other side not fallen.
  constexpr std::array<const char*, 4> kKinds = {"probe 0 (start level)", "known side", "other side, fallen",
                                                 "other side, not fallen"};
  std::array<Anatomy, 4> sum{};
  std::array<int, 4> count{};
  std::array<double, 4> slip_sum{}, land_sum{}, end_sum{}, ramp_sum{};
  long mismatches = 0, early_locks = 0, wrong_sides = 0, decided = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      physics::Model m;
      m.p.drive_radius = 0.005 + 0.025 * i / (n - 1);
      m.p.contact_distance = 0.02 + 0.03 * j / (n - 1);
      for (const Threshold th : {Threshold::Fall, Threshold::Omega1}) {
        const BisectSpec spec = map_bench_spec(th, 0.05 * kPi);
        BisectCarry carry;
        for (int k = 0; k < probe_count(spec); ++k) {
          const Probe p = run_probe(spec, m, run, 50.0, k, carry);
          if (p.ran) {
            const ChainSetup chain =
                probe_chain(spec, m, run, 50.0, k == 0 ? std::vector<physics::DriveSegment>{} : carry.history,
                         k == 0 ? spec.start_omega : carry.known_omega, p.omega);
            const physics::State start =
                k == 0 ? seed_state(m, chain.motor(), spec.start_seed, spec.start_omega, 0, 0.0) : carry.known;
            const bool trace = tracing && i == ti && j == tj && th == tth && k == tk;
            const Anatomy a = dissect(chain, start, th, trace);
            mismatches += a.total != p.out.steps;
            early_locks += a.early_lock;
            // The same probe from the same carry held through its window: the same class?
            if (p.decided) {
              BisectSpec held = spec;
              held.decide_early = false;
              const Probe f = run_probe(held, m, run, 50.0, k, carry);
              ++decided;
              if (f.classification.cls != p.classification.cls) {
                ++wrong_sides;
                std::printf("  R=%.4f d=%.3f %s k=%d %.4fπ: decided %s, held through %s\n", m.p.drive_radius,
                            m.p.contact_distance, std::string(to_string(th)).c_str(), k, p.omega / kPi,
                            std::string(to_string(p.classification.cls)).c_str(),
                            std::string(to_string(f.classification.cls)).c_str());
              }
            }
            const int kind = k == 0 ? 0 : p.known_side ? 1 : p.classification.cls == OrbitClass::Fallen ? 2 : 3;
            ++count[kind];
            for (int q = 0; q < kPhases; ++q) sum[kind].steps[q] += a.steps[q];
            sum[kind].total += a.total;
            ramp_sum[kind] += a.ramp;
            end_sum[kind] += a.end;
            if (kind == 2) {
              slip_sum[kind] += std::isnan(a.slip) ? a.land : a.slip;
              land_sum[kind] += a.land;
            }
            if (verbose)
              std::printf("R=%.4f d=%.3f %-10s k=%d %.4fπ %-16s %s steps %5ld: ramp %5.0f stuck %5.0f moving %5.0f "
                          "on ball %5.0f window %5.0f | ramp %.1f s, held to slip %.1f s, to land %.1f s, end %.1f s\n",
                          m.p.drive_radius, m.p.contact_distance, std::string(to_string(th)).c_str(), k,
                          p.omega / kPi, std::string(to_string(p.classification.cls)).c_str(),
                          p.decided ? "decided" : "held   ", a.total, a.steps[kRamp], a.steps[kStuck],
                          a.steps[kMoving], a.steps[kOnBall], a.steps[kWindow], a.ramp, a.slip, a.land, a.end);
          }
          carry = p.next;
        }
      }
    }
  long all = 0;
  for (const Anatomy& a : sum) all += a.total;
  std::printf("probes of ω_fall and ω1 over a %d × %d grid of (R, d), bisection to 0.05π, decided early: %ld steps\n",
              n, n, all);
  std::printf("  %-24s %6s %9s %6s", "probes", "count", "steps", "share");
  for (const char* name : kNames) std::printf(" %9s", name);
  std::printf("   mean: ramp [s], held to slip, to land, to end\n");
  for (int kind = 0; kind < 4; ++kind) {
    const double c = std::max(count[kind], 1);
    std::printf("  %-24s %6d %9ld %5.1f%%", kKinds[kind], count[kind], sum[kind].total,
                100.0 * double(sum[kind].total) / double(std::max(all, 1L)));
    for (double s : sum[kind].steps) std::printf(" %9.0f", s / c);
    std::printf("   %6.1f", ramp_sum[kind] / c);
    if (kind == 2)
      std::printf(" %6.1f %6.1f", slip_sum[kind] / c, land_sum[kind] / c);
    else
      std::printf(" %6s %6s", "", "");
    std::printf(" %6.1f\n", end_sum[kind] / c);
  }
  std::printf("  (per-phase columns: mean steps a probe; replayed steps differing from the probe's own: %ld)\n",
              mismatches);
  std::printf("  locks decided before three whole 5 s blocks held at the level: %ld\n", early_locks);
  std::printf("  probes decided early whose class differs from the same probe's held through its window from the "
              "same start: %ld of %ld\n", wrong_sides, decided);
  return mismatches == 0 && wrong_sides == 0 ? 0 : 1;
}
