// astrojax keys: every configuration key the reader accepts, from the key catalogue.
#include <cstdio>
#include <fmt/format.h>

#include "app/commands.hpp"
#include "config/key_catalogue.hpp"

namespace ajx::app {

int keys_command(bool markdown) {
  if (markdown) {
    std::fputs(config::key_reference_markdown().c_str(), stdout);
    return 0;
  }
  for (const config::KeyInfo& k : config::key_catalogue())
    std::fputs(fmt::format("{}.{}  ({}{}; allowed {}{})\n    {}\n", k.section, k.key, k.type,
                           k.unit.empty() ? "" : ", " + k.unit, k.allowed,
                           k.fallback.empty() ? "" : "; default " + k.fallback, k.doc)
                   .c_str(),
               stdout);
  return 0;
}

}  // namespace ajx::app
