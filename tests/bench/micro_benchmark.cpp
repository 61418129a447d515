// Micro-benchmarks (Google Benchmark): the cost of one right-hand-side evaluation in each
// contact mode, of one step of each method, of the full run path per evaluation (BM_run),
// and the integrator overhead of a step,
//   overhead = 1 - (RHS evaluations per step) x (cost of one evaluation) / (cost of a step),
// i.e. the part of a step spent outside the physics (stage combinations, error norm, the
// std::function call, the derivative cache). Printed as a table after the benchmarks.
// Run:  build/tests/bench/micro_benchmark [--benchmark_repetitions=5]
// The state is the paper's Table 1 orbit with the bead high, turning at ω_m = 6π rad/s
// (sweep::seed_state "circular_high"), R = 1 cm, d = 3 cm: a taut, sliding string.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <string>

#include "numerics/stepper.hpp"
#include "physics/astrojax_system.hpp"
#include "physics/rotating_axes.hpp"
#include "sim/simulation.hpp"
#include "sweep/seeds.hpp"

namespace {

using namespace ajx;
using numerics::Vec;

constexpr double kOmega = 6.0 * std::numbers::pi;  // ω_m [rad/s]

struct Fixture {
  physics::Model model;
  physics::MotorSchedule schedule{0.01, {{kOmega, kOmega, 1e6}}};  // R: the model.p.drive_radius set below
  physics::State s0;
  Fixture() {
    model.p.drive_radius = 0.01;
    model.p.contact_distance = 0.03;
    s0 = sweep::seed_state(model, schedule, "circular_high", kOmega, 0, 0.0);
  }
};
const Fixture& fixture() {
  static const Fixture f;
  return f;
}

// The right-hand side in the lab axes, or in the axes turning with the motor
// (physics/rotating_axes.hpp, the product's default: no sin/cos, plus the frame terms −Ω×r', −Ω×v').
using Rhs = void (*)(const physics::Model&, const physics::MotorSchedule&, const physics::Contact&, double,
                     const Vec&, Vec&);

// One evaluation through numerics::System, as every stepper calls it.
void BM_rhs_in(benchmark::State& st, physics::Mode mode, Rhs rhs) {
  const Fixture& fx = fixture();
  physics::Contact c = fx.s0.contact;
  c.mode = mode;
  c.sigma = 1;
  c.s_star = (physics::Vec3(fx.s0.y.segment<3>(physics::idx::r1)) - fx.schedule.top(0).a).norm();
  const numerics::System f = [&](double t, const Vec& y, Vec& dydt) { rhs(fx.model, fx.schedule, c, t, y, dydt); };
  Vec y = fx.s0.y, dydt(physics::idx::dim);
  double t = 0.0;
  for (auto _ : st) {
    f(t, y, dydt);
    benchmark::DoNotOptimize(dydt.data());
    t += 1e-9;  // a new time each call: no caching anywhere
  }
}
void BM_rhs(benchmark::State& st, physics::Mode mode) { BM_rhs_in(st, mode, &physics::rhs); }
void BM_rhs_rotating(benchmark::State& st, physics::Mode mode) { BM_rhs_in(st, mode, &physics::rhs_in_rotating_axes); }
BENCHMARK_CAPTURE(BM_rhs, sliding, physics::Mode::Sliding);
BENCHMARK_CAPTURE(BM_rhs, stuck, physics::Mode::Stuck);
BENCHMARK_CAPTURE(BM_rhs, bottom_stop, physics::Mode::BottomStop);
BENCHMARK_CAPTURE(BM_rhs, slack, physics::Mode::Slack);
BENCHMARK_CAPTURE(BM_rhs_rotating, sliding, physics::Mode::Sliding);
BENCHMARK_CAPTURE(BM_rhs_rotating, stuck, physics::Mode::Stuck);
BENCHMARK_CAPTURE(BM_rhs_rotating, bottom_stop, physics::Mode::BottomStop);

// The motor kinematics alone (φ(t), sin φ, cos φ, ȧ, ä), part of every evaluation above: the
// most a formulation in the frame co-rotating with the motor (autonomous, no sin/cos) could
// save per evaluation.
void BM_top(benchmark::State& st) {
  const Fixture& fx = fixture();
  double t = 0.0;
  for (auto _ : st) {
    const physics::TopKinematics k = fx.schedule.top(t);
    benchmark::DoNotOptimize(k.a_ddot.data());
    t += 1e-9;
  }
}
BENCHMARK(BM_top);

// One accepted step (attempt + accept) along the orbit, in the sliding mode. Every 2000 steps
// the state goes back to the seed (and the stepper is reset), so the orbit never drifts far.
void BM_step(benchmark::State& st, const char* method, double h) {
  const Fixture& fx = fixture();
  const physics::Contact c = fx.s0.contact;
  const numerics::System f = [&](double t, const Vec& y, Vec& dydt) {
    physics::rhs(fx.model, fx.schedule, c, t, y, dydt);
  };
  auto stepper = numerics::make_stepper(method);
  const numerics::Tolerances tol{1e-9, 1e-12};
  Vec y = fx.s0.y, y_new(physics::idx::dim);
  double t = 0.0;
  long k = 0, restarts = 0;
  for (auto _ : st) {
    benchmark::DoNotOptimize(stepper->attempt(f, t, y, h, y_new, tol));
    stepper->accept(f);
    y = y_new;
    t += h;
    if (++k % 2000 == 0) {
      y = fx.s0.y;
      t = 0.0;
      stepper->reset();
      ++restarts;
    }
  }
  // Evaluations per accepted step, the restarts' extra first stages excluded.
  st.counters["rhs_per_step"] = double(stepper->rhs_evals() - restarts) / double(st.iterations());
}
BENCHMARK_CAPTURE(BM_step, euler, "euler", 5e-4);
BENCHMARK_CAPTURE(BM_step, rk4, "rk4", 5e-4);
BENCHMARK_CAPTURE(BM_step, dopri5, "dopri5", 2e-3);
BENCHMARK_CAPTURE(BM_step, dop853, "dop853", 5e-3);
BENCHMARK_CAPTURE(BM_step, radau_iia, "radau_iia", 2e-3);

// The full run path per right-hand-side evaluation: sim::Simulation::run with the product's
// defaults (DOP853, rotating axes, guard events with the certified step bound, projection),
// 1 s of the orbit per iteration, without samples and with the sweeps' 100 Hz samples, and
// without the guards' step bound, and with the run statistics of `astrojax run` (ω_ball over the
// last half second here: the balls' azimuths followed on the interpolant).
// s_per_eval = CPU time / RHS evaluations (printed as ...n: nanoseconds), to set against BM_rhs_rotating/sliding (the bare
// right-hand side). The state is the seed orbit (sliding, taut) or the bead resting on the
// bottom ball of sweeps/scenes/bottom_stop_fast.toml at 15π rad/s.
void BM_run(benchmark::State& st, bool bottom, double sample_rate, bool bound = true, bool statistics = false) {
  const Fixture& fx = fixture();
  const physics::MotorSchedule fast{fx.model.p.drive_radius, {{15 * std::numbers::pi, 15 * std::numbers::pi, 1e6}}};
  const physics::MotorSchedule& schedule = bottom ? fast : fx.schedule;
  const physics::State start =
      bottom ? sim::explicit_state(fx.model, fast, {-0.00047020629163896111, -8.5514041346164998e-05, -0.79593113236439883},
                                   {-0.00030637474098384307, -7.5606879979839547e-05, -0.82593068337876641},
                                   {-0.00014442299005515755, -0.0066561981605852659, 5.3244405839770204e-05},
                                   {-0.00032151735987066675, 0.0010426578278003615, 5.4819768458085324e-05},
                                   physics::Mode::BottomStop)
             : fx.s0;
  sim::RunOptions opt;
  opt.run_statistics = statistics;  // off: as a sweep runs it
  opt.guard_step_bound = bound;
  sim::Simulation simulation(fx.model, schedule, opt);
  long evals = 0, samples = 0;
  const sim::SampleObserver count = [&](const sim::Sample&) { ++samples; };
  for (auto _ : st) {
    physics::State s = start;
    const sim::RunSummary r = simulation.run(s, s.t + 1.0, sample_rate > 0 ? 1.0 / sample_rate : 0.0, count);
    evals += r.rhs_evals;
  }
  st.counters["s_per_eval"] = benchmark::Counter(double(evals), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  st.counters["evals_per_s"] = double(evals) / double(st.iterations());
}
BENCHMARK_CAPTURE(BM_run, sliding, false, 0.0)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_run, sliding_100Hz, false, 100.0)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_run, bottom_stop_fast, true, 0.0)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_run, bottom_stop_fast_100Hz, true, 100.0)->Unit(benchmark::kMicrosecond);
// Without the guards' step bound (h ≤ 4/Ω): the most a cheaper certified bound could save.
BENCHMARK_CAPTURE(BM_run, sliding_no_bound, false, 0.0, false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_run, bottom_stop_fast_no_bound, true, 0.0, false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_run, bottom_stop_fast_statistics, true, 0.0, true, true)->Unit(benchmark::kMicrosecond);

// Collects the mean CPU time per iteration, then prints the overhead table.
class OverheadReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      if (r.run_type != Run::RT_Iteration && r.aggregate_name != "median") continue;
      const std::string name = r.run_name.str();
      // With repetitions, the median aggregate (reported last) is the figure kept.
      cpu_ns_[name] = r.GetAdjustedCPUTime();  // time unit: ns (the default)
      const auto it = r.counters.find("rhs_per_step");
      if (it != r.counters.end()) evals_[name] = it->second.value;
    }
  }
  void Finalize() override {
    ConsoleReporter::Finalize();
    const auto rhs = cpu_ns_.find("BM_rhs/sliding");
    if (rhs == cpu_ns_.end()) return;
    std::printf("\nintegrator overhead (sliding mode; one RHS evaluation = %.1f ns):\n", rhs->second);
    std::printf("%-8s %12s %14s %14s %10s\n", "method", "step [ns]", "RHS per step", "in RHS [ns]", "overhead");
    for (const char* m : {"euler", "rk4", "dopri5", "dop853", "radau_iia"}) {
      const std::string key = std::string("BM_step/") + m;
      if (!cpu_ns_.count(key) || !evals_.count(key)) continue;
      const double step = cpu_ns_[key], in_rhs = evals_[key] * rhs->second;
      std::printf("%-8s %12.1f %14.2f %14.1f %9.1f%%\n", m, step, evals_[key], in_rhs,
                  100.0 * (1.0 - in_rhs / step));
    }
  }

 private:
  std::map<std::string, double> cpu_ns_, evals_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  OverheadReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  return 0;
}
