#include "sweep/plan.hpp"

#include <algorithm>
#include <cmath>

#include "physics/drive.hpp"
#include "sweep/seeds.hpp"

namespace ajx::sweep {

SweepPlan make_plan(const config::SweepConfig& cfg) {
  SweepPlan plan;
  for (const config::GridPoint& g : config::expand_grid(cfg)) {
    if (!cfg.hold) {
      plan.starts.push_back({cfg.start_seed, cfg.start_omega, 0});
      plan.points.push_back(g);
      continue;
    }
    // The hold mode: one staircase of a single level, settle then measure.
    for (double w : cfg.hold->omega)
      for (const std::string& seed : cfg.hold->seeds)
        for (int k = 0; k <= cfg.hold->perturbations; ++k) {
          plan.starts.push_back({seed, w, k});
          config::GridPoint held = g;
          held.protocol = {Segment{Segment::Kind::Steps, {}, {w, w, 1, cfg.hold->settle, cfg.hold->measure, 1.0}}};
          plan.points.push_back(std::move(held));
        }
  }
  plan.kick = cfg.hold ? cfg.hold->perturbation : 0.0;
  for (std::size_t i = 0; i < plan.points.size(); ++i) {
    ChainSetup c;
    c.model = plan.points[i].model;
    c.protocol = compile(plan.points[i].protocol, plan.starts[i].omega);
    c.run = cfg.run;
    c.sample_rate = cfg.sample_rate;
    plan.spans.push_back(split(c.protocol, cfg.windows_per_task));
    plan.first_task.push_back(plan.n_tasks);
    plan.n_tasks += plan.spans.back().size();
    plan.max_windows = std::max(plan.max_windows, c.protocol.windows.size());
    for (const Window& w : c.protocol.windows)
      plan.max_samples = std::max(plan.max_samples, std::size_t(std::ceil((w.t_end - w.t_begin) * c.sample_rate)) + 1);
    plan.total_duration += c.protocol.duration;
    plan.setups.push_back(std::move(c));
  }
  return plan;
}

physics::State SweepPlan::start_state(std::size_t c) const {
  const physics::MotorSchedule schedule(setups[c].protocol.schedule);
  return seed_state(setups[c].model, schedule, starts[c].seed, starts[c].omega, starts[c].perturbation, kick);
}

}  // namespace ajx::sweep
