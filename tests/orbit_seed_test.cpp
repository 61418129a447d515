// The hold mode's seed "locked_orbit": at 6π rad/s (where the sweep's hold mode finds a locked
// orbit with the bead high) the seed is a stable orbit held by friction, and the Simulation
// started from it through sweep::seed_state stays on it: no spin-up, no transient.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <cstring>
#include <numbers>
#include <thread>
#include <utility>

#include "orbits/continuation.hpp"
#include "orbits/corotating_frame.hpp"
#include "orbits/orbit_families.hpp"
#include "orbits/orbit_seed.hpp"
#include "sim/simulation.hpp"
#include "sweep/seeds.hpp"

using namespace ajx;

TEST(OrbitSeed, LockedOrbitSeedAt6PiIsStableHeldAndStaysPut) {
  const physics::Model m;
  const double w = 6 * std::numbers::pi;
  const auto seed = orbits::locked_orbit_seed(m, w);
  ASSERT_TRUE(seed.has_value());
  EXPECT_EQ(seed->rank, 1);
  EXPECT_TRUE(seed->stable && seed->orbit.admissible);
  EXPECT_LT(seed->orbit.s, m.p.string_length - m.p.contact_distance);  // the bead off the ball
  // Through the sweep's seed function, on a schedule whose phase at t = 0 is not zero.
  const physics::MotorSchedule sched(m.p.drive_radius, {{w, w, 30.0}}, 0.7);
  physics::State s = sweep::seed_state(m, sched, "locked_orbit", w, 0, 0.0);
  EXPECT_EQ(s.contact.mode, physics::Mode::Stuck);
  EXPECT_NEAR(s.contact.s_star, seed->orbit.s, 1e-12);
  sim::RunOptions opt;
  opt.method = "dop853";
  opt.integ.tol.rtol = 1e-11;
  opt.integ.tol.atol = 1e-13;
  sim::Simulation simulation(m, sched, opt);
  const sim::RunSummary r = simulation.run(s, 20.0, 0.0);
  ASSERT_TRUE(r.ok()) << r.failure;
  EXPECT_EQ(s.contact.mode, physics::Mode::Stuck);
  // In the co-rotating frame the pair has not moved: a stable equilibrium started on it
  // departs only by the integration error (rtol 1e-11 over ~380 radians of motor phase).
  const physics::TopKinematics top = sched.top(s.t);
  const orbits::Vec12 z = orbits::frame_state(s.y, top.phi, w);
  const double moved = (z.head<3>() - seed->orbit.p1).norm() + (z.segment<3>(3) - seed->orbit.p2).norm();
  EXPECT_LT(moved, 1e-7);
  std::printf("measured locked_orbit_seed: s %.4f m, bead radius %.4f m, margins %.4f/%.4f N, moved %.2e m in 20 s\n",
              seed->orbit.s, seed->orbit.rho1, seed->orbit.margins.up, seed->orbit.margins.down, moved);
}

TEST(OrbitSeed, RampDownFromTheSeedSlipsWhereItsBranchLeavesTheCone) {
  // From the 6π seed, ramp ω_m down: the bead holds until the quasi-static branch of its
  // stuck orbit leaves the static cone (cone_exit_down, located by continuation), and slips
  // there. The ramp makes the orbit lag the branch by an amount first order in the rate, so
  // the miss must shrink at least twofold when the rate is divided by 4, and at 0.025 rad/s²
  // be within 1e-3 of ω_m.
  const physics::Model m;
  const double pi = std::numbers::pi, w0 = 6 * pi, w1 = 4.4 * pi;
  const auto seed = orbits::locked_orbit_seed(m, w0);
  ASSERT_TRUE(seed.has_value());
  orbits::ContinuationOptions c;
  c.direction = -1;
  c.lambda_min = w1;
  c.lambda_max = w0 + 1.0;
  const orbits::Branch b = orbits::continue_branch({m, w0, orbits::Closure::Stuck, seed->orbit.s},
                                                   orbits::unknowns(seed->orbit), "omega", c);
  double exit = -1;
  for (const auto& e : b.events)
    if (e.kind == orbits::EventKind::ConeExitDown && exit < 0) exit = e.lambda;
  ASSERT_GT(exit, w1);
  std::vector<double> miss;
  for (double rate : {0.1, 0.025}) {
    const physics::MotorSchedule sched(m.p.drive_radius, {{w0, w0, 1.0}, {w0, w1, (w0 - w1) / rate}});
    physics::State s = sweep::seed_state(m, sched, "locked_orbit", w0, 0, 0.0);
    sim::RunOptions opt;
    opt.method = "dop853";
    opt.integ.tol.rtol = 1e-10;
    opt.integ.tol.atol = 1e-12;
    sim::Simulation simulation(m, sched, opt);
    double slip = -1, landed = -1;
    const sim::RunSummary r = simulation.run(s, sched.duration(), 1e-3, [&](const sim::Sample& x) {
      if (slip < 0 && x.contact.mode != physics::Mode::Stuck) slip = x.top.omega;
      if (landed < 0 && x.contact.mode == physics::Mode::BottomStop) landed = x.top.omega;
    });
    ASSERT_TRUE(r.ok()) << r.failure;
    ASSERT_GT(slip, 0) << "the bead never slipped";
    miss.push_back(slip - exit);
    std::printf("measured ramp_down_slip: rate %g rad/s², slips at %.6f rad/s, branch leaves the cone at %.6f "
                "rad/s (%.5fπ), miss %.2e rad/s; the bead then slides in steps and lands on the ball at %.4fπ\n",
                rate, slip, exit, exit / pi, slip - exit, landed / pi);
  }
  EXPECT_LT(std::abs(miss[1]), 0.5 * std::abs(miss[0]));
  EXPECT_LT(std::abs(miss[1]), 1e-3 * exit);
}

namespace {
bool same_bits(const std::optional<orbits::SeedOrbit>& a, const std::optional<orbits::SeedOrbit>& b) {
  if (a.has_value() != b.has_value()) return false;
  if (!a) return true;
  const orbits::Vec9 x = orbits::unknowns(a->orbit), y = orbits::unknowns(b->orbit);
  return std::memcmp(x.data(), y.data(), sizeof(double) * 9) == 0 && a->rank == b->rank && a->stable == b->stable &&
         a->orbit.closure == b->orbit.closure;
}
}  // namespace

TEST(OrbitSeed, SeedIsTheCataloguesDeepestStableHeldOrbitAndItsMemoryGivesTheSameBits) {
  // The seed solves only the stuck family of the grid (no frictionless orbits, no cone edges):
  // it is still one of the catalogue's orbits, bit for bit, and none of the catalogue's stable
  // held stuck orbits lies deeper inside the cone.
  physics::Model m;
  m.p.drive_radius = 0.02;
  const double w = 4 * std::numbers::pi;
  const auto seed = orbits::solve_locked_orbit_seed(m, w);
  ASSERT_TRUE(seed.has_value());
  ASSERT_EQ(seed->rank, 1);
  const orbits::OrbitCatalogue cat = orbits::find_orbits(m, w, {orbits::kSeedGridPoints});
  const auto depth = [](const orbits::SteadyOrbit& o) { return std::min(o.margins.up, o.margins.down); };
  bool found = false;
  for (const auto& o : cat.stuck) {
    const orbits::Vec9 x = orbits::unknowns(o), y = orbits::unknowns(seed->orbit);
    found = found || std::memcmp(x.data(), y.data(), sizeof(double) * 9) == 0;
    if (o.admissible && orbits::stability({m, w, o.closure, o.s}, x).stable) EXPECT_LE(depth(o), depth(seed->orbit));
  }
  EXPECT_TRUE(found) << "the seed is not one of the catalogue's stuck orbits";
  // From memory: the same bits on the first call (solved), the second (remembered), and from
  // two threads at once on a model solved by neither before.
  EXPECT_TRUE(same_bits(orbits::locked_orbit_seed(m, w), seed));
  EXPECT_TRUE(same_bits(orbits::locked_orbit_seed(m, w), seed));
  physics::Model other = m;
  other.layers.friction_law = physics::FrictionLaw::PointContact;  // a layer alone: a key of its own
  std::optional<orbits::SeedOrbit> a, b;
  std::thread ta([&] { a = orbits::locked_orbit_seed(other, w); }), tb([&] { b = orbits::locked_orbit_seed(other, w); });
  ta.join();
  tb.join();
  const auto direct = orbits::solve_locked_orbit_seed(other, w);
  EXPECT_TRUE(same_bits(a, direct) && same_bits(b, direct));
  EXPECT_FALSE(same_bits(direct, seed)) << "the point-contact law's seed is the capstan's: the key missed the layer";
}

TEST(OrbitSeed, ScanGivesTheSeedOfEveryRowSolvedInFull) {
  // The scan solves rows cheaply and again in full only where they can decide; its seed must be
  // the definition's bit for bit: at R = 5 mm, where the winner comes out of the drag's homotopy
  // and most directions fail it (at 6π with the point-contact law and no top stop, a homotopy
  // of 12 iterations a step missed the deepest orbit, s = 0.73 m, and took one at s = 0.8 mm);
  // at R = 1.26 mm and 12.2π (a model drawn at random, where 20 or 30 iterations a step missed
  // the deepest unstable orbit); at the documented set; with the bead on the bottom stop
  // (R = 5 mm, d = 2 cm at 4π: no stuck orbit held).
  const double pi = std::numbers::pi;
  const auto model = [](double R, double d) {
    physics::Model m;
    m.p.drive_radius = R;
    m.p.contact_distance = d;
    return m;
  };
  physics::Model point = model(0.005, 0.035), axis = model(0.0012601406869219621, 0.027910328307694486);
  point.layers.friction_law = physics::FrictionLaw::PointContact;
  point.layers.top_stop = false;
  axis.p.bead_mass = 0.050578841790830394;
  axis.p.ball_mass = 0.015671462419353528;
  axis.p.string_length = 0.96785965060987056;
  const std::pair<physics::Model, double> cases[] = {{model(0.005, 0.03), 4 * pi}, {point, 6 * pi},
                                                     {axis, 38.299972870494933}, {model(0.015, 0.035), 4 * pi},
                                                     {model(0.005, 0.02), 4 * pi}};
  for (const auto& [m, w] : cases) {
    const std::clock_t c0 = std::clock();
    const auto full = orbits::solve_locked_orbit_seed(m, w);
    const std::clock_t c1 = std::clock();
    const auto scan = orbits::scan_locked_orbit_seed(m, w);
    const std::clock_t c2 = std::clock();
    ASSERT_TRUE(full.has_value());
    std::printf("measured seed_cost: R %.4g m, d %.4g m, ω %.3fπ: rank %d at s %.4f m; CPU every row in full %.3f s, "
                "the scan %.3f s\n", m.p.drive_radius, m.p.contact_distance, w / pi, full->rank, full->orbit.s,
                double(c1 - c0) / CLOCKS_PER_SEC, double(c2 - c1) / CLOCKS_PER_SEC);
    EXPECT_TRUE(same_bits(scan, full)) << "R " << m.p.drive_radius << " d " << m.p.contact_distance << " ω "
                                       << w / pi << "π: full s " << full->orbit.s << " rank " << full->rank
                                       << ", scan s " << (scan ? scan->orbit.s : -1.0) << " rank "
                                       << (scan ? scan->rank : -1);
  }
}
