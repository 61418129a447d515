// Checks made on an output path before any work, so that a run or a sweep never computes
// something it cannot store, never writes over its own input and never leaves a half-made
// directory tree behind a refused command.
#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace ajx::app {

// Refuses (config::ConfigError naming `source` and `key`) an output `path` that is empty, ends
// in '/', names a directory, is one of `inputs`, or whose directory cannot be written (the
// nearest existing ancestor must be a directory where a file can be made). `siblings` are the
// suffixes of the files written beside it (".part", ".journal"): none may be a directory.
// Makes nothing: the caller creates the missing directories once every check has passed.
void check_output_path(std::string_view source, std::string_view key, const std::string& path,
                       const std::vector<std::string>& inputs, const std::vector<std::string>& siblings);

// Refuses (config::ConfigError) an output `path` that exists already, unless `force`: a file
// made earlier is never replaced by accident.
void check_not_overwriting(std::string_view source, std::string_view key, const std::string& path, bool force);

}  // namespace ajx::app
