// The windows of a sweep file classified again from their stored samples, with other
// classifier settings, without integrating again: `astrojax classify` writes them back,
// `astrojax thresholds --set classifier.NAME=...` reads its brackets from them.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "io/hdf5_file.hpp"
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
std::vector<ReclassifiedWindow> reclassify_windows(const io::File& f, const sweep::ClassifierSettings& settings);

// The statistic of kStats called `name` in a row.
double row_stat(const WindowRow& row, std::string_view name);

}  // namespace ajx::results
