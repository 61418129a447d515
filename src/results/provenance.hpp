// What every file the program writes records about how it was made: the program, its version
// and git commit (read by CMake when it builds, src/results/source_commit.cmake), the command line, the configuration verbatim
// with its source and overrides, and the configuration in force as values (/resolved), under a
// format name and version that readers check.
#pragma once
#include <fmt/format.h>

#include <span>
#include <string>

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <variant>

#include "config/config.hpp"
#include "config/resolved.hpp"
#include "io/hdf5_file.hpp"

namespace ajx::results {

// The layout version of run and sweep files (root attribute format_version):
//   1  (no attribute) before the resolved configuration;
//   2  /resolved holds every model parameter, layer, integrator setting and the start as
//      attributes keyed "model.drive_radius", ...; root attribute `format` says "run" or "sweep".
//   3  lists of strings (overrides, names, labels, purposes, columns, axes, failures) stored as
//      1-D string attributes, one element per item, no longer joined; sweeps hold /classes.
//   4  the motor's work is the motor's with a clutch (tie clutch, pair couple): a run's
//      /trajectory/motor_work and a sweep's /windows/motor_power are at the rod (W_m), the
//      string's side moved to string_work, string_power; clutch_loss, clutch_power,
//      /trajectory/chi and tie_energy new; /trajectory/phi is the motor's phase.
//   5  sweeps with [bisect] chains hold /brackets (each bisection's bracket and every probe);
//      files without bisections are laid out as in format 4.
//      A sweep with basin chains holds /basins (results/basin_file.hpp), also since 5.
inline constexpr std::int64_t kFileFormatVersion = 5;

// A new output file written as "<path>.part" (its folder made if missing), renamed to <path> by
// commit(); destroyed uncommitted, it leaves nothing behind.
inline io::File create_output(const std::filesystem::path& path) {
  std::error_code ec;
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), ec);
  return io::File::create_temporary(path);
}

inline void write_format(io::File& f, std::string_view kind) {
  f.set_attribute("format", kind);
  f.set_attribute("format_version", kFileFormatVersion);
}

inline void write_resolved(io::Group& g, const config::CommonConfig& cfg) {
  for (const config::Setting& s : config::resolved_settings(cfg))
    std::visit([&](const auto& v) { g.set_attribute(s.key, v); }, s.value);
}

// The format version of a file this program reads, 1 when it has none; a newer one than this
// program writes, or one that is not a positive integer, is refused (newer: naming both).
inline std::int64_t checked_format_version(const io::File& f, const std::string& path) {
  if (!f.has_attribute("format_version")) return 1;
  if (f.attribute_type_class("format_version") != io::TypeClass::Integer || f.attribute_dims("format_version").size() > 1)
    throw std::runtime_error(fmt::format("{}: format_version is not an integer", path));
  const std::int64_t v = f.read_int64_attribute("format_version");
  if (v > kFileFormatVersion)
    throw std::runtime_error(fmt::format("{}: file format version {} is newer than this program reads ({}); "
                                         "use the astrojax that wrote it", path, v, kFileFormatVersion));
  if (v < 1) throw std::runtime_error(fmt::format("{}: file format version {} is not one (1 to {})", path, v, kFileFormatVersion));
  return v;
}

// The program's version and the git commit it was built from (set by CMake at configure time,
// in provenance.cpp only, so that a new commit recompiles one file).
std::string program_version();
std::string program_commit();         // 12 hex digits, or "unknown"
std::string program_commit_origin();  // where it was read: git, or the source archive

inline void write_provenance(io::File& f, const std::string& command_line, const config::CommonConfig& cfg) {
  f.set_attribute("program", "astrojax-explorer");
  f.set_attribute("version", program_version());
  f.set_attribute("git_commit", program_commit());
  f.set_attribute("command_line", command_line);
  auto config = f.write_string_dataset("config", cfg.source_text);
  config.set_attribute("source", cfg.source_name);
  config.set_attribute("overrides", std::span<const std::string>(cfg.overrides));
  io::Group resolved = f.create_group("resolved");
  write_resolved(resolved, cfg);
}

// What one run of a sweep (the first, or a resume) records of itself in /provenance: a
// resume's times go under resume_start_time and resume_wall_time beside the first run's.
struct SweepRunRecord {
  std::string command_line, host;
  int ranks = 0;
  bool resume = false;
  std::string started, ended;   // ISO 8601
  double wall = 0;              // [s]
  std::string farm_status;
  double tasks_per_second = 0;
  std::uint64_t bytes_to_workers = 0, bytes_from_workers = 0;  // farm messages, headers included
  double work_seconds = 0;           // summed over ranks: integration alone
  double master_result_seconds = 0;  // rank 0: journal, write (time in the farm's on_result)
  double master_cpu_seconds = 0;     // rank 0: CPU of the master's loop (0 on one rank with one thread)
  int threads = 1;                   // of rank 0 that integrate (parallel::FarmOptions::threads)
  double settle_seconds_skipped = 0; // [s] of settling not integrated, the orbit known (sim/settle_watch.hpp)
};

inline void write_run_record(io::Group& prov, const SweepRunRecord& r) {
  prov.set_attribute("program", "astrojax-explorer");
  prov.set_attribute("command_line", r.command_line);
  prov.set_attribute("ranks", r.ranks);
  prov.set_attribute("host", r.host);
  prov.set_attribute(r.resume ? "resume_start_time" : "start_time", r.started);
  prov.set_attribute("end_time", r.ended);
  prov.set_attribute(r.resume ? "resume_wall_time" : "wall_time", r.wall);
  prov.set_attribute("farm_status", r.farm_status);
  prov.set_attribute("tasks_per_second", r.tasks_per_second);
  prov.set_attribute("bytes_to_workers", r.bytes_to_workers);
  prov.set_attribute("bytes_from_workers", r.bytes_from_workers);
  prov.set_attribute("work_seconds", r.work_seconds);
  prov.set_attribute("master_result_seconds", r.master_result_seconds);
  prov.set_attribute("master_cpu_seconds", r.master_cpu_seconds);
  prov.set_attribute("threads", r.threads);
  prov.set_attribute("settle_seconds_skipped", r.settle_seconds_skipped);  // every run of the sweep, resumes included
  prov.set_attribute("version", program_version());
  prov.set_attribute("git_commit", program_commit());  // when built
}

}  // namespace ajx::results
