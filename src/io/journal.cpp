#include "io/journal.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/uio.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <algorithm>
#include <fstream>
#include <optional>
#include <iterator>
#include <utility>

namespace ajx::io {

namespace {

constexpr char kFileMagic[8] = {'A', 'J', 'X', 'J', 'R', 'N', 'L', '1'};
constexpr std::uint32_t kRecordMagic = 0x4a524543;
struct RecordHeader {
  std::uint32_t magic;
  std::uint32_t crc;  // of key, length and payload
  std::int64_t key;
  std::uint64_t length;
};
static_assert(sizeof(RecordHeader) == 24);

std::uint32_t crc_of(std::int64_t key, std::uint64_t length, const std::byte* data, std::size_t n) {
  uLong c = crc32(0L, Z_NULL, 0);
  c = crc32(c, reinterpret_cast<const Bytef*>(&key), sizeof key);
  c = crc32(c, reinterpret_cast<const Bytef*>(&length), sizeof length);
  // zlib takes uInt lengths: feed large payloads in pieces.
  for (std::size_t at = 0; at < n;) {
    const std::size_t piece = std::min<std::size_t>(n - at, 1u << 30);
    c = crc32(c, reinterpret_cast<const Bytef*>(data + at), uInt(piece));
    at += piece;
  }
  return std::uint32_t(c);
}

std::string sys_error(const std::string& what, const std::filesystem::path& p) {
  return what + " '" + p.string() + "': " + std::strerror(errno);
}

// Writes all of buf; false (errno set) on failure.
bool write_all(int fd, const void* buf, std::size_t n) {
  const char* p = static_cast<const char*>(buf);
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    p += w;
    n -= std::size_t(w);
  }
  return true;
}

// Writes a record's header and payload with one system call where the kernel takes both (the
// master appends one record per result); false (errno set) on failure.
bool write_record(int fd, const void* head, std::size_t nh, const void* data, std::size_t nd) {
  iovec v[2] = {{const_cast<void*>(head), nh}, {const_cast<void*>(data), nd}};
  ssize_t w = 0;
  do w = ::writev(fd, v, nd > 0 ? 2 : 1); while (w < 0 && errno == EINTR);
  if (w < 0) return false;
  const std::size_t done = std::size_t(w);
  if (done >= nh + nd) return true;
  // A short write (a signal, a full pipe): the rest one piece at a time.
  if (done < nh) return write_all(fd, static_cast<const char*>(head) + done, nh - done) && write_all(fd, data, nd);
  return write_all(fd, static_cast<const char*>(data) + (done - nh), nd - (done - nh));
}

// An exclusive lock for the writer's lifetime: a second sweep on the same output (a resume
// started while the ranks of a killed mpirun still run) is refused. File systems without
// flock (some Lustre mounts) give no protection; that is not an error.
void lock_or_throw(int fd, const std::filesystem::path& p) {
  if (::flock(fd, LOCK_EX | LOCK_NB) == 0 || errno != EWOULDBLOCK) return;
  ::close(fd);
  throw JournalError("'" + p.string() + "' is in use by another running sweep (wait for it to end, or end it)");
}

}  // namespace

Journal::Journal(Journal&& o) noexcept
    : fd_(std::exchange(o.fd_, -1)), path_(std::move(o.path_)), size_(o.size_), found_(std::move(o.found_)) {}
Journal& Journal::operator=(Journal&& o) noexcept {
  if (this != &o) {
    close();
    fd_ = std::exchange(o.fd_, -1);
    path_ = std::move(o.path_);
    size_ = o.size_;
    found_ = std::move(o.found_);
  }
  return *this;
}
Journal::~Journal() { close(); }

void Journal::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

Journal Journal::create(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw JournalError(sys_error("cannot create the journal", path));
  lock_or_throw(fd, path);
  if (::ftruncate(fd, 0) != 0 || !write_all(fd, kFileMagic, sizeof kFileMagic)) {
    const std::string e = sys_error("cannot write the journal", path);
    ::close(fd);
    throw JournalError(e);
  }
  return Journal(fd, path, sizeof kFileMagic);
}

namespace {

// The intact record at `at` of `all` (magic, a length within the file, the CRC), or nullopt.
std::optional<RecordHeader> record_at(const std::vector<char>& all, std::size_t at) {
  RecordHeader h;
  if (all.size() - at < sizeof h) return std::nullopt;
  std::memcpy(&h, all.data() + at, sizeof h);
  if (h.magic != kRecordMagic || h.length > all.size() - at - sizeof h) return std::nullopt;
  const auto* data = reinterpret_cast<const std::byte*>(all.data() + at + sizeof h);
  if (crc_of(h.key, h.length, data, std::size_t(h.length)) != h.crc) return std::nullopt;
  return h;
}

// Offsets after `from` where the record magic appears (candidates for the next record).
std::size_t next_magic(const std::vector<char>& all, std::size_t from) {
  const auto* m = reinterpret_cast<const char*>(&kRecordMagic);
  const auto it = std::search(all.begin() + std::ptrdiff_t(std::min(from, all.size())), all.end(), m, m + 4);
  return std::size_t(it - all.begin());
}

// The stretch [at, end) that holds no intact record: why, and how many records it held (its
// first, plus every record magic inside it).
JournalDamage damage_at(const std::vector<char>& all, std::size_t at, std::size_t end) {
  JournalDamage d{at, end - at, 1, ""};
  for (std::size_t k = next_magic(all, at + 1); k + 4 <= end; k = next_magic(all, k + 1)) ++d.records;
  RecordHeader h;
  if (all.size() - at < sizeof h) {
    d.reason = "cut short";
  } else {
    std::memcpy(&h, all.data() + at, sizeof h);
    if (h.magic != kRecordMagic)
      d.reason = "damaged record header";
    else if (h.length > all.size() - at - sizeof h)
      d.reason = end == all.size() ? "cut short" : "damaged record header";
    else
      d.reason = "checksum mismatch";
  }
  return d;
}

}  // namespace

JournalContents Journal::read(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw JournalError(sys_error("cannot open the journal", path));
  const std::vector<char> all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  JournalContents out;
  if (all.size() < sizeof kFileMagic || std::memcmp(all.data(), kFileMagic, sizeof kFileMagic) != 0) {
    // A damaged magic in front of intact records is damage, not another kind of file.
    if (all.size() < sizeof kFileMagic || !record_at(all, sizeof kFileMagic))
      throw JournalError("'" + path.string() + "' is not an astrojax journal (nor one whose first record is intact)");
    out.damaged_magic = true;
  }
  std::size_t at = sizeof kFileMagic;
  out.valid_bytes = at;
  while (at < all.size()) {
    if (const auto h = record_at(all, at)) {
      const auto* data = reinterpret_cast<const std::byte*>(all.data() + at + sizeof *h);
      out.records.push_back({h->key, std::vector<std::byte>(data, data + h->length)});
      at += sizeof *h + std::size_t(h->length);
      out.valid_bytes = at;
      continue;
    }
    // Skip to the next intact record, or to the end.
    std::size_t next = next_magic(all, at + 1);
    while (next < all.size() && !record_at(all, next)) next = next_magic(all, next + 1);
    out.damage.push_back(damage_at(all, at, next));
    if (at == sizeof kFileMagic) out.first_record_lost = true;
    at = next;
  }
  out.torn_tail = out.valid_bytes < all.size();
  return out;
}

bool Journal::in_use(const std::filesystem::path& path) {
  // Opened for writing where allowed: NFS emulates flock with fcntl locks, whose exclusive kind
  // needs a descriptor open for writing.
  int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool held = ::flock(fd, LOCK_EX | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  ::close(fd);  // releases the lock if it was taken here
  return held;
}

Journal Journal::open_append(const std::filesystem::path& path,
                             const std::function<void(const JournalContents&)>& accept) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) throw JournalError(sys_error("cannot open the journal", path));
  lock_or_throw(fd, path);
  Journal j(fd, path, 0);  // closes fd if what follows throws
  j.found_ = read(path);
  const JournalContents& c = j.found_;
  if (accept) accept(c);
  const bool inner_damage = c.damaged_magic || c.damage.size() > (c.torn_tail ? 1u : 0u);
  if (inner_damage) {
    j.rewrite_intact();
  } else {
    if ((c.torn_tail && ::ftruncate(fd, off_t(c.valid_bytes)) != 0) || ::lseek(fd, off_t(c.valid_bytes), SEEK_SET) < 0)
      throw JournalError(sys_error("cannot cut the torn tail of the journal", path));
    j.size_ = c.valid_bytes;
  }
  return j;
}

// The journal replaced by one of its intact records only, written beside it and renamed over
// it (a process killed meanwhile leaves the damaged journal as it was). The new file is locked
// before it takes the journal's name, so no other sweep can take it in between.
void Journal::rewrite_intact() {
  const std::filesystem::path tmp = path_.string() + ".salvage";
  const int nfd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (nfd < 0) throw JournalError(sys_error("cannot write the salvaged journal", tmp));
  lock_or_throw(nfd, tmp);
  Journal fresh(nfd, path_, 0);
  try {
    if (!write_all(nfd, kFileMagic, sizeof kFileMagic))
      throw JournalError(sys_error("cannot write the salvaged journal", tmp));
    fresh.size_ = sizeof kFileMagic;
    for (const JournalRecord& r : found_.records) fresh.append(r.key, r.payload);
    if (::fsync(nfd) != 0 || ::rename(tmp.c_str(), path_.c_str()) != 0)
      throw JournalError(sys_error("cannot replace the damaged journal by its salvaged records", path_));
  } catch (const JournalError&) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
  close();
  fd_ = std::exchange(fresh.fd_, -1);
  size_ = fresh.size_;
}

void Journal::append(std::int64_t key, std::span<const std::byte> payload) {
  if (fd_ < 0) throw JournalError("journal '" + path_.string() + "' is closed");
  RecordHeader h{kRecordMagic, 0, key, payload.size()};
  h.crc = crc_of(key, h.length, payload.data(), payload.size());
  if (!write_record(fd_, &h, sizeof h, payload.data(), payload.size())) {
    const std::string e = sys_error("cannot append to the journal", path_);
    // Leave no torn record behind: back to the last committed one.
    if (::ftruncate(fd_, off_t(size_)) == 0) ::lseek(fd_, off_t(size_), SEEK_SET);
    throw JournalError(e);
  }
  size_ += sizeof h + payload.size();
}

}  // namespace ajx::io
