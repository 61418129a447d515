#include "results/verify.hpp"

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>
#include <sstream>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "io/journal.hpp"
#include "results/reclassify.hpp"
#include "results/sweep_file.hpp"
#include "results/sweep_reader.hpp"
#include "results/sweep_recovery.hpp"
#include "sweep/orbit_classes.hpp"
#include "sweep/plan.hpp"

namespace ajx::results {

namespace {

// Equal bit for bit, NaN equal to NaN.
bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b)); }

// The layout datasets that the sweep file alone determines.
constexpr const char* kLayout[] = {"chains/grid_values", "chains/model",      "chains/group",      "chains/variant",
                                   "chains/start_seed",  "chains/start_omega", "chains/part",      "chains/hold_omega",
                                   "chains/seed",        "chains/perturbation", "windows/t_begin", "windows/t_end",
                                   "windows/omega_m_begin", "windows/omega_m_end", "windows/phi_begin",
                                   "windows/direction",  "windows/segment",   "tasks/chain",       "tasks/index",
                                   "tasks/t_begin",      "tasks/t_end",
                                   "basins/chain", "basins/level", "basins/sample", "basins/start",
                                   "basins/levels/part", "basins/levels/omega_m", "basins/levels/first",
                                   "basins/levels/samples", "basins/levels/family"};

// "[c, k]" of element i of a dims array.
std::string at(const io::Dims& d, std::size_t i) {
  std::vector<std::size_t> idx(d.size());
  for (std::size_t a = d.size(); a-- > 0;) idx[a] = i % d[a], i /= d[a];
  return fmt::format("[{}]", fmt::join(idx, ", "));
}

std::string quoted(const std::vector<std::string>& v) {
  std::vector<std::string> out;
  for (const std::string& s : v) out.push_back("'" + s + "'");  // escaped where printed
  return fmt::format("{}", fmt::join(out, ", "));
}

// The configuration stored in /config, read without the validating reader (whose first
// problem may lie elsewhere): the layout can be checked against it all the same.
config::SweepConfig stored_config(const io::File& f) {
  const io::Dataset config = f.open_dataset("config");
  std::vector<std::string> overrides;
  if (!config.attribute_dims("overrides").empty()) {
    overrides = config.read_strings_attribute("overrides");
  } else {
    std::stringstream joined(config.read_string_attribute("overrides"));
    for (std::string line; std::getline(joined, line);)
      if (!line.empty()) overrides.push_back(line);
  }
  return config::parse_sweep_config(config.read_string(), config.read_string_attribute("source"), overrides);
}

// Each layout dataset of `f` against the same made afresh from its /config, and, when the
// file opened through the reader (`in`), its names and labels too.
void check_layout(const io::File& f, const SweepReader* in, std::vector<std::string>& damaged) {
  config::SweepConfig cfg;
  try {
    cfg = stored_config(f);
  } catch (const std::exception& e) {
    if (!in) return;  // the reader said what is wrong
    throw SweepFileError(in->path(), "config", e.what());
  }
  const sweep::SweepPlan plan = config::make_plan(cfg);
  const std::filesystem::path ref_path =
      std::filesystem::temp_directory_path() / fmt::format("astrojax-verify-{}.h5", ::getpid());
  struct Remove {
    std::filesystem::path p;
    ~Remove() {
      std::error_code ec;
      std::filesystem::remove(p, ec);
    }
  } remove{ref_path};
  {
    SweepFile ref(io::File::create(ref_path), plan.chains(), plan.max_windows, plan.max_samples, plan.n_tasks);
    ref.create(cfg, plan);
    ref.close();
  }
  const SweepReader ref(ref_path);
  const io::File& r = ref.file();
  for (const char* path : kLayout) {
    if (!r.exists(path) && !f.exists(path)) continue;
    if (!r.exists(path) || !f.exists(path)) {
      damaged.push_back(fmt::format("/{} is {} but /config ({}) makes it{}", path, f.exists(path) ? "there" : "missing",
                                    cfg.source_name, r.exists(path) ? "" : " not"));
      continue;
    }
    io::Array<double> got;
    try {
      got = f.read_doubles(path);
    } catch (const io::Hdf5Error& e) {
      if (!in) continue;  // the reader said so
      damaged.push_back(fmt::format("/{}: cannot be read: {}", path, e.what()));
      continue;
    }
    const auto want = r.read_doubles(path);
    if (want.dims != got.dims) {
      damaged.push_back(fmt::format("/{}: shape [{}], /config ({}) makes [{}]", path, fmt::join(got.dims, ", "),
                                    cfg.source_name, fmt::join(want.dims, ", ")));
      continue;
    }
    for (std::size_t i = 0; i < want.data.size(); ++i)
      if (!same(want.data[i], got.data[i])) {
        damaged.push_back(fmt::format("/{} at {}: {} where /config ({}) makes {}", path, at(got.dims, i), got.data[i],
                                      cfg.source_name, want.data[i]));
        break;
      }
  }
  if (!in) return;
  const auto names = [&](const char* what, const std::vector<std::string>& got, const std::vector<std::string>& want) {
    if (got != want)
      damaged.push_back(fmt::format("/{}: {} where /config ({}) makes {}", what, quoted(got), cfg.source_name, quoted(want)));
  };
  names("chains@axes", in->axes(), ref.axes());
  names("chains/model@columns", in->models().present, ref.models().present);
  names("chains/group@names", in->groups().names, ref.groups().names);
  names("chains/group@purposes", in->groups().texts, ref.groups().texts);
  names("chains/variant@names", in->variants().names, ref.variants().names);
  names("chains/variant@labels", in->variants().texts, ref.variants().texts);
  names("chains/start_seed@names", in->start_seeds().names, ref.start_seeds().names);
}

// Every computed window classified again from its samples, against what /windows holds.
void check_classes(const SweepReader& in, std::vector<std::string>& damaged) {
  const sweep::ClassifierSettings settings = sweep::parse_classifier_settings(in.classifier_settings());
  std::size_t differ = 0;
  std::string first;
  const io::Dims cw{in.chains(), in.windows()};
  for (const ReclassifiedWindow& w : reclassify_windows(in, settings)) {
    const std::size_t i = w.chain * in.windows() + w.window;
    std::string what;
    if (w.row.cls != w.old_class)
      what = fmt::format("/windows/class at {}: {}, but /samples at {} give {}", at(cw, i), w.old_class, at(cw, i), w.row.cls);
    for (std::size_t k = 0; k < kNumStats && what.empty(); ++k)
      if (!same(in.stat(kStats[k].name).data[i], w.row.stats[k]))
        what = fmt::format("/windows/{} at {}: {}, but /samples at {} give {}", kStats[k].name, at(cw, i),
                           in.stat(kStats[k].name).data[i], at(cw, i), w.row.stats[k]);
    for (std::size_t m = 0; m < kNumModes && what.empty(); ++m)
      if (!same(in.mode_fraction().data[i * kNumModes + m], w.row.mode_fraction[m]))
        what = fmt::format("/windows/mode_fraction at [{}, {}, {}]: {}, but /samples at {} give {}", w.chain, w.window, m,
                           in.mode_fraction().data[i * kNumModes + m], at(cw, i), w.row.mode_fraction[m]);
    if (what.empty()) continue;
    if (differ++ == 0) first = what;
  }
  if (differ == 0) return;
  const std::string with = in.classifier_settings().empty()
                               ? std::string("the default classifier settings")
                               : fmt::format("the settings {}", fmt::join(in.classifier_settings(), ", "));
  damaged.push_back(fmt::format("{}{}, classified with {} (/windows@classifier_settings)", first,
                                differ == 1 ? "" : fmt::format(" (and {} more windows whose /windows row differs from "
                                                               "what their samples give)", differ - 1), with));
}

// Format 3: /classes as this program declares them, descriptions and colours too (the
// analysis draws with them).
void check_class_table(const SweepReader& in, std::vector<std::string>& damaged) {
  if (in.format_version() < 3) return;
  const auto description = in.file().open_dataset("classes/description").read_strings();
  const auto colour = in.file().open_dataset("classes/colour").read_strings();
  for (std::size_t k = 0; k < sweep::kNumOrbitClasses; ++k) {
    if (description[k] != sweep::kOrbitClasses[k].description)
      damaged.push_back(fmt::format("/classes/description at [{}]: '{}', not this program's", k, description[k]));
    if (colour[k] != sweep::kOrbitClasses[k].colour)
      damaged.push_back(fmt::format("/classes/colour at [{}]: '{}', this program's is '{}'", k, colour[k],
                                    sweep::kOrbitClasses[k].colour));
  }
}

// Datasets written before the checksums: a changed value there cannot be seen.
void note_unchecked(const SweepReader& in, std::vector<std::string>& notes) {
  std::vector<std::string> paths{"windows/class", "windows/mode_fraction", "samples/count", "tasks/status",
                                 "tasks/steps", "tasks/final_state"};
  for (const auto& st : kStats) paths.push_back(std::string("windows/") + st.name);
  for (const auto& st : kPowers) paths.push_back(std::string("windows/") + st.name);
  for (const char* c : kSampleColumns) paths.push_back(std::string("samples/") + c);
  std::vector<std::string> unchecked;
  for (const std::string& p : paths)
    if (in.file().exists(p) && !in.file().open_dataset(p).checksummed()) unchecked.push_back("/" + p);
  if (!unchecked.empty())
    notes.push_back(fmt::format("no checksum on {} (a file written before they had one): a changed value there "
                                "cannot be seen", fmt::join(unchecked, ", ")));
}

// The tasks' status, and a partial file's journal.
void check_tasks(const SweepReader& in, const std::string& path, VerifyReport& rep) {
  const auto& status = in.status();
  std::size_t done = 0, never = 0;
  for (TaskStatus s : status) (s == TaskStatus::NeverRan ? never : done) += 1;
  rep.notes.push_back(fmt::format("{} of {} tasks have a result, {} never ran", done, status.size(), never));
  const bool partial = path.size() > 5 && path.compare(path.size() - 5, 5, ".part") == 0;
  const std::string journal = partial ? path.substr(0, path.size() - 5) + ".journal" : path + ".journal";
  if (std::filesystem::exists(journal)) {
    const io::JournalContents j = io::Journal::read(journal);
    const std::size_t results = j.records.empty() ? 0 : j.records.size() - 1;
    const std::string damage = journal_damage_text(j);
    rep.notes.push_back(damage.empty() ? fmt::format("{}: {} results with valid checksums", journal, results)
                                       : fmt::format("{}: {}", journal, damage));
    for (std::size_t k = 1; k < j.records.size(); ++k) {
      const std::int64_t id = j.records[k].key;
      if (id < 0 || std::size_t(id) >= status.size())
        rep.damaged.push_back(fmt::format("{}: record {} names task {}", journal, k, id));
    }
  } else if (partial) {
    rep.damaged.push_back(fmt::format("no journal {}: the results in the .part cannot be checked", journal));
  } else if (never > 0) {
    rep.damaged.push_back(fmt::format("/tasks/status: {} tasks never ran, but the file is not a .part", never));
  }
}

}  // namespace

VerifyReport verify_sweep_file(const std::string& path) {
  VerifyReport rep;
  const auto report = [&](const SweepFileError& e) {
    rep.damaged.push_back(e.dataset().empty() ? e.problem() : fmt::format("/{}: {}", e.dataset(), e.problem()));
  };
  std::optional<SweepReader> in;
  try {
    in.emplace(path);
  } catch (const SweepFileError& e) {
    report(e);
  }
  try {
    const io::File f = io::File::open_read(path);
    check_layout(f, in ? &*in : nullptr, rep.damaged);  // what a checksum cannot see
    if (in) {
      note_unchecked(*in, rep.notes);
      check_class_table(*in, rep.damaged);
      check_classes(*in, rep.damaged);
      check_tasks(*in, path, rep);
    }
  } catch (const SweepFileError& e) {
    report(e);
  } catch (const std::exception& e) {  // unreadable, its /config no longer makes a sweep, the journal, ...
    if (in || rep.damaged.empty()) rep.damaged.push_back(e.what());
  }
  return rep;
}

}  // namespace ajx::results
