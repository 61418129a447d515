// astrojax windows: every computed window of a sweep file as one CSV row, with the classifier's
// reason for its class. The reason is not stored in the file: each window is classified again
// from its stored samples with the file's own classifier settings, which gives the stored
// class back (the sweep classified the same rounded samples); a window where it does not
// (a file written by another version of the classifier) says so in `reclassified_class`.
#include <cstdio>
#include <fmt/format.h>
#include <fstream>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "app/output_paths.hpp"
#include "config/config.hpp"
#include "config/text.hpp"
#include "results/reclassify.hpp"
#include "results/sweep_reader.hpp"

namespace ajx::app {

namespace {

std::string quoted(std::string s) {
  for (std::size_t i = 0; (i = s.find('"', i)) != std::string::npos; i += 2) s.insert(i, "\"");
  return "\"" + s + "\"";
}

std::string class_name(std::int32_t cls) {
  return cls < 0 ? std::string() : std::string(sweep::to_string(static_cast<sweep::OrbitClass>(cls)));
}

// The CSV of every computed window of the file at `path`, read through the one reader (a
// damaged file, or one without samples, throws SweepFileError naming it).
std::string windows_csv(const std::string& path) {
  const results::SweepReader in(path);
  const sweep::ClassifierSettings settings = sweep::parse_classifier_settings(in.classifier_settings());
  const auto name_of = [](const results::NameList& list, std::size_t c) {
    return c < list.of_chain.size() ? list.names[std::size_t(list.of_chain[c])] : std::string();
  };
  const auto &wb = in.omega_m_begin(), &we = in.omega_m_end(), &tb = in.t_begin(), &te = in.t_end();
  const auto &omega_ball = in.stat("omega_ball"), &confidence = in.stat("confidence");
  const auto& dir = in.direction();
  std::string csv = "chain,group,variant,window,t_begin_s,t_end_s,omega_m_begin_rad_s,omega_m_end_rad_s,direction,"
                    "class,omega_ball_rad_s,confidence,reclassified_class,reason\n";
  for (const results::ReclassifiedWindow& w : results::reclassify_windows(in, settings)) {
    const std::size_t c = w.chain, k = w.window;
    const std::int32_t again = w.row.cls;
    csv += fmt::format("{},{},{},{},{:.9g},{:.9g},{:.9g},{:.9g},{},{},{:.9g},{:.6g},{},{}\n", c,
                       quoted(name_of(in.groups(), c)), quoted(name_of(in.variants(), c)), k, tb(c, k), te(c, k),
                       wb(c, k), we(c, k), dir(c, k), class_name(w.old_class), omega_ball(c, k), confidence(c, k),
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
    std::fprintf(stderr, "error: %s\n", config::printable(e.what()).c_str());
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
