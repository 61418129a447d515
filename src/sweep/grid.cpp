#include "sweep/grid.hpp"

#include <fmt/format.h>

#include "physics/parameter_table.hpp"

namespace ajx::sweep {

bool is_grid_axis(std::string_view key) {
  if (key == kRampRateAxis) return true;
  const physics::ParameterInfo* p = physics::find_parameter(key);
  return p ? p->grid_axis : physics::find_alias(key) != nullptr;
}

std::vector<std::string> grid_axis_keys() {
  std::vector<std::string> keys = physics::grid_parameter_keys();
  keys.emplace_back(kRampRateAxis);
  return keys;
}

namespace {

// Sets axis a's value v on the point: a model parameter, or the rate of every ramp.
void set_axis(GridPoint& g, const GridAxis& axis, std::size_t index, double v, std::string_view source_name) {
  if (axis.key != kRampRateAxis) {
    physics::set_parameter(g.model.p, axis.key, v);
    return;
  }
  if (!(v > 0.0 && v <= 1e4))  // as protocol.segment[i].rate
    throw GridError(fmt::format("{}: key 'grid.ramp_rate[{}]': {} is out of range; allowed (0, 10000] rad/s²",
                                source_name, index, v));
  for (auto& seg : g.protocol)
    if (seg.kind == Segment::Kind::Ramp) seg.ramp.rate = v;
}

}  // namespace

std::vector<GridPoint> expand_grid(const physics::Model& base, const SweepSpec& spec, std::string_view source_name) {
  const std::vector<GridAxis>& grid = spec.grid;
  std::vector<GridPoint> points;
  std::vector<std::size_t> at(grid.size(), 0);
  for (;;) {
    GridPoint g{{}, base, spec.protocol};
    for (std::size_t a = 0; a < grid.size(); ++a) {
      const double v = grid[a].values[at[a]];
      g.values.push_back(v);
      set_axis(g, grid[a], at[a], v, source_name);
    }
    for (const physics::ParameterIssue& issue : physics::validate(g.model)) {
      std::string where;
      for (std::size_t a = 0; a < grid.size(); ++a) where += fmt::format(" grid.{}[{}]", grid[a].key, at[a]);
      throw GridError(fmt::format("{}: key '{}' at grid point{}: {} is out of range; allowed {}", source_name,
                                  issue.key, where.empty() ? " (no grid)" : where, issue.value, issue.allowed));
    }
    points.push_back(std::move(g));
    // Next index, the last axis fastest.
    std::size_t a = grid.size();
    while (a > 0 && ++at[a - 1] == grid[a - 1].values.size()) at[--a] = 0;
    if (a == 0) break;
  }
  return points;
}

}  // namespace ajx::sweep
