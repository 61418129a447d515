// A work-precision scene from a run file (sweeps/scenes/*.toml): its model, schedule, run
// options and initial state. Throws config::ConfigError naming the file and key.
#pragma once
#include <string>
#include <vector>

#include "bench/work_precision.hpp"

namespace ajx::bench {

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides, double horizon);

}  // namespace ajx::bench
