// What lets a sweep survive faults: the identity of a sweep in its journal (a resume must come
// from the same sweep file and overrides), and the disk-space check made before any work.
#pragma once
#include <sys/statvfs.h>

#include <algorithm>
#include <cstdio>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fmt/format.h>
#include <string>
#include <vector>

#include "results/resource_budget.hpp"
#include "config/config.hpp"
#include "io/journal.hpp"
#include "sweep/plan.hpp"
#include "sweep/task.hpp"

namespace ajx::results {

// A task's journal record: a kind byte, then for Ran the task's encoded result
// (sweep_result.hpp), for FailedWithoutOutput the reason (a task past its wall-clock bound),
// for NotRun nothing.
enum class RecordKind : std::uint8_t { Ran = 1, FailedWithoutOutput = 2, NotRun = 3 };

// The journal's first record (key -1): the sweep file verbatim, a NUL, the overrides.
inline constexpr std::int64_t kJournalIdentity = -1;
inline std::vector<std::byte> journal_identity(const config::SweepConfig& cfg) {
  const std::string s = cfg.source_text + '\0' + fmt::format("{}", fmt::join(cfg.overrides, "\n"));
  const auto* p = reinterpret_cast<const std::byte*>(s.data());
  return std::vector<std::byte>(p, p + s.size());
}

// Bytes a sweep may write at most: every window's samples (12 doubles per sample: t, ω_m, L1,
// T1, T2, mode, r1, r2) once uncompressed in the journal and once, at worst uncompressed, in
// the HDF5 file, plus the per-window statistics and per-task states (small beside them).
inline std::uint64_t sweep_bytes_bound(const std::vector<sweep::ChainSetup>& setups, std::size_t cap) {
  std::uint64_t windows = 0;
  for (const auto& c : setups) windows += c.protocol.windows.size();
  return 2 * windows * (std::uint64_t(cap) * 12 * 8 + 64 * 8);
}

// Refuses, before any work, a sweep whose file cannot fit on its file system.
inline void check_space(const config::SweepConfig& cfg, const std::filesystem::path& out,
                        const std::vector<sweep::ChainSetup>& setups, std::size_t cap) {
  std::filesystem::path dir = out.parent_path();  // the nearest that exists: made only once this passes
  std::error_code ec;
  while (!dir.empty() && !std::filesystem::exists(dir, ec)) dir = dir.parent_path();
  if (dir.empty()) dir = ".";
  struct statvfs fs;
  if (statvfs(dir.c_str(), &fs) != 0) return;  // an unreadable directory fails at create, with its reason
  const std::uint64_t free_bytes = std::uint64_t(fs.f_bavail) * fs.f_frsize;
  const std::uint64_t need = sweep_bytes_bound(setups, cap);
  if (need > free_bytes)
    throw config::ConfigError(fmt::format(
        "{}: key 'output.path': the sweep may write up to {:.1f} MB ({} and its journal), but {} has only {:.1f} MB "
        "free",
        cfg.source_name, double(need) / 1e6, out.string(), dir.string(), double(free_bytes) / 1e6));
}

// Memory of the busiest rank, refused before any work beyond the budget: rank 0 holds the plan
// (about 1 kB a chain, 128 B a window, 256 B a task) and, like every worker, one task's samples
// (12 doubles a sample) about three times over: as sampled, compressed, and in the message.
inline void check_sweep_memory(const config::SweepConfig& cfg, const sweep::SweepPlan& plan, double max_memory_mb) {
  double windows = 0;
  for (const auto& c : plan.setups) windows += double(c.protocol.windows.size());
  const double per_task = double(std::min<std::size_t>(std::size_t(cfg.windows_per_task), plan.max_windows));
  const double task_bytes = 3.0 * per_task * double(plan.max_samples) * 12 * 8;
  const double plan_bytes = 1024.0 * double(plan.chains()) + 128.0 * windows + 256.0 * double(plan.n_tasks);
  check_memory(cfg.source_name, cfg.hold ? "hold.sample_rate" : cfg.basin ? "basin.sample_rate" : "protocol.sample_rate",
               fmt::format("a task of {:.0f} windows of up to {} samples, with a plan of {} chains and {} tasks",
                           per_task, plan.max_samples, plan.chains(), plan.n_tasks),
               task_bytes + plan_bytes, memory_budget(max_memory_mb), max_memory_mb);
}

// A resume's journal must come from this sweep: its first record is the sweep file and overrides
// it was started with. One whose first record is damaged cannot be matched, and is refused with
// that reason rather than taken for another sweep's (a journal killed before its first record was
// whole holds no result: nothing is lost, and the resume writes it).
inline void check_journal_identity(const config::SweepConfig& cfg, const std::filesystem::path& journal,
                                   const io::JournalContents& c) {
  if (c.records.empty()) return;
  if (c.first_record_lost)
    throw config::ConfigError(fmt::format(
        "{}: key 'output.path': {}: its header record (the sweep file and overrides it was started with, from byte "
        "{}) is damaged, so its {} intact results cannot be matched to this sweep; start afresh with --force "
        "(it discards them)",
        cfg.source_name, journal.string(), c.damage.front().offset, c.records.size()));
  if (c.records.front().key != kJournalIdentity || c.records.front().payload != journal_identity(cfg))
    throw config::ConfigError(fmt::format(
        "{}: key 'output.path': {} was written by a different sweep file or overrides; resume it with the "
        "same ones, or start afresh with --force",
        cfg.source_name, journal.string()));
}

// What a journal's damage costs, in one sentence ("" when it has none): the results kept and
// discarded, where and why, and what runs again. Said alike by a resume and by verify.
inline std::string journal_damage_text(const io::JournalContents& c) {
  std::string header = c.damaged_magic ? "its file header (the first 8 bytes) is damaged; the records behind it are "
                                         "intact and kept" : "";
  if (c.damage.empty()) return header;
  std::vector<std::string> where;
  for (const io::JournalDamage& d : c.damage)
    where.push_back(fmt::format("{} at bytes {}-{}, {} record{}", d.reason, d.offset, d.offset + d.length, d.records,
                                d.records == 1 ? "" : "s"));
  // The header record lost with no result after it (killed while writing it) is no result.
  const std::size_t lost = c.records_lost() - (c.first_record_lost ? 1 : 0);
  const std::size_t kept = c.records.empty() ? 0 : c.records.size() - 1;
  return fmt::format("{}{}{} results kept, {} discarded ({}); {}", header, header.empty() ? "" : "; ", kept, lost,
                     fmt::join(where, "; "),
                     lost == 0 ? "nothing to run again" : lost == 1 ? "that task runs again" : "those tasks run again");
}

// What a resume lost to damage in its journal, on stderr.
inline void report_journal_damage(const std::filesystem::path& journal, const io::JournalContents& c) {
  const std::string text = journal_damage_text(c);
  if (!text.empty()) std::fprintf(stderr, "warning: %s: %s\n", journal.c_str(), text.c_str());
}

// Refuses to start afresh over an interrupted sweep's files: its finished tasks would be lost.
// `--resume` continues them, `--force` discards them.
inline void check_no_unfinished_sweep(const config::SweepConfig& cfg, const std::filesystem::path& part,
                                      const std::filesystem::path& journal) {
  std::vector<std::string> found;
  std::error_code ec;
  if (std::filesystem::exists(part, ec)) found.push_back(part.string());
  if (std::filesystem::exists(journal, ec)) {
    std::size_t results = 0;
    try {  // the first record is the sweep's identity, the others are results
      const std::size_t n = io::Journal::read(journal).records.size();
      results = n > 0 ? n - 1 : 0;
    } catch (const io::JournalError&) {
    }
    found.push_back(fmt::format("{} ({} finished task results)", journal.string(), results));
  }
  if (found.empty()) return;
  throw config::ConfigError(fmt::format(
      "{}: key 'output.path': an interrupted sweep is there: {}; continue it with --resume, or discard it and start "
      "afresh with --force",
      cfg.source_name, fmt::join(found, " and ")));
}

}  // namespace ajx::results
