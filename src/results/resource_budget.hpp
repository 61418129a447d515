// What a command will need, known before it starts: memory against a budget (--max-memory, or
// half the machine's memory) and bytes of output against the free space where they go. A plan
// that cannot fit is refused with exit 2 and the numbers, instead of dying of bad_alloc later.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>

namespace ajx::results {

// Bytes of memory one process may plan for: max_memory_mb when > 0, else half the physical
// memory of the machine.
double memory_budget(double max_memory_mb);

// Free bytes on the file system where `path` will be made (its nearest existing directory);
// infinity when that cannot be told.
double free_bytes_for(const std::string& path);

// Refuses (config::ConfigError naming `source` and `key`) `what` needing `bytes` of memory
// beyond `budget`.
void check_memory(std::string_view source, std::string_view key, std::string_view what, double bytes, double budget,
                  double max_memory_mb);

}  // namespace ajx::results
