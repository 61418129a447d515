// Long-horizon validation (ctest -L long): the paper's protocol shape over 600 s, ramp up from
// rest past 14π rad/s, down to 3π, up again, with the paper's l, m, c_D, μ and both friction
// laws. Over the whole run: W_m = ΔE + losses to 1e-6 of W_m, constraint drift below 1e-10 m,
// friction power never negative while the string is taut; with dopri5 and dop853.
#include <gtest/gtest.h>

#include <cstdio>

#include "sim/simulation.hpp"

using namespace ajx;
using namespace ajx::physics;

namespace {
const double pi = 3.141592653589793;
}

class PaperProtocol : public ::testing::TestWithParam<std::tuple<FrictionLaw, std::string>> {};

TEST_P(PaperProtocol, EnergyBalanceAndDriftHoldOver600s) {
  const auto [law, method] = GetParam();
  Model m;
  m.p.drive_radius = 0.01;
  m.layers.friction_law = law;
  const MotorSchedule sched(m.p.drive_radius, {{0.0, 14.5 * pi, 250.0}, {14.5 * pi, 3.0 * pi, 200.0}, {3.0 * pi, 16.0 * pi, 150.0}});
  State s = sim::hanging_at_rest(m, sched);
  sim::RunOptions o;
  o.method = method;
  o.integ.tol.rtol = 1e-10;
  o.integ.tol.atol = 1e-12;
  sim::Simulation simulation(m, sched, o);
  double min_power_taut = 0.0;
  const sim::RunSummary r = simulation.run(s, sched.duration(), 0.005, [&](const sim::Sample& smp) {
    if (smp.dyn.T2 >= 0.0) min_power_taut = std::min(min_power_taut, smp.dyn.friction_power);
  });
  ASSERT_TRUE(r.ok()) << r.failure;
  EXPECT_LT(std::abs(r.energy.residual), 1e-6 * r.energy.motor_work);
  EXPECT_LT(r.max_drift, 1e-10);
  EXPECT_LT(r.max_sample_drift, 1e-10);
  EXPECT_GE(min_power_taut, 0.0);
  std::printf("measured %s/%s: W_m %.6e J residual %.2e J drag %.4e J friction %.4e J impacts %.3e J "
              "sticks %ld switches %ld steps %ld min tension %.3e N\n",
              std::string(to_string(law)).c_str(), method.c_str(), r.energy.motor_work, r.energy.residual,
              r.energy.drag_loss, r.energy.friction_loss, r.energy.impact_loss, r.sticks, r.mode_switches,
              r.steps, r.min_tension);
}

INSTANTIATE_TEST_SUITE_P(Laws, PaperProtocol,
                         ::testing::Combine(::testing::Values(FrictionLaw::Capstan, FrictionLaw::PointContact),
                                            ::testing::Values(std::string("dopri5"), std::string("dop853"))));
