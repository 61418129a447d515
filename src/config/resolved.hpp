// The configuration in force, as values: every model parameter and layer (from the parameter
// table), every integrator setting and the start, keyed as in a TOML file ("model.drive_radius",
// "layers.tie", "integrator.rtol"). Every output file stores it, so that a reader needs neither
// the TOML text nor this program to know what ran.
#pragma once
#include <string>
#include <variant>
#include <vector>

#include "config/config.hpp"

namespace ajx::config {

struct Setting {
  std::string key;
  std::variant<double, std::string> value;  // a number in SI units, or a word as written in TOML
};

std::vector<Setting> resolved_settings(const CommonConfig& c);

}  // namespace ajx::config
