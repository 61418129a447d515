#include "config/resolved.hpp"

#include <fmt/format.h>

#include "physics/parameter_table.hpp"

namespace ajx::config {

std::vector<Setting> resolved_settings(const CommonConfig& c) {
  std::vector<Setting> out;
  const auto add = [&](std::string key, std::variant<double, std::string> v) { out.push_back({std::move(key), std::move(v)}); };
  for (const physics::ParameterInfo& p : physics::kParameters) add(fmt::format("model.{}", p.key), c.model.p.*p.field);
  for (const physics::LayerInfo& l : physics::layer_table()) {
    if (l.kind == physics::LayerInfo::Kind::Number) add(fmt::format("layers.{}", l.key), c.model.layers.*l.number);
    else add(fmt::format("layers.{}", l.key), l.value(c.model.layers));
  }
  const sim::RunOptions& r = c.run;
  add("integrator.method", r.method);
  add("integrator.rtol", r.integ.tol.rtol);
  add("integrator.atol", r.integ.tol.atol);
  add("integrator.step", r.integ.h_fixed);
  if (r.guard_step_bound) add("integrator.max_step", std::string("auto"));
  else add("integrator.max_step", r.integ.h_max);
  add("integrator.event_samples", double(r.integ.event_samples));
  add("integrator.axes", std::string(r.axes == sim::Axes::Lab ? "lab" : r.axes == sim::Axes::Auto ? "auto" : "rotating"));
  add("integrator.projection_tol", r.projection_tol);
  add("integrator.max_events", double(r.max_events));
  add("integrator.rest_speed", r.rest_speed);
  add("integrator.chatter_switches", double(r.chatter_switches));
  add("integrator.chatter_window", r.chatter_window);
  add("integrator.omega_window", r.omega_window);
  add("initial.preset", c.initial.preset);
  if (!c.initial.orbit.empty()) add("initial.orbit", c.initial.orbit);
  add("initial.length_tolerance", c.initial.length_tolerance);
  return out;
}

}  // namespace ajx::config
