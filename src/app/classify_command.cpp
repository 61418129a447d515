// astrojax classify: classify every window of a sweep file again from its stored samples,
// with other classifier settings, without integrating again (results/reclassify.hpp). A
// damaged input is refused before anything is written; the copy (or the file, with --force)
// is replaced only when complete.
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <string>

#include "app/commands.hpp"
#include "app/output_paths.hpp"
#include "config/text.hpp"
#include "results/reclassify.hpp"

namespace ajx::app {

int classify_command(const ClassifyArgs& args) {
  sweep::ClassifierSettings settings;
  try {
    settings = sweep::parse_classifier_settings(args.settings);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "error: --set %s\n", e.what());
    return kExitBadInput;
  }
  // The file to write: a copy at -o, or the input itself when --force says so.
  std::string target = args.input;
  try {
    if (args.output.empty() && !args.force)
      throw config::ConfigError(fmt::format("{}: classify rewrites the file's classes; give -o COPY for a reclassified "
                                            "copy, or --force to rewrite it in place", args.input));
    if (!args.output.empty()) {
      check_output_path(args.input, "-o", args.output, {args.input}, {});
      check_not_overwriting(args.input, "-o", args.output, args.force);
      target = args.output;
    }
    if (!std::filesystem::is_regular_file(args.input))
      throw config::ConfigError(fmt::format("{}: no such file", args.input));
  } catch (const config::ConfigError& e) {
    std::fprintf(stderr, "error: %s\n", config::printable(e.what()).c_str());
    return kExitBadInput;
  }
  try {
    const results::ReclassifySummary s = results::reclassify_file(args.input, target, settings, args.settings);
    std::printf("classified %zu windows again in %s: %ld changed class\n", s.windows, target.c_str(), s.changed);
  } catch (const results::SweepFileError& e) {
    std::fprintf(stderr, "error: %s\n", config::printable(e.what()).c_str());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s: %s\n", args.input.c_str(), config::printable(e.what()).c_str());
    return kExitBadInput;
  }
  return 0;
}

}  // namespace ajx::app
