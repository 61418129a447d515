#include "app/output_paths.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>

#include "config/config.hpp"

namespace ajx::app {

namespace fs = std::filesystem;

namespace {

// Whether `a` and `b` name one file: the same inode when both exist, else the same normal form.
bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec) && !ec;
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

// The nearest ancestor of `p` that exists ("." for a bare relative name).
fs::path existing_ancestor(const fs::path& p) {
  fs::path dir = p.parent_path();
  std::error_code ec;
  while (!dir.empty() && !fs::exists(dir, ec)) dir = dir.parent_path();
  return dir.empty() ? fs::path(".") : dir;
}

// Whether a file can be made in `dir`: made and removed at once (access(2) says yes to root
// and knows nothing of read-only mounts).
std::string cannot_create_in(const fs::path& dir) {
  std::string probe = (dir / ".astrojax-probe-XXXXXX").string();
  const int fd = mkstemp(probe.data());
  if (fd < 0) return std::strerror(errno);
  close(fd);
  unlink(probe.c_str());
  return {};
}

}  // namespace

void check_output_path(std::string_view source, std::string_view key, const std::string& path,
                       const std::vector<std::string>& inputs, const std::vector<std::string>& siblings) {
  const auto refuse = [&](const std::string& why) {
    throw config::ConfigError(fmt::format("{}: key '{}': {}", source, key, why));
  };
  if (path.empty()) refuse("the output path is empty");
  if (path.back() == '/' || fs::path(path).filename() == "." || fs::path(path).filename() == "..")
    refuse(fmt::format("'{}' names a directory; give a file name, e.g. {}/out.h5", path,
                       path.substr(0, path.find_last_not_of('/') + 1)));
  std::error_code ec;
  if (fs::is_directory(path, ec)) refuse(fmt::format("'{}' is a directory; give a file name inside it", path));
  for (const std::string& s : siblings)
    if (fs::is_directory(path + s, ec))
      refuse(fmt::format("'{}{}' (written beside '{}') is a directory", path, s, path));
  for (const std::string& in : inputs)
    if (same_file(path, in)) refuse(fmt::format("'{}' is the input file {}; it would be overwritten", path, in));
  const fs::path dir = existing_ancestor(path);
  if (!fs::is_directory(dir, ec))
    refuse(fmt::format("cannot write '{}': '{}' is not a directory", path, dir.string()));
  if (const std::string why = cannot_create_in(dir); !why.empty())
    refuse(fmt::format("cannot write '{}': no file can be made in '{}' ({})", path, dir.string(), why));
}

void check_not_overwriting(std::string_view source, std::string_view key, const std::string& path, bool force) {
  std::error_code ec;
  if (!force && fs::exists(path, ec))
    throw config::ConfigError(fmt::format("{}: key '{}': '{}' exists; give --force to replace it, or another -o",
                                          source, key, path));
}

}  // namespace ajx::app
