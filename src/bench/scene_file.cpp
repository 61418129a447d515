#include "bench/scene_file.hpp"

#include <filesystem>
#include <fmt/format.h>
#include <stdexcept>

#include "config/config.hpp"

namespace ajx::bench {

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides, double horizon) {
  const config::RunConfig c = config::load_run_config(path, overrides);
  Scene s;
  s.name = std::filesystem::path(path).stem().string();
  s.model = c.model;
  s.schedule = physics::MotorSchedule(c.model.p.drive_radius, c.schedule);
  s.run = c.run;
  s.horizon = horizon;
  try {
    s.initial = c.initial.preset == "hanging"
                    ? sim::hanging_at_rest(c.model, s.schedule)
                    : sim::explicit_state(c.model, s.schedule, c.initial.r1, c.initial.r2, c.initial.v1,
                                          c.initial.v2, c.initial.mode, 0.0, c.initial.length_tolerance,
                                          c.initial.tie_slip_rate);
  } catch (const std::invalid_argument& e) {
    throw config::ConfigError(fmt::format("{}: key 'initial': {}", c.source_name, e.what()));
  }
  return s;
}

}  // namespace ajx::bench
