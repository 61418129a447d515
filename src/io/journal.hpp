// An append-only journal of opaque records, the commit log beside a file that a killed process
// may leave half-written (an HDF5 file killed between two flushes can be unreadable).
// Knows nothing of physics or HDF5.
//
// Layout: an 8-byte magic "AJXJRNL1", then records, each
//   u32 magic 0x4a524543 | u32 CRC-32 of the rest | i64 key | u64 length | length payload bytes
// (little-endian, the architecture's own). A record is committed once append() returns: its
// bytes are in the kernel, so they survive the death of the process (kill -9, a job killed
// at its time limit), though not a crash of the machine before the kernel writes them.
// Damage is skipped, not fatal: a stretch that is no intact record (a record cut short, one
// failing its CRC, a damaged record header) is skipped up to the next intact record, found by
// its magic and CRC, and read() says where each stretch lies, why, and how many records it
// held; a damaged file magic is reported as such and the records behind it read. open_append()
// cuts a torn tail away and rewrites a journal with damage inside to its intact records.
// The writer holds an exclusive flock on the journal (released by the kernel when the process
// dies, however): create() and open_append() of a journal another process writes throw
// JournalError, and in_use() asks without taking it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
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

// A stretch of a journal that holds no intact record: bytes [offset, offset + length).
struct JournalDamage {
  std::uint64_t offset = 0, length = 0;
  std::size_t records = 1;  // records it held, as far as their framing still shows (at least 1)
  std::string reason;       // "cut short", "checksum mismatch", "damaged record header"
};

// What read() found: the intact records, and every stretch skipped.
struct JournalContents {
  std::vector<JournalRecord> records;
  std::uint64_t valid_bytes = 0;    // end of the last intact record
  bool torn_tail = false;           // bytes after it (an append cut short, or damage at the end)
  bool damaged_magic = false;       // the first 8 bytes are not the journal's magic (records behind it intact)
  bool first_record_lost = false;   // the first record (at byte 8) is in a damaged stretch
  std::vector<JournalDamage> damage;  // in file order; the torn tail, if any, last
  std::size_t records_lost() const {
    std::size_t n = 0;
    for (const JournalDamage& d : damage) n += d.records;
    return n;
  }
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
  // An existing journal, for appending after its intact records: locked, read, and shown to
  // `accept` (if given) before anything changes; accept may throw to refuse it as it is. Then a
  // torn tail is cut off, and a journal with damage before its end (or a damaged magic) is
  // rewritten with its intact records only. found() is what was read.
  static Journal open_append(const std::filesystem::path& path,
                             const std::function<void(const JournalContents&)>& accept = {});
  // Every intact record of the journal at `path`, and the damage between them.
  static JournalContents read(const std::filesystem::path& path);
  // Whether another process holds the journal at `path` (a sweep writing it).
  static bool in_use(const std::filesystem::path& path);

  // Appends one record. On failure (disk full, ...) the journal is cut back to its last
  // committed record and JournalError is thrown: the record is not committed.
  void append(std::int64_t key, std::span<const std::byte> payload);
  void close();  // also done by the destructor
  const std::filesystem::path& path() const { return path_; }
  // What open_append() read before it cut or rewrote anything (its records may be moved out).
  JournalContents& found() { return found_; }

 private:
  Journal(int fd, std::filesystem::path path, std::uint64_t size) : fd_(fd), path_(std::move(path)), size_(size) {}
  void rewrite_intact();
  int fd_ = -1;
  std::filesystem::path path_;
  std::uint64_t size_ = 0;  // bytes committed
  JournalContents found_;
};

}  // namespace ajx::io
