// Sweep tasks: a chain run as tasks (each from the previous task's final state) records
// every window at the fixed sample rate; the result depends on the task alone; the byte
// encoding for the farm is exact; a failed integration comes back with its reason.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "one_set.hpp"
#include "physics/state_row.hpp"
#include "sim/simulation.hpp"
#include "sweep/seeds.hpp"
#include "sweep/task.hpp"

using namespace ajx;
using namespace ajx::sweep;

namespace {
const double pi = 3.141592653589793;

ChainSetup short_chain() {
  ChainSetup c;
  c.model.p.drive_radius = 0.01;
  Segment up{Segment::Kind::Ramp, {2 * pi, 6 * pi, 0.5, 2.0}, {}};
  Segment hold{Segment::Kind::Steps, {}, {6 * pi, 5 * pi, 2, 3.0, 2.0, 1.0}};
  c.protocol = compile({up, hold}, 2 * pi);
  c.run.method = "dop853";
  c.run.integ.tol.rtol = 1e-10;
  c.run.integ.tol.atol = 1e-12;
  c.sample_rate = 100.0;
  return c;
}

// Run the chain as consecutive tasks, each from the previous task's final state.
std::vector<WindowRecord> run_chain(const ChainSetup& c, int windows_per_task) {
  const physics::MotorSchedule sched = c.motor();
  physics::State carry = sim::hanging_at_rest(c.model, sched);
  std::vector<WindowRecord> all;
  for (const TaskSpan& span : split(c.protocol, windows_per_task)) {
    TaskOutput out = run_task(c, span, carry);
    EXPECT_TRUE(out.ok) << out.failure;
    EXPECT_DOUBLE_EQ(out.final_state.t, span.t_end);
    carry = out.final_state;
    for (auto& w : out.windows) all.push_back(std::move(w));
  }
  return all;
}
}  // namespace

TEST(Task, EveryWindowIsRecordedAtTheSampleRate) {
  const ChainSetup c = short_chain();
  const auto windows = run_chain(c, 2);
  ASSERT_EQ(windows.size(), c.protocol.windows.size());
  for (std::size_t i = 0; i < windows.size(); ++i) {
    const Window& w = c.protocol.windows[i];
    const WindowRecord& r = windows[i];
    EXPECT_EQ(r.index, int(i));
    // N = duration × rate, give or take the grid's phase at the window's edges.
    EXPECT_NEAR(double(r.size()), (w.t_end - w.t_begin) * c.sample_rate, 1.0);
    ASSERT_GT(r.size(), 0u);
    EXPECT_GE(r.t.front(), w.t_begin);
    EXPECT_LT(r.t.back(), w.t_end);
    EXPECT_EQ(r.r1.size(), 3 * r.size());
    EXPECT_NEAR(r.omega_m.front(), w.omega_begin, std::abs(w.omega_end - w.omega_begin) / 10 + 1e-9);
  }
}

TEST(Task, EveryWindowClosesItsEnergyBalance) {
  // P_motor = P_drag + P_other + dE/dt over any window, ramps and holds alike: the ledgers are
  // the run's own work integrals, whose balance closes to ~1e-10 of W_m at rtol 1e-10
  // (simulation_test); 1e-7 of the largest power leaves three orders for round-off.
  const ChainSetup c = short_chain();
  for (const WindowRecord& r : run_chain(c, 3)) {
    const WindowPowers p = window_powers(r);
    const double scale = std::max({std::abs(p.motor), p.drag, std::abs(p.energy_rate)});
    ASSERT_GT(scale, 0.0);
    EXPECT_NEAR(p.motor, p.drag + p.other + p.energy_rate, 1e-7 * scale) << "window " << r.index;
    EXPECT_GT(p.drag, 0.0);
  }
}

TEST(Task, EveryWindowClosesTheMotorsLedgerWithTheClutch) {
  // The tie clutch of the main job (tests/one_set.hpp) from the circular_high seed, held at 10π:
  // the tie slips and the orbit lags. Over every window the motor's power at the rod splits as
  // P_m = P_string + P_clutch + dE_tie/dt, and P_string = P_drag + P_other + dE/dt, both to the
  // quadratures' error (~rtol of the work, 1e-7 of the largest power leaves three orders). The
  // clutch takes a real share (the measurement: 58 % in the steady lag).
  ChainSetup c;
  c.model = one_parameter_set();
  const double w = 10 * pi;
  c.protocol = compile({Segment{Segment::Kind::Steps, {}, {w, w + 0.4, 3, 1.0, 2.0, 1.0}}}, w);  // 3 windows
  c.run.method = "dop853";
  c.run.integ.tol.rtol = 1e-10;
  c.run.integ.tol.atol = 1e-12;
  c.sample_rate = 50.0;
  const physics::MotorSchedule sched = c.motor();
  const TaskOutput out = run_task(c, split(c.protocol, 8).front(), seed_state(c.model, sched, "circular_high", w, 0, 0.0));
  ASSERT_TRUE(out.ok) << out.failure;
  ASSERT_FALSE(out.windows.empty());
  for (const WindowRecord& r : out.windows) {
    const WindowPowers p = window_powers(r);
    const double dt = r.last.t - r.first.t, tie_rate = (r.last.tie_energy - r.first.tie_energy) / dt;
    const double scale = std::max({std::abs(p.motor), std::abs(p.string), p.drag, std::abs(p.energy_rate)});
    EXPECT_NEAR(p.motor, p.string + p.clutch + tie_rate, 1e-7 * scale) << "window " << r.index;
    EXPECT_NEAR(p.string, p.drag + p.other + p.energy_rate, 1e-7 * scale) << "window " << r.index;
    EXPECT_GT(p.clutch, 0.1 * p.motor) << "window " << r.index;
  }
  const WindowPowers last = window_powers(out.windows.back());
  std::printf("measured clutch lag at 10π, last window: P_m %.4e W, P_string %.4e W, P_clutch %.4e W (%.0f %%)\n",
              last.motor, last.string, last.clutch, 100 * last.clutch / last.motor);
}

TEST(Task, TheMotorSustainsALockedOrbitAndNothingMore) {
  // Started on the stable locked orbit at 6π (the locked_orbit seed: an equilibrium of the
  // co-rotating frame to Newton's round-off), the motor's mean power equals drag's and E does
  // not change. Departures from the orbit decay (its slowest rate is -c_D/2m), so the only
  // drift left is the integrator's, ~rtol per unit time: |dE/dt| ≤ 1e-6 P_drag with margin.
  ChainSetup c;
  c.model.p.drive_radius = 0.01;
  c.model.p.contact_distance = 0.03;
  const double w = 6 * pi;
  c.protocol = compile({Segment{Segment::Kind::Steps, {}, {w, w, 1, 2.0, 10.0, 1.0}}}, w);
  c.run.method = "dop853";
  c.run.integ.tol.rtol = 1e-10;
  c.run.integ.tol.atol = 1e-12;
  c.sample_rate = 50.0;
  const physics::MotorSchedule sched = c.motor();
  const TaskOutput out = run_task(c, split(c.protocol, 1).front(), seed_state(c.model, sched, "locked_orbit", w, 0, 0.0));
  ASSERT_TRUE(out.ok) << out.failure;
  ASSERT_EQ(out.windows.size(), 1u);
  const WindowPowers p = window_powers(out.windows.front());
  ASSERT_GT(p.drag, 0.0);
  EXPECT_NEAR(p.motor, p.drag, 1e-6 * p.drag);
  EXPECT_NEAR(p.energy_rate, 0.0, 1e-6 * p.drag);
  EXPECT_NEAR(p.other, 0.0, 1e-6 * p.drag);  // the bead is stuck: no friction work, no impacts
  std::printf("measured on the locked orbit at 6π: P_motor %.6e W, P_drag %.6e W, dE/dt %.2e W\n", p.motor, p.drag,
              p.energy_rate);
}

TEST(Task, SplittingAChainDifferentlyChangesNothingBeyondTheTolerance) {
  // Task boundaries restart the integrator; the trajectory is the same to the tolerance
  // (this scene is a driven pendulum on the bottom stop, not chaotic over 20 s).
  const ChainSetup c = short_chain();
  const auto a = run_chain(c, 1), b = run_chain(c, 100);
  ASSERT_EQ(a.size(), b.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].size(), b[i].size());
    for (std::size_t k = 0; k < a[i].r2.size(); ++k) worst = std::max(worst, std::abs(a[i].r2[k] - b[i].r2[k]));
  }
  EXPECT_LT(worst, 1e-7);
}

TEST(Task, TheSameTaskTwiceGivesTheSameBytes) {
  const ChainSetup c = short_chain();
  const physics::MotorSchedule sched = c.motor();
  const auto spans = split(c.protocol, 3);
  const physics::State s0 = sim::hanging_at_rest(c.model, sched);
  EXPECT_EQ(encode(run_task(c, spans[0], s0)), encode(run_task(c, spans[0], s0)));
}

TEST(Task, EncodingRoundTripsExactly) {
  const ChainSetup c = short_chain();
  const physics::MotorSchedule sched = c.motor();
  const TaskOutput out = run_task(c, split(c.protocol, 2)[0], sim::hanging_at_rest(c.model, sched));
  const std::vector<std::byte> bytes = encode(out);
  const TaskOutput back = decode_output(bytes);
  EXPECT_EQ(encode(back), bytes);
  EXPECT_EQ(back.windows.size(), out.windows.size());
  EXPECT_EQ(back.final_state.y, out.final_state.y);
  EXPECT_EQ(back.final_state.contact.mode, out.final_state.contact.mode);
  const physics::State st = decode_state(encode(out.final_state));
  EXPECT_EQ(st.y, out.final_state.y);
  EXPECT_EQ(st.t, out.final_state.t);
  std::vector<std::byte> cut(bytes.begin(), bytes.end() - 3);
  EXPECT_THROW(decode_output(cut), std::runtime_error);
}

// The state row (physics/state_row.hpp), the one codec of the carry and /tasks/final_state:
// every field, the tie's χ and χ̇ too, back bit for bit; a rigid tie's row has NaN χ and
// decodes to the 15 components it had.
TEST(Task, TheStateRowRoundTripsEveryField) {
  physics::State s;
  s.t = 12.5;
  s.contact = physics::Contact(physics::Mode::Stuck, -1, 0.4321);
  s.contact.tie = {true, -1, 0.25};
  s.impact_loss = 1.5e-3;
  s.y.resize(physics::idx::dim_tie);
  for (int k = 0; k < physics::idx::dim_tie; ++k) s.y(k) = 0.1 * k - 0.7;
  const std::vector<double> row = physics::state_row(s);
  ASSERT_EQ(row.size(), physics::kStateCols);
  ASSERT_EQ(physics::state_column_names().size(), physics::kStateCols);
  const physics::State back = physics::state_from_row(row);
  EXPECT_EQ(physics::state_row(back), row);
  EXPECT_EQ(back.y, s.y);
  EXPECT_EQ(back.contact.mode, s.contact.mode);
  EXPECT_EQ(back.contact.sigma, -1);
  EXPECT_EQ(back.contact.s_star, 0.4321);
  EXPECT_TRUE(back.contact.tie.slip);
  EXPECT_EQ(back.contact.tie.sigma, -1);
  EXPECT_EQ(back.contact.tie.offset, 0.25);
  EXPECT_EQ(decode_state(encode(s)).y, s.y);
  s.y.conservativeResize(physics::idx::dim);
  const std::vector<double> rigid = physics::state_row(s);
  EXPECT_TRUE(std::isnan(rigid[physics::kStateChiColumn]));
  EXPECT_EQ(physics::state_from_row(rigid).y.size(), physics::idx::dim);
  EXPECT_EQ(physics::state_from_row(rigid).y, s.y);
}

TEST(Task, AFailedIntegrationComesBackWithItsReasonAndLastGoodState) {
  ChainSetup c = short_chain();
  c.run.integ.max_steps = 50;  // far too few for the first task
  const physics::MotorSchedule sched = c.motor();
  const TaskOutput out = run_task(c, split(c.protocol, 100)[0], sim::hanging_at_rest(c.model, sched));
  EXPECT_FALSE(out.ok);
  EXPECT_NE(out.failure.find("max steps"), std::string::npos) << out.failure;
  EXPECT_TRUE(out.final_state.y.allFinite());
  EXPECT_LT(out.final_state.t, c.protocol.duration);
}
