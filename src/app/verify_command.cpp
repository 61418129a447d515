// astrojax verify: checks a sweep's file, finished or partial, and reports what is damaged.
// The layout (/chains, the windows' and tasks' spans) is made again from the sweep file stored in
// /config and compared value by value; every dataset is read whole, so that a chunk whose
// checksum fails (Fletcher32 on every uncompressed chunk, the zlib Adler-32 of a deflated sample
// chunk) shows; a partial file's journal is read
// (every record has a CRC-32) and its tasks compared with the file's status.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "results/sweep_file.hpp"
#include "io/journal.hpp"
#include "sweep/plan.hpp"

namespace ajx::app {

namespace {

bool same_values(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!(a[i] == b[i] || (std::isnan(a[i]) && std::isnan(b[i])))) return false;
  return true;
}

// The layout datasets that the sweep file alone determines.
constexpr const char* kLayout[] = {"chains/grid_values", "chains/model",          "chains/group",
                                   "chains/variant",     "chains/start_seed",     "chains/start_omega", "chains/part",
                                   "windows/t_begin",    "windows/t_end",         "windows/omega_m_begin",
                                   "windows/omega_m_end", "windows/phi_begin", "windows/direction",    "windows/segment",
                                   "tasks/chain",        "tasks/index",           "tasks/t_begin",
                                   "tasks/t_end"};

// Each layout dataset of `f` against the same one made afresh from its /config.
void check_layout(const io::File& f, std::vector<std::string>& damaged) {
  const io::Dataset config = f.open_dataset("config");
  std::vector<std::string> overrides;
  const std::string joined = config.read_string_attribute("overrides");
  for (std::size_t a = 0, b; a < joined.size(); a = b + 1) {
    b = joined.find('\n', a);
    if (b == std::string::npos) b = joined.size();
    if (b > a) overrides.push_back(joined.substr(a, b - a));
  }
  const config::SweepConfig cfg =
      config::parse_sweep_config(config.read_string(), config.read_string_attribute("source"), overrides);
  const sweep::SweepPlan plan = config::make_plan(cfg);
  const std::filesystem::path ref_path =
      std::filesystem::temp_directory_path() / fmt::format("astrojax-verify-{}.h5", ::getpid());
  {
    results::SweepFile ref(io::File::create(ref_path), plan.chains(), plan.max_windows, plan.max_samples, plan.n_tasks);
    ref.create(cfg, plan);
    ref.close();
  }
  const io::File r = io::File::open_read(ref_path);
  for (const char* path : kLayout) {
    if (!r.exists(path)) continue;
    if (!f.exists(path)) {
      damaged.push_back(fmt::format("/{} is missing", path));
      continue;
    }
    io::Array<double> got;
    try {
      got = f.read_doubles(path);
    } catch (const io::Hdf5Error& e) {  // its checksum fails
      damaged.push_back(fmt::format("/{} cannot be read: {}", path, e.what()));
      continue;
    }
    const auto want = r.read_doubles(path);
    if (want.dims != got.dims || !same_values(want.data, got.data))
      damaged.push_back(fmt::format("/{} differs from what {} makes", path, cfg.source_name));
  }
  std::filesystem::remove(ref_path);
}

// Every result dataset read whole: a chunk whose checksum fails (Fletcher32, or a deflated
// chunk's Adler-32) or that cannot be decoded throws. Files from before the checksums: noted.
void check_results(const io::File& f, std::vector<std::string>& damaged, std::vector<std::string>& notes) {
  std::vector<std::string> paths{"windows/class", "windows/mode_fraction", "samples/count", "tasks/status",
                                 "tasks/steps", "tasks/final_state"};
  for (const auto& st : results::kStats) paths.push_back(std::string("windows/") + st[0]);
  // string_power and clutch_power since format 4
  const bool v4 = results::checked_format_version(f, "") >= 4;
  for (const auto& st : results::kPowers)
    if (v4 || f.exists(std::string("windows/") + st[0])) paths.push_back(std::string("windows/") + st[0]);
  for (const char* c : results::kSampleColumns) paths.push_back(std::string("samples/") + c);
  std::vector<std::string> unchecked;
  for (const std::string& p : paths) {
    try {
      if (!f.open_dataset(p).checksummed()) unchecked.push_back("/" + p);
      (void)f.read_doubles(p);
    } catch (const io::Hdf5Error& e) {
      damaged.push_back(fmt::format("/{} cannot be read: {}", p, e.what()));
    }
  }
  if (!unchecked.empty())
    notes.push_back(fmt::format("no checksum on {} (a file written before they had one): a changed value there "
                                "cannot be seen", fmt::join(unchecked, ", ")));
}

}  // namespace

int verify_command(const VerifyArgs& args) {
  std::vector<std::string> damaged, notes;
  try {
    const io::File f = io::File::open_read(args.input);
    results::checked_format_version(f, args.input);
    check_layout(f, damaged);
    check_results(f, damaged, notes);
    const auto status = results::read_task_statuses(f);
    std::size_t done = 0, never = 0;
    for (results::TaskStatus s : status) (s == results::TaskStatus::NeverRan ? never : done) += 1;
    notes.push_back(fmt::format("{} of {} tasks have a result, {} never ran", done, status.size(), never));
    const std::string in = args.input;
    const bool partial = in.size() > 5 && in.compare(in.size() - 5, 5, ".part") == 0;
    const std::string journal = partial ? in.substr(0, in.size() - 5) + ".journal" : in + ".journal";
    if (std::filesystem::exists(journal)) {
      const io::JournalContents j = io::Journal::read(journal);
      const std::size_t results = j.records.empty() ? 0 : j.records.size() - 1;
      notes.push_back(fmt::format("{}: {} results with valid checksums{}", journal, results,
                                  j.torn_tail ? ", then a record cut short or damaged (that task runs again)" : ""));
      for (std::size_t k = 1; k < j.records.size(); ++k) {
        const std::int64_t id = j.records[k].key;
        if (id < 0 || std::size_t(id) >= status.size()) damaged.push_back(fmt::format("{}: record {} names task {}", journal, k, id));
      }
    } else if (partial) {
      damaged.push_back(fmt::format("no journal {}: the results in the .part cannot be checked", journal));
    } else if (never > 0) {
      damaged.push_back(fmt::format("{} tasks never ran, but the file is not a .part", never));
    }
  } catch (const std::exception& e) {  // unreadable, or its /config no longer a valid sweep file
    damaged.push_back(e.what());
  }
  for (const std::string& n : notes) std::printf("  %s\n", n.c_str());
  for (const std::string& d : damaged) std::printf("  DAMAGED: %s\n", d.c_str());
  std::printf("%s  %s\n", damaged.empty() ? "ok" : "DAMAGED", args.input.c_str());
  return damaged.empty() ? 0 : kExitBadInput;
}

}  // namespace ajx::app
