#include "results/reclassify.hpp"

#include <iterator>
#include <span>
#include <stdexcept>
#include <string>

#include "results/sweep_file.hpp"

namespace ajx::results {

std::vector<ReclassifiedWindow> reclassify_windows(const io::File& f, const sweep::ClassifierSettings& settings) {
  const auto cls = f.read_int32s("windows/class"), count = f.read_int32s("samples/count");
  const StoredModels models = read_chain_models(f);
  const auto t = f.read_doubles("samples/t"), om = f.read_doubles("samples/omega_m"), L1 = f.read_doubles("samples/L1");
  const auto T1 = f.read_doubles("samples/T1"), T2 = f.read_doubles("samples/T2"), mode = f.read_doubles("samples/mode");
  const auto r1 = f.read_doubles("samples/r1"), r2 = f.read_doubles("samples/r2");
  const std::size_t C = cls.rows(), W = cls.cols(), cap = t.dims.at(2);
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
    if (name == kStats[i][0]) return row.stats[i];
  throw std::logic_error("no window statistic named " + std::string(name));
}

}  // namespace ajx::results
