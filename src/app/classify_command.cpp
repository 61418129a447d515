// astrojax classify: classify every window of a sweep file again from its stored samples,
// with other classifier settings, without integrating again.
#include <cmath>
#include <cstdio>
#include <fmt/format.h>
#include <string>
#include <utility>
#include <vector>

#include <filesystem>

#include "app/commands.hpp"
#include "app/output_paths.hpp"
#include "results/reclassify.hpp"
#include "results/sweep_file.hpp"

namespace ajx::app {

int classify_command(const ClassifyArgs& args) {
  sweep::ClassifierSettings settings;
  try {
    settings = sweep::parse_classifier_settings(args.settings);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "error: --set %s\n", e.what());
    return kExitBadInput;
  }
  const std::string used = fmt::format("{}", fmt::join(args.settings, "\n"));
  // The file to rewrite: a copy at -o, or the input itself when --force says so.
  std::string target = args.input;
  try {
    if (args.output.empty() && !args.force)
      throw config::ConfigError(fmt::format("{}: classify rewrites the file's classes; give -o COPY for a reclassified "
                                            "copy, or --force to rewrite it in place", args.input));
    if (!args.output.empty()) {
      check_output_path(args.input, "-o", args.output, {args.input}, {});
      check_not_overwriting(args.input, "-o", args.output, args.force);
      std::filesystem::copy_file(args.input, args.output, std::filesystem::copy_options::overwrite_existing);
      target = args.output;
    }
  } catch (const config::ConfigError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  } catch (const std::filesystem::filesystem_error& e) {
    std::fprintf(stderr, "error: %s: %s\n", args.input.c_str(), e.what());
    return kExitBadInput;
  }

  try {
    io::File f = io::File::open_rw(target);
    results::checked_format_version(f, target);
    const auto again = results::reclassify_windows(f, settings);
    const auto cls = f.read_int32s("windows/class");
    const auto cap = f.open_dataset("samples/t").dims().at(2);
    results::SweepFile out(std::move(f), cls.rows(), cls.cols(), cap, 0);
    long changed = 0;
    for (const results::ReclassifiedWindow& w : again) {
      changed += w.row.cls != w.old_class;
      out.write_rows(w.chain, w.window, std::span<const results::WindowRow>(&w.row, 1));
    }
    io::Group wg = out.file().open_group("windows");
    wg.set_attribute("classifier_settings", used.empty() ? std::string("defaults") : used);
    out.close();
    std::printf("classified %zu windows again in %s: %ld changed class\n", again.size(), target.c_str(), changed);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s: %s\n", args.input.c_str(), e.what());
    return kExitBadInput;
  }
  return 0;
}

}  // namespace ajx::app
