// An append-only journal of opaque records, the commit log beside a file that a killed process
// may leave half-written (an HDF5 file killed between two flushes can be unreadable).
// Knows nothing of physics or HDF5.
//
// Layout: an 8-byte magic "AJXJRNL1", then records, each
//   u32 magic 0x4a524543 | u32 CRC-32 of the rest | i64 key | u64 length | length payload bytes
// (little-endian, the architecture's own). A record is committed once append() returns: its
// bytes are in the kernel, so they survive the death of the process (kill -9, a job killed
// at its time limit), though not a crash of the machine before the kernel writes them. A record
// cut short or failing its CRC ends the journal: it and anything after it are ignored, and
// open_append() truncates them away. The writer holds an exclusive flock on the journal:
// create() and open_append() of a journal another process writes throw JournalError.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace ajx::io {

class JournalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct JournalRecord {
  std::int64_t key = 0;
  std::vector<std::byte> payload;
};

// What read() found: the committed records, and whether a torn tail was dropped.
struct JournalContents {
  std::vector<JournalRecord> records;
  std::uint64_t valid_bytes = 0;  // length of the committed prefix
  bool torn_tail = false;         // bytes after it (an append cut short)
};

class Journal {
 public:
  Journal() = default;
  Journal(Journal&& o) noexcept;
  Journal& operator=(Journal&& o) noexcept;
  Journal(const Journal&) = delete;
  Journal& operator=(const Journal&) = delete;
  ~Journal();

  // A new, empty journal (an existing file is replaced).
  static Journal create(const std::filesystem::path& path);
  // An existing journal, for appending after its committed records (a torn tail is cut off).
  static Journal open_append(const std::filesystem::path& path);
  // Every committed record of the journal at `path`.
  static JournalContents read(const std::filesystem::path& path);

  // Appends one record. On failure (disk full, ...) the journal is cut back to its last
  // committed record and JournalError is thrown: the record is not committed.
  void append(std::int64_t key, std::span<const std::byte> payload);
  void close();  // also done by the destructor
  const std::filesystem::path& path() const { return path_; }
  // open_append() found a torn tail and cut it off.
  bool cut_torn_tail() const { return cut_tail_; }

 private:
  Journal(int fd, std::filesystem::path path, std::uint64_t size) : fd_(fd), path_(std::move(path)), size_(size) {}
  int fd_ = -1;
  std::filesystem::path path_;
  std::uint64_t size_ = 0;  // bytes committed
  bool cut_tail_ = false;
};

}  // namespace ajx::io
