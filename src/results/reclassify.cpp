#include "results/reclassify.hpp"

#include "results/basin_file.hpp"

#include <unistd.h>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <iterator>
#include <span>
#include <stdexcept>
#include <string>

#include "results/sweep_file.hpp"

namespace ajx::results {

std::vector<ReclassifiedWindow> reclassify_windows(const SweepReader& in, const sweep::ClassifierSettings& settings) {
  const auto& cls = in.classes();
  const auto& count = in.count();
  const StoredModels& models = in.models();
  const auto t = in.samples("t"), om = in.samples("omega_m"), L1 = in.samples("L1");
  const auto T1 = in.samples("T1"), T2 = in.samples("T2"), mode = in.samples("mode");
  const auto r1 = in.samples("r1"), r2 = in.samples("r2");
  const std::size_t C = in.chains(), W = in.windows(), cap = in.samples_per_window();
  std::vector<ReclassifiedWindow> out;
  for (std::size_t c = 0; c < C; ++c) {
    const sweep::OrbitScales scales = sweep::orbit_scales(models.chains[c]);
    for (std::size_t k = 0; k < W; ++k) {
      const auto n = std::size_t(count(c, k));
      if (cls(c, k) < 0 || n == 0) continue;  // never computed
      const std::size_t o = (c * W + k) * cap;
      std::vector<int> modes(n);
      for (std::size_t i = 0; i < n; ++i) modes[i] = int(mode.data[o + i]);
      sweep::OrbitWindow w;
      w.t = std::span<const double>(&t.data[o], n);
      w.omega_m = std::span<const double>(&om.data[o], n);
      w.r1 = std::span<const double>(&r1.data[3 * o], 3 * n);
      w.r2 = std::span<const double>(&r2.data[3 * o], 3 * n);
      w.L1 = std::span<const double>(&L1.data[o], n);
      w.T1 = std::span<const double>(&T1.data[o], n);
      w.T2 = std::span<const double>(&T2.data[o], n);
      w.mode = modes;
      w.failed = cls(c, k) == static_cast<std::int32_t>(sweep::OrbitClass::Failed);
      w.failure = "the integration failed (see /tasks)";
      const sweep::OrbitClassification found = sweep::classify_orbit(w, scales, settings);
      out.push_back({c, k, cls(c, k), window_row(found), found.reason});
    }
  }
  return out;
}

double row_stat(const WindowRow& row, std::string_view name) {
  for (std::size_t i = 0; i < kNumStats; ++i)
    if (name == kStats[i].name) return row.stats[i];
  throw std::logic_error("no window statistic named " + std::string(name));
}

ReclassifySummary reclassify_file(const std::filesystem::path& input, const std::filesystem::path& output,
                                  const sweep::ClassifierSettings& settings, const std::vector<std::string>& used) {
  namespace fs = std::filesystem;
  ReclassifySummary summary;
  std::vector<ReclassifiedWindow> again;
  std::size_t C = 0, W = 0, cap = 0;
  {
    const SweepReader in(input);  // validated: a damaged input stops here, nothing written
    again = reclassify_windows(in, settings);
    C = in.chains(), W = in.windows(), cap = in.samples_per_window();
  }
  const fs::path tmp = output.parent_path() / fmt::format(".{}.classify-{}", output.filename().string(), ::getpid());
  try {
    fs::copy_file(input, tmp, fs::copy_options::overwrite_existing);
    SweepFile out(io::File::open_rw(tmp), C, W, cap, 0);
    for (const ReclassifiedWindow& w : again) {
      summary.changed += w.row.cls != w.old_class;
      out.write_rows(w.chain, w.window, std::span<const WindowRow>(&w.row, 1));
    }
    io::Group wg = out.file().open_group("windows");
    wg.set_attribute("classifier_settings", used.empty() ? std::string("defaults") : fmt::format("{}", fmt::join(used, "\n")));
    write_basin_results(out.file());  // the basins' classes and fractions follow the windows'
    out.close();
    fs::rename(tmp, output);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  summary.windows = again.size();
  return summary;
}

}  // namespace ajx::results
