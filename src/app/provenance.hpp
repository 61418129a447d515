// What every file the program writes records about how it was made: the program, its version
// and git commit (set by CMake at configure time), the command line, and the configuration
// verbatim with its source and overrides.
#pragma once
#include <fmt/format.h>

#include <string>

#include "config/config.hpp"
#include "io/hdf5_file.hpp"

namespace ajx::app {

inline void write_provenance(io::File& f, const std::string& command_line, const config::CommonConfig& cfg) {
  f.set_attribute("program", "astrojax-explorer");
  f.set_attribute("version", ASTROJAX_VERSION);
  f.set_attribute("git_commit", ASTROJAX_GIT_COMMIT);
  f.set_attribute("command_line", command_line);
  auto config = f.write_string_dataset("config", cfg.source_text);
  config.set_attribute("source", cfg.source_name);
  config.set_attribute("overrides", fmt::format("{}", fmt::join(cfg.overrides, "\n")));
}

}  // namespace ajx::app
