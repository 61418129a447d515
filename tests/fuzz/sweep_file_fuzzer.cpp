// libFuzzer target: the sweep-file parser and everything done with a sweep file before any
// work (the grid, the chains' protocols and their split into tasks). Any input must either
// pass or be rejected with config::ConfigError; any other exception, a crash, a sanitizer
// report, a hang or a runaway allocation is a bug. Built with clang by tests/fuzz/CMakeLists.txt.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "config/config.hpp"
#include "sweep/plan.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const ajx::config::SweepConfig cfg = ajx::config::parse_sweep_config(text, "fuzz.toml");
    // The chains exactly as astrojax sweep builds them, each split into tasks.
    (void)ajx::config::make_plan(cfg);
  } catch (const ajx::config::ConfigError&) {
    // rejected with a message: the expected outcome for bad input
  }
  return 0;
}
