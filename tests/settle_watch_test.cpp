// Settling that stops once its orbit is known (sim/settle_watch.hpp, run through sweep tasks):
// a fixed point's settle ends early and its measured window starts within ε l of where the full
// settle leaves it, with the same class; a settle that never converges gives the same bits as
// without the early stop; a tolerance of zero or one above the classifier's is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "config/config.hpp"
#include "sweep/plan.hpp"
#include "sweep/task.hpp"

using namespace ajx;

namespace {

// Both balls hanging at 17π with the paper's rigid tie: the fallen pair (the bead on the bottom
// ball) settles onto a fixed point of the co-rotating frame, turning with the motor; its swing
// about it decays at about the drag rate, so that ε l is reached some 85 s into the settle.
const char* kFixed = R"(
[model]
drive_radius = 0.015
contact_distance = 0.035
[layers]
friction = "stick_slip"
[integrator]
method = "dop853"
rtol = 1e-9
atol = 1e-11
[hold]
omega = [53.40707511102649]
settle = 150.0
measure = 10.0
sample_rate = 50.0
)";

// Both balls hanging, kicked (0.3 m/s) at ω_m = 0: a swing that drag damps at γ ~ 0.05/s, far
// from rest for the whole 30 s settle.
const char* kSwing = R"(
[model]
drive_radius = 0.015
contact_distance = 0.035
[integrator]
method = "dop853"
rtol = 1e-9
atol = 1e-11
[hold]
omega = [0.0]
settle = 30.0
measure = 5.0
perturbations = 1
perturbation = 0.3
sample_rate = 50.0
)";

// The fitted tie clutch from Table 1's orbit at 4π, stepped up to 15π and 15.5π: a flower, the
// balls circling their own axes while the pattern turns. In the frame turning with the tie it
// comes back to itself about every 2 s (6 crossings of the section), not a fixed point.
const char* kPeriodic = R"(
[model]
drive_radius = 0.015
contact_distance = 0.035
tie_static_torque = 1.5e-3
tie_kinetic_torque = 1.35e-3
tie_damping = 2e-6
[layers]
friction = "stick_slip"
tie = "clutch"
[integrator]
method = "dop853"
rtol = 1e-9
atol = 1e-11
[protocol]
start_seed = "circular_high"
start_omega = 12.566370614359172
windows_per_task = 4
sample_rate = 50.0
[[protocol.segment]]
kind = "steps"
from = 12.566370614359172
to = 12.566370614359172
num = 1
settle = 60.0
measure = 10.0
[[protocol.segment]]
kind = "steps"
from = 47.12388980384689
to = 48.69468613064179
num = 2
settle = 100.0
measure = 20.0
step_rate = 0.1
)";

// A staircase of one held level, for the keys of [protocol].
const char* kSteps = R"(
[protocol]
[[protocol.segment]]
kind = "steps"
from = 12.566370614359172
to = 12.566370614359172
num = 1
settle = 60.0
measure = 10.0
)";

struct Ran {
  sweep::TaskOutput out;
  std::vector<sweep::OrbitClassification> classes;
};

Ran run_chain(const std::string& text, std::size_t chain, const std::vector<std::string>& overrides) {
  const config::SweepConfig cfg = config::parse_sweep_config(text, "test.toml", overrides);
  const sweep::SweepPlan plan = config::make_plan(cfg);
  Ran r;
  r.out = sweep::run_task(plan.setups[chain], plan.spans[chain][0], plan.start_state(chain));
  r.classes = sweep::classify_windows(plan.setups[chain], r.out);
  return r;
}

}  // namespace

TEST(SettleWatch, AFixedPointEndsItsSettleEarlyAndIsMeasuredFromWithinTolerance) {
  const double eps = 1e-3, l = 0.826;
  const Ran early = run_chain(kFixed, 0, {"hold.early_stop=true"});
  const Ran full = run_chain(kFixed, 0, {"hold.early_stop=false"});
  ASSERT_TRUE(early.out.ok && full.out.ok);
  EXPECT_EQ(full.out.skipped, 0.0);
  EXPECT_GT(early.out.skipped, 10.0);         // at least two blocks of the 150 s settle left out
  EXPECT_LT(early.out.steps, full.out.steps);  // and not integrated
  EXPECT_EQ(early.out.simulated, full.out.simulated);  // the same stretch of the schedule
  ASSERT_EQ(early.classes.size(), 1u);
  EXPECT_EQ(early.classes[0].cls, sweep::OrbitClass::Fallen);
  EXPECT_EQ(early.classes[0].cls, full.classes[0].cls);
  // The window holds the same sample times, and starts within ε l of the full settle's state
  // (both lie within the estimated distance D ≤ ε l of the fixed point).
  const auto& a = early.out.windows[0];
  const auto& b = full.out.windows[0];
  ASSERT_EQ(a.t, b.t);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(a.r1[std::size_t(k)], b.r1[std::size_t(k)], eps * l) << k;
    EXPECT_NEAR(a.r2[std::size_t(k)], b.r2[std::size_t(k)], eps * l) << k;
  }
  // ... and so on through the window: the orbit is the same.
  for (std::size_t i = 0; i < a.r1.size(); ++i) EXPECT_NEAR(a.r1[i], b.r1[i], eps * l) << i;
}

TEST(SettleWatch, APeriodicOrbitSkipsWholePeriodsAndIsMeasuredAsTheSameOrbit) {
  const Ran early = run_chain(kPeriodic, 0, {"protocol.early_stop=true"});
  const Ran full = run_chain(kPeriodic, 0, {"protocol.early_stop=false"});
  ASSERT_TRUE(early.out.ok && full.out.ok);
  EXPECT_GT(early.out.skipped, 10.0);
  EXPECT_LT(early.out.steps, full.out.steps);
  EXPECT_EQ(early.out.simulated, full.out.simulated);
  ASSERT_EQ(early.classes.size(), 3u);
  ASSERT_EQ(full.classes.size(), 3u);
  for (std::size_t w = 0; w < 3; ++w) {
    const auto& a = early.classes[w];
    const auto& b = full.classes[w];
    EXPECT_EQ(a.cls, b.cls) << w << ": " << a.reason << " | " << b.reason;
    if (w == 0) continue;
    EXPECT_EQ(a.cls, sweep::OrbitClass::Flower) << a.reason;  // not a fixed point of the turning frame
    EXPECT_EQ(early.out.windows[w].t, full.out.windows[w].t);
    // The same orbit at another phase: the features the classifier compares differ by less than
    // its own steadiness tolerances (L1_drift_tol l, omega_drift_tol ω_ball).
    const sweep::ClassifierSettings cs;
    EXPECT_LT(std::abs(a.stats.L1.mean - b.stats.L1.mean), cs.L1_drift_tol * 0.826) << w;
    EXPECT_LT(std::abs(a.stats.omega_ball - b.stats.omega_ball), cs.omega_drift_tol * std::abs(b.stats.omega_ball)) << w;
  }
}

TEST(SettleWatch, ASettleThatNeverConvergesIsIntegratedAsWithoutIt) {
  // Chain 1: the kicked copy of the hanging seed.
  const Ran on = run_chain(kSwing, 1, {"hold.early_stop=true"});
  const Ran off = run_chain(kSwing, 1, {"hold.early_stop=false"});
  ASSERT_TRUE(on.out.ok && off.out.ok);
  EXPECT_EQ(on.out.skipped, 0.0);
  // Bit for bit, but for the count of right-hand sides: the section's crossings were located
  // on the interpolant, which DOP853 builds with 3 more stages.
  EXPECT_GE(on.out.rhs_evals, off.out.rhs_evals);
  sweep::TaskOutput same = on.out;
  same.rhs_evals = off.out.rhs_evals;
  EXPECT_EQ(sweep::encode(same), sweep::encode(off.out));
}

TEST(SettleWatch, ToleranceOutOfRangeIsRefusedNamingFileKeyAndRange) {
  for (const char* bad : {"protocol.early_stop_tolerance=0", "protocol.early_stop_tolerance=-1e-3",
                          "protocol.early_stop_tolerance=0.02"}) {
    try {
      config::parse_sweep_config(kSteps, "steps.toml", {bad});
      ADD_FAILURE() << "accepted " << bad;
    } catch (const config::ConfigError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("steps.toml"), std::string::npos) << what;
      EXPECT_NE(what.find("early_stop_tolerance"), std::string::npos) << what;
      EXPECT_NE(what.find("(0, 0.01]"), std::string::npos) << what;
    }
  }
}
