// The windows of a sweep file classified again from their stored samples, with other
// classifier settings, without integrating again: `astrojax classify` writes them back,
// `astrojax thresholds --set classifier.NAME=...` reads its brackets from them, and
// `astrojax verify` compares them with what the file holds.
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "results/sweep_reader.hpp"
#include "results/sweep_result.hpp"
#include "sweep/orbit_classifier.hpp"

namespace ajx::results {

struct ReclassifiedWindow {
  std::size_t chain = 0, window = 0;
  std::int32_t old_class = -1;  // as the file has it
  WindowRow row;                // the new class and statistics
  std::string reason;           // the classifier's, one line
};

// Every computed window (class >= 0 with samples) in chain-major order. A window whose
// integration failed stays failed: its samples cannot say why.
std::vector<ReclassifiedWindow> reclassify_windows(const SweepReader& in, const sweep::ClassifierSettings& settings);

// The statistic of kStats called `name` in a row.
double row_stat(const WindowRow& row, std::string_view name);

struct ReclassifySummary {
  std::size_t windows = 0;  // classified again
  long changed = 0;         // of which changed class
};

// astrojax classify: `input` read and validated (a damaged one throws SweepFileError naming
// it, before anything is written), its windows classified again with `settings` (recorded as
// /windows@classifier_settings, `used` the "name=value" lines, empty for the defaults), and the
// result written to `output`, which may be `input` itself: through a temporary file beside it,
// renamed over `output` only when complete, removed on any failure.
ReclassifySummary reclassify_file(const std::filesystem::path& input, const std::filesystem::path& output,
                                  const sweep::ClassifierSettings& settings, const std::vector<std::string>& used);

}  // namespace ajx::results
