// astrojax verify: checks a sweep's file, finished or partial, and reports what is damaged,
// naming the dataset and the index (results/verify.hpp says what is checked and how).
#include <cstdio>
#include <string>

#include "app/commands.hpp"
#include "config/text.hpp"
#include "results/verify.hpp"

namespace ajx::app {

int verify_command(const VerifyArgs& args) {
  const results::VerifyReport rep = results::verify_sweep_file(args.input);
  for (const std::string& n : rep.notes) std::printf("  %s\n", config::printable(n).c_str());
  for (const std::string& d : rep.damaged) std::printf("  DAMAGED: %s\n", config::printable(d).c_str());
  std::printf("%s  %s\n", rep.damaged.empty() ? "ok" : "DAMAGED", config::printable(args.input).c_str());
  return rep.damaged.empty() ? 0 : kExitBadInput;
}

}  // namespace ajx::app
