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
#include "app/sweep_file.hpp"

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
    checked_format_version(f, target);
    const auto cls = f.read_int32s("windows/class"), count = f.read_int32s("samples/count");
    const StoredModels models = read_chain_models(f);
    const auto t = f.read_doubles("samples/t"), om = f.read_doubles("samples/omega_m"), L1 = f.read_doubles("samples/L1");
    const auto T1 = f.read_doubles("samples/T1"), T2 = f.read_doubles("samples/T2"), mode = f.read_doubles("samples/mode");
    const auto r1 = f.read_doubles("samples/r1"), r2 = f.read_doubles("samples/r2");
    const std::size_t C = cls.rows(), W = cls.cols(), cap = t.dims.at(2);
    SweepFile out(std::move(f), C, W, cap, 0);
    long changed = 0, total = 0;
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
        // A window the integration failed in stays failed: the samples cannot say why.
        w.failed = cls(c, k) == static_cast<std::int32_t>(sweep::OrbitClass::Failed);
        w.failure = "the integration failed (see /tasks)";
        const sweep::OrbitClassification r = sweep::classify_orbit(w, scales, settings);
        changed += static_cast<std::int32_t>(r.cls) != cls(c, k);
        ++total;
        const WindowRow row = window_row(r);
        out.write_rows(c, k, std::span<const WindowRow>(&row, 1));
      }
    }
    io::Group wg = out.file().open_group("windows");
    wg.set_attribute("classifier_settings", used.empty() ? std::string("defaults") : used);
    out.close();
    std::printf("classified %ld windows again in %s: %ld changed class\n", total, target.c_str(), changed);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s: %s\n", args.input.c_str(), e.what());
    return kExitBadInput;
  }
  return 0;
}

}  // namespace ajx::app
