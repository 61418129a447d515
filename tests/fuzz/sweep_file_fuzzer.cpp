// libFuzzer target: the sweep-file parser and everything done with a sweep file before any
// work (the grid, the chains' protocols and their split into tasks). Any input must either
// pass or be rejected with config::ConfigError; any other exception, a crash, a sanitizer
// report, a hang or a runaway allocation is a bug. Built with clang by tests/fuzz/CMakeLists.txt.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "config/config.hpp"
#include "sweep/protocol.hpp"
#include "sweep/task.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const ajx::config::SweepConfig cfg = ajx::config::parse_sweep_config(text, "fuzz.toml");
    // The chains as astrojax sweep builds them (src/app/sweep_command.cpp): a grid point runs the
    // protocol; in the hold mode, every held ω_m is one step-and-hold segment.
    for (const auto& g : ajx::config::expand_grid(cfg)) {
      if (!cfg.hold) {
        (void)ajx::sweep::split(ajx::sweep::compile(g.protocol, cfg.start_omega), cfg.windows_per_task);
        continue;
      }
      for (double w : cfg.hold->omega) {
        const ajx::sweep::Segment held{ajx::sweep::Segment::Kind::Steps, {}, {w, w, 1, cfg.hold->settle, cfg.hold->measure, 1.0}};
        (void)ajx::sweep::split(ajx::sweep::compile({held}, w), cfg.windows_per_task);
      }
    }
  } catch (const ajx::config::ConfigError&) {
    // rejected with a message: the expected outcome for bad input
  }
  return 0;
}
