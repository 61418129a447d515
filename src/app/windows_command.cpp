// astrojax windows: every computed window of a sweep file as one CSV row, with the classifier's
// reason for its class. The reason is not stored in the file: each window is classified again
// from its stored samples with the file's own classifier settings, which gives the stored
// class back (the sweep classified the same rounded samples); a window where it does not
// (a file written by another version of the classifier) says so in `reclassified_class`.
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "app/output_paths.hpp"
#include "config/config.hpp"
#include "io/hdf5_file.hpp"
#include "results/provenance.hpp"
#include "results/reclassify.hpp"
#include "results/sweep_file.hpp"

namespace ajx::app {

namespace {

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l, sep);) out.push_back(l);
  return out;
}

std::string quoted(std::string s) {
  for (std::size_t i = 0; (i = s.find('"', i)) != std::string::npos; i += 2) s.insert(i, "\"");
  return "\"" + s + "\"";
}

std::string class_name(std::int32_t cls) {
  return cls < 0 ? std::string() : std::string(sweep::to_string(static_cast<sweep::OrbitClass>(cls)));
}

// The CSV of every computed window of the file at `path`.
std::string windows_csv(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(fmt::format("{}: no such file", path));
  const io::File f = io::File::open_read(path);
  results::checked_format_version(f, path);
  for (const char* need : {"windows/class", "windows/omega_m_begin", "samples/count"})
    if (!f.exists(need))
      throw std::runtime_error(fmt::format("{}: not a sweep file with stored samples (no /{})", path, need));
  sweep::ClassifierSettings settings;
  const io::Group wg = f.open_group("windows");
  if (wg.has_attribute("classifier_settings")) {
    const std::string used = wg.read_string_attribute("classifier_settings");
    if (used != "defaults") {
      std::vector<std::string> lines;
      for (const std::string& l : split(used, '\n'))
        if (!l.empty()) lines.push_back(l);
      settings = sweep::parse_classifier_settings(lines);
    }
  }
  std::vector<std::int32_t> group, variant;
  std::vector<std::string> groups, variants;
  if (f.exists("chains/group") && f.exists("chains/variant")) {
    group = f.read_int32s("chains/group").data;
    variant = f.read_int32s("chains/variant").data;
    groups = split(f.open_dataset("chains/group").read_string_attribute("names"), '\n');
    variants = split(f.open_dataset("chains/variant").read_string_attribute("names"), '\n');
  }
  const auto at = [](const std::vector<std::string>& names, const std::vector<std::int32_t>& index, std::size_t c) {
    return c < index.size() && index[c] >= 0 && std::size_t(index[c]) < names.size() ? names[std::size_t(index[c])]
                                                                                     : std::string();
  };
  const auto wb = f.read_doubles("windows/omega_m_begin"), we = f.read_doubles("windows/omega_m_end");
  const auto tb = f.read_doubles("windows/t_begin"), te = f.read_doubles("windows/t_end");
  const auto omega_ball = f.read_doubles("windows/omega_ball"), confidence = f.read_doubles("windows/confidence");
  const auto dir = f.read_int32s("windows/direction");
  std::string csv = "chain,group,variant,window,t_begin_s,t_end_s,omega_m_begin_rad_s,omega_m_end_rad_s,direction,"
                    "class,omega_ball_rad_s,confidence,reclassified_class,reason\n";
  for (const results::ReclassifiedWindow& w : results::reclassify_windows(f, settings)) {
    const std::size_t c = w.chain, k = w.window;
    const std::int32_t again = w.row.cls;
    csv += fmt::format("{},{},{},{},{:.9g},{:.9g},{:.9g},{:.9g},{},{},{:.9g},{:.6g},{},{}\n", c,
                       quoted(at(groups, group, c)), quoted(at(variants, variant, c)), k, tb(c, k), te(c, k), wb(c, k),
                       we(c, k), dir(c, k), class_name(w.old_class), omega_ball(c, k), confidence(c, k),
                       again == w.old_class ? "same" : class_name(again), quoted(w.reason));
  }
  return csv;
}

}  // namespace

int windows_command(const WindowsArgs& args) {
  std::string csv;
  try {
    if (args.output != "-") {
      check_output_path(args.input, "-o", args.output, {args.input}, {});
      check_not_overwriting(args.input, "-o", args.output, args.force);
    }
    csv = windows_csv(args.input);
  } catch (const std::exception& e) {  // a missing or foreign file, an output that exists
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  }
  if (args.output == "-") {
    std::fputs(csv.c_str(), stdout);
    return 0;
  }
  std::ofstream out(args.output);
  out << csv;
  if (!out) {
    std::fprintf(stderr, "error: cannot write %s\n", args.output.c_str());
    return kExitOutputFailed;
  }
  return 0;
}

}  // namespace ajx::app
