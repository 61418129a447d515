#include "results/resource_budget.hpp"

#include <sys/statvfs.h>
#include <unistd.h>

#include <filesystem>
#include <fmt/format.h>
#include <limits>

#include "config/config.hpp"

namespace ajx::results {

double memory_budget(double max_memory_mb) {
  if (max_memory_mb > 0) return max_memory_mb * 1e6;
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return std::numeric_limits<double>::infinity();
  return 0.5 * double(pages) * double(page);
}

double free_bytes_for(const std::string& path) {
  std::filesystem::path dir = std::filesystem::path(path).parent_path();
  std::error_code ec;
  while (!dir.empty() && !std::filesystem::exists(dir, ec)) dir = dir.parent_path();
  if (dir.empty()) dir = ".";
  struct statvfs fs;
  if (statvfs(dir.c_str(), &fs) != 0) return std::numeric_limits<double>::infinity();
  return double(fs.f_bavail) * double(fs.f_frsize);
}

void check_memory(std::string_view source, std::string_view key, std::string_view what, double bytes, double budget,
                  double max_memory_mb) {
  if (bytes <= budget) return;
  throw config::ConfigError(fmt::format(
      "{}: key '{}': {} needs {:.4g} MB of memory, beyond the budget of {:.4g} MB ({})", source, key, what, bytes / 1e6,
      budget / 1e6, max_memory_mb > 0 ? "--max-memory" : "half the machine's memory; --max-memory sets another"));
}

}  // namespace ajx::results
