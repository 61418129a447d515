#include "io/journal.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <fstream>
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
    : fd_(std::exchange(o.fd_, -1)), path_(std::move(o.path_)), size_(o.size_), cut_tail_(o.cut_tail_) {}
Journal& Journal::operator=(Journal&& o) noexcept {
  if (this != &o) {
    close();
    fd_ = std::exchange(o.fd_, -1);
    path_ = std::move(o.path_);
    size_ = o.size_;
    cut_tail_ = o.cut_tail_;
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

JournalContents Journal::read(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw JournalError(sys_error("cannot open the journal", path));
  const std::vector<char> all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (all.size() < sizeof kFileMagic || std::memcmp(all.data(), kFileMagic, sizeof kFileMagic) != 0)
    throw JournalError("'" + path.string() + "' is not an astrojax journal");
  JournalContents out;
  std::size_t at = sizeof kFileMagic;
  while (true) {
    RecordHeader h;
    if (all.size() - at < sizeof h) break;
    std::memcpy(&h, all.data() + at, sizeof h);
    if (h.magic != kRecordMagic || h.length > all.size() - at - sizeof h) break;
    const auto* data = reinterpret_cast<const std::byte*>(all.data() + at + sizeof h);
    if (crc_of(h.key, h.length, data, std::size_t(h.length)) != h.crc) break;
    out.records.push_back({h.key, std::vector<std::byte>(data, data + h.length)});
    at += sizeof h + std::size_t(h.length);
  }
  out.valid_bytes = at;
  out.torn_tail = at < all.size();
  return out;
}

Journal Journal::open_append(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) throw JournalError(sys_error("cannot open the journal", path));
  lock_or_throw(fd, path);
  const JournalContents c = read(path);
  if ((c.torn_tail && ::ftruncate(fd, off_t(c.valid_bytes)) != 0) || ::lseek(fd, off_t(c.valid_bytes), SEEK_SET) < 0) {
    const std::string e = sys_error("cannot cut the torn tail of the journal", path);
    ::close(fd);
    throw JournalError(e);
  }
  Journal j(fd, path, c.valid_bytes);
  j.cut_tail_ = c.torn_tail;
  return j;
}

void Journal::append(std::int64_t key, std::span<const std::byte> payload) {
  if (fd_ < 0) throw JournalError("journal '" + path_.string() + "' is closed");
  RecordHeader h{kRecordMagic, 0, key, payload.size()};
  h.crc = crc_of(key, h.length, payload.data(), payload.size());
  if (!write_all(fd_, &h, sizeof h) || !write_all(fd_, payload.data(), payload.size())) {
    const std::string e = sys_error("cannot append to the journal", path_);
    // Leave no torn record behind: back to the last committed one.
    if (::ftruncate(fd_, off_t(size_)) == 0) ::lseek(fd_, off_t(size_), SEEK_SET);
    throw JournalError(e);
  }
  size_ += sizeof h + payload.size();
}

}  // namespace ajx::io
