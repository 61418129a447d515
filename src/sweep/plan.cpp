#include "sweep/plan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "physics/drive.hpp"
#include "sweep/basin.hpp"
#include "sweep/seeds.hpp"

namespace ajx::sweep {

namespace {

// A basin part: N chains per level, each one held level whose start is drawn (sweep/basin.hpp).
void add_basin_chains(SweepPlan& plan, const SweepSpec& cfg, const GridPoint& g, std::size_t part) {
  const BasinSpec& b = *cfg.basin;
  for (std::size_t k = 0; k < b.omega.size(); ++k)
    for (int n = 0; n < b.samples; ++n) {
      ChainStart start{std::string(to_string(b.family)), b.omega[k], 0, 0.0};
      start.level = int(k);
      start.sample = n;
      plan.starts.push_back(std::move(start));
      plan.points.push_back(g);
      plan.part.push_back(part);
    }
}

// The chains of one sweep (a plain file, or one part of a grouped file), appended to the plan.
void add_chains(SweepPlan& plan, const PlanPart& p, std::size_t part) {
  const SweepSpec& cfg = p.spec;
  for (const GridPoint& g : expand_grid(p.model, cfg, p.source_name)) {
    if (cfg.basin) {
      add_basin_chains(plan, cfg, g, part);
      continue;
    }
    if (cfg.bisect) {  // one chain of probes per grid point
      plan.starts.push_back({cfg.bisect->start_seed, cfg.bisect->start_omega, 0, 0.0});
      plan.points.push_back(g);
      plan.part.push_back(part);
      continue;
    }
    if (!cfg.hold) {
      plan.starts.push_back({cfg.start_seed, cfg.start_omega, 0, 0.0});
      plan.points.push_back(g);
      plan.part.push_back(part);
      continue;
    }
    // The hold mode: one staircase of a single level, settle then measure.
    for (double w : cfg.hold->omega)
      for (const std::string& seed : cfg.hold->seeds)
        for (int k = 0; k <= cfg.hold->perturbations; ++k) {
          plan.starts.push_back({seed, w, k, cfg.hold->perturbation});
          GridPoint held = g;
          held.protocol = {Segment{Segment::Kind::Steps, {}, {w, w, 1, cfg.hold->settle, cfg.hold->measure, 1.0}}};
          plan.points.push_back(std::move(held));
          plan.part.push_back(part);
        }
  }
}

// A bisection chain: probe_count tasks without windows, whose times depend on the bracket (NaN
// in the plan); its simulated time estimated as the holds plus the ramps between the levels.
void add_probes(SweepPlan& plan, const PlanPart& part, std::size_t chain) {
  const BisectSpec& b = *part.spec.bisect;
  ChainSetup c;
  c.model = plan.points[chain].model;
  c.run = part.run;
  c.sample_rate = part.spec.sample_rate;
  const int n = probe_count(b);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  plan.spans.push_back(std::vector<TaskSpan>(std::size_t(n), TaskSpan{nan, nan, 0, 0}));
  plan.first_task.push_back(plan.n_tasks);
  plan.n_tasks += std::size_t(n);
  c.protocol.duration = n * (b.settle + b.measure) + (std::abs(b.from - b.start_omega) + 2.0 * std::abs(b.to - b.from)) / b.step_rate;
  plan.total_duration += c.protocol.duration;
  plan.setups.push_back(std::move(c));
}

}  // namespace

SweepPlan make_plan(const std::vector<PlanPart>& parts) {
  SweepPlan plan;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const std::size_t first = plan.points.size();
    add_chains(plan, parts[i], i);
    // The part's grid values, placed on the file's axes.
    std::vector<std::size_t> at;
    for (const GridAxis& a : parts[i].spec.grid) {
      auto it = std::find(plan.axes.begin(), plan.axes.end(), a.key);
      if (it == plan.axes.end()) it = plan.axes.insert(plan.axes.end(), a.key);
      at.push_back(std::size_t(it - plan.axes.begin()));
    }
    for (std::size_t c = first; c < plan.points.size(); ++c) {
      std::vector<double> v(plan.axes.size(), std::numeric_limits<double>::quiet_NaN());
      for (std::size_t a = 0; a < at.size(); ++a) v[at[a]] = plan.points[c].values[a];
      plan.points[c].values = std::move(v);
    }
  }
  for (auto& p : plan.points) p.values.resize(plan.axes.size(), std::numeric_limits<double>::quiet_NaN());
  physics::State level_orbit;  // a cloud's orbit, found at sample 0 of each level (its samples are consecutive)
  for (std::size_t i = 0; i < plan.points.size(); ++i) {
    const PlanPart& part = parts[plan.part[i]];
    plan.bisect.push_back(part.spec.bisect);
    if (part.spec.bisect) {
      add_probes(plan, part, i);
      continue;
    }
    ChainSetup c;
    c.model = plan.points[i].model;
    ChainStart& start = plan.starts[i];
    if (start.sample >= 0) {
      const BasinSpec& b = *part.spec.basin;
      c.protocol = basin_protocol(b, start.omega, start.level, start.sample);
      const physics::MotorSchedule schedule = c.motor();
      const physics::State* orbit = nullptr;
      if (b.family == BasinFamily::Cloud) {
        if (start.sample == 0) level_orbit = basin_orbit(c.model, schedule, b, start.omega);
        orbit = &level_orbit;
      }
      start.state = basin_start(c.model, schedule, b, start.omega, start.level, start.sample, orbit);
    } else {
      c.protocol = compile(plan.points[i].protocol, start.omega);
    }
    c.run = part.run;
    c.sample_rate = part.spec.sample_rate;
    c.settle_tolerance = part.spec.early_stop ? part.spec.early_stop_tolerance : 0.0;
    plan.spans.push_back(split(c.protocol, part.spec.windows_per_task));
    plan.first_task.push_back(plan.n_tasks);
    plan.n_tasks += plan.spans.back().size();
    plan.max_windows = std::max(plan.max_windows, c.protocol.windows.size());
    for (const Window& w : c.protocol.windows)
      plan.max_samples = std::max(plan.max_samples, std::size_t(std::ceil((w.t_end - w.t_begin) * c.sample_rate)) + 1);
    plan.total_duration += c.protocol.duration;
    plan.setups.push_back(std::move(c));
  }
  // The file's layout needs one window and one sample at least (a sweep of bisections alone
  // stores no window).
  plan.max_windows = std::max<std::size_t>(plan.max_windows, 1);
  plan.max_samples = std::max<std::size_t>(plan.max_samples, 1);
  return plan;
}

bool SweepPlan::has_bisection() const {
  return std::any_of(bisect.begin(), bisect.end(), [](const auto& b) { return b.has_value(); });
}

physics::State SweepPlan::start_state(std::size_t c) const {
  if (starts[c].state) return *starts[c].state;
  const physics::MotorSchedule schedule = setups[c].motor();
  return seed_state(setups[c].model, schedule, starts[c].seed, starts[c].omega, starts[c].perturbation, starts[c].kick);
}

}  // namespace ajx::sweep
