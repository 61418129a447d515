// Thin RAII layer over the HDF5 C library (serial). Knows nothing of physics.
//
// Every HDF5 handle is owned by exactly one move-only object; every C call is checked and a
// failure throws Hdf5Error naming the call, the object path and the file, plus the most
// specific message of HDF5's own error stack, e.g.
//   H5Dcreate2 failed for '/trajectory/r1' in out/run.h5: name already exists
// HDF5's automatic error printing is switched off when a file is created or opened.
// Argument mistakes that HDF5 never sees (a shape that does not match the data, a row of the
// wrong width) throw std::invalid_argument; misuse of a temporary file throws std::logic_error.
//
// Lifetime: a File closes the file completely when it is closed, committed or destroyed
// (HDF5 "strong" close). Groups and datasets obtained from it must not be used afterwards:
// their operations then throw Hdf5Error, and destroying them (in any order) is harmless.
//
// Layout conventions: arrays are row-major (C order) with explicit dimensions, stored as
// little-endian IEEE doubles / two's-complement integers; strings are variable-length UTF-8.
// Reading converts any numeric dataset to the requested element type (HDF5 conversion).
// Not thread-safe (serial HDF5).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace ajx::io {

class Hdf5Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Dimensions of a dataset, slowest-varying first: {rows, cols} for a 2-D array, {n} for 1-D,
// {} for a scalar.
using Dims = std::vector<std::size_t>;

// Data read back from a dataset: dims and the row-major elements.
template <class T>
struct Array {
  Dims dims;
  std::vector<T> data;

  std::size_t rows() const { return dims.empty() ? 1 : dims[0]; }
  // Meaningful for 1-D (1) and 2-D arrays.
  std::size_t cols() const { return dims.size() < 2 ? 1 : dims[1]; }
  // Element (i, j) of a 2-D array.
  const T& operator()(std::size_t i, std::size_t j) const { return data[i * cols() + j]; }
  T& operator()(std::size_t i, std::size_t j) { return data[i * cols() + j]; }
};

// Element type stored in the file.
enum class DType { Float64, Float32, Int64, Int32, Int8 };

// The class of a stored dataset's or attribute's element type, for readers that check a file
// against its layout before they trust it.
enum class TypeClass { Integer, Float, String, Other };

namespace detail {

// Owner of one HDF5 identifier (hid_t is int64_t in HDF5 >= 1.10; checked in the .cpp).
// Closes it with the call matching its kind; a handle already closed by the library (strong
// file close) is skipped.
class Handle {
 public:
  enum class Kind : std::uint8_t { File, Group, Dataset, Dataspace, Datatype, Attribute, PropertyList };

  Handle() noexcept = default;
  Handle(std::int64_t id, Kind kind) noexcept : id_(id), kind_(kind) {}
  Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, -1)), kind_(other.kind_) {}
  Handle& operator=(Handle&& other) noexcept;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }

  std::int64_t get() const noexcept { return id_; }
  Kind kind() const noexcept { return kind_; }
  bool valid() const noexcept { return id_ >= 0; }
  // Close and forget, ignoring errors. close() is the checked variant (false on failure).
  void reset() noexcept;
  [[nodiscard]] bool close() noexcept;

 private:
  std::int64_t id_ = -1;
  Kind kind_ = Kind::File;
};

struct FileState;  // per open file: its name and open flag (in the .cpp)

}  // namespace detail

// Anything that carries attributes: the file (root group), groups, datasets.
// Writing an attribute that exists replaces it.
class Object {
 public:
  // Absolute HDF5 path of the object ("/" for the file) and the file it lives in.
  const std::string& path() const noexcept { return path_; }
  const std::string& file_name() const noexcept;
  bool valid() const noexcept { return handle_.valid(); }

  void set_attribute(std::string_view name, std::string_view value);
  void set_attribute(std::string_view name, const char* value) { set_attribute(name, std::string_view(value)); }
  void set_attribute(std::string_view name, double value);
  void set_attribute(std::string_view name, std::int64_t value);
  void set_attribute(std::string_view name, std::span<const double> values);
  // A 1-D attribute of variable-length UTF-8 strings, one element per item (empty allowed).
  void set_attribute(std::string_view name, std::span<const std::string> values);
  // Any other integer (int, unsigned, ...) is stored as int64; bool is rejected at compile time.
  template <class I>
    requires std::is_integral_v<I> && (!std::is_same_v<I, bool>) && (!std::is_same_v<I, std::int64_t>)
  void set_attribute(std::string_view name, I value) {
    set_attribute(name, static_cast<std::int64_t>(value));
  }

  bool has_attribute(std::string_view name) const;
  std::string read_string_attribute(std::string_view name) const;
  double read_double_attribute(std::string_view name) const;  // numeric attributes convert
  std::int64_t read_int64_attribute(std::string_view name) const;
  std::vector<double> read_doubles_attribute(std::string_view name) const;
  // A string attribute as a list: a 1-D (or scalar) attribute of strings, fixed or variable length.
  std::vector<std::string> read_strings_attribute(std::string_view name) const;
  TypeClass attribute_type_class(std::string_view name) const;
  // The attribute's number of elements and rank (0 for a scalar).
  Dims attribute_dims(std::string_view name) const;

  // The raw hid_t, for the rare call this layer does not wrap. Ownership stays here.
  std::int64_t native_handle() const noexcept { return handle_.get(); }

 protected:
  Object() = default;
  Object(detail::Handle h, std::shared_ptr<detail::FileState> file, std::string path)
      : handle_(std::move(h)), file_(std::move(file)), path_(std::move(path)) {}

  detail::Handle handle_;
  std::shared_ptr<detail::FileState> file_;
  std::string path_;
};

class Dataset : public Object {
 public:
  Dataset() = default;

  Dims dims() const;
  TypeClass type_class() const;
  // Whether its chunks carry a checksum HDF5 checks on every read: Fletcher32, or deflate
  // (the zlib stream's Adler-32).
  bool checksummed() const;
  Array<double> read_doubles() const;
  Array<std::int64_t> read_int64s() const;
  Array<std::int32_t> read_int32s() const;
  // Scalar (or single-element) string dataset, variable- or fixed-length.
  std::string read_string() const;
  // A 1-D dataset of strings, one per element.
  std::vector<std::string> read_strings() const;

  // Write a row-major block of shape `count` at `offset` (both of the dataset's rank): results
  // that arrive piece by piece, into a dataset made by Group::create_filled.
  void write_region(const Dims& offset, const Dims& count, std::span<const double> data);
  void write_region(const Dims& offset, const Dims& count, std::span<const std::int32_t> data);
  void write_region(const Dims& offset, const Dims& count, std::span<const std::int64_t> data);
  // Write one whole chunk, already passed through the dataset's filters (see encode_chunk), at
  // `offset` (a multiple of the chunk shape): the compression can then happen elsewhere.
  void write_chunk(const Dims& offset, std::span<const std::byte> filtered);

 protected:
  friend class Group;
  using Object::Object;
};

// One chunk of doubles (a Float64 dataset) or floats (Float32) through the filters
// Group::create_filled sets for deflate > 0, in HDF5's order: byte shuffle, then deflate at
// that level. For Dataset::write_chunk; `values` fills the whole chunk (pad with the fill
// value). Pure: any rank may call it.
std::vector<std::byte> encode_chunk(std::span<const double> values, int deflate);
std::vector<std::byte> encode_chunk(std::span<const float> values, int deflate);


// A group. Paths may be nested ("a/b/c", relative to this group) or absolute ("/a/b").
// Creating groups, datasets and tables creates missing intermediate groups.
class Group : public Object {
 public:
  Group() = default;

  bool exists(std::string_view path) const;  // any link: group or dataset
  Group create_group(std::string_view path);  // fails if it exists
  Group open_group(std::string_view path) const;
  Group require_group(std::string_view path);  // open, or create if missing
  void remove(std::string_view path);         // unlinks a group or dataset (its space is not reclaimed)

  // Whole arrays, row-major; the product of dims must equal data.size() (dims {} = scalar).
  // A non-empty array is stored in chunks that carry HDF5's Fletcher32 checksum: a byte changed
  // on disk makes its read throw Hdf5Error ("data error detected by Fletcher32 checksum").
  Dataset write_dataset(std::string_view path, std::span<const double> data, const Dims& dims);
  Dataset write_dataset(std::string_view path, std::span<const std::int64_t> data, const Dims& dims);
  Dataset write_dataset(std::string_view path, std::span<const std::int32_t> data, const Dims& dims);
  // 1-D shortcuts: dims = {data.size()}.
  Dataset write_dataset(std::string_view path, std::span<const double> data) { return write_dataset(path, data, {data.size()}); }
  Dataset write_dataset(std::string_view path, std::span<const std::int64_t> data) { return write_dataset(path, data, {data.size()}); }
  Dataset write_dataset(std::string_view path, std::span<const std::int32_t> data) { return write_dataset(path, data, {data.size()}); }
  Dataset write_dataset(std::string_view path, std::span<const std::int8_t> data);
  // 1-D dataset of variable-length UTF-8 strings (contiguous, unchecksummed: HDF5 cannot
  // checksum the heap that holds the strings).
  Dataset write_dataset(std::string_view path, std::span<const std::string> data);
  // Scalar variable-length UTF-8 string dataset, for long texts (e.g. a configuration file).
  Dataset write_string_dataset(std::string_view path, std::string_view text);
  // A chunked dataset of shape `dims` whose unwritten elements read as `fill` (NaN marks
  // results not computed yet), written later with Dataset::write_region. `chunk` has the
  // rank of `dims`; deflate 0 (none) to 9. Without deflate every chunk carries a Fletcher32
  // checksum; with it, the zlib stream's Adler-32 checks the chunk.
  Dataset create_filled(std::string_view path, const Dims& dims, DType dtype, double fill, const Dims& chunk,
                        int deflate = 0);

  Dataset open_dataset(std::string_view path) const;
  Array<double> read_doubles(std::string_view path) const { return open_dataset(path).read_doubles(); }
  Array<std::int64_t> read_int64s(std::string_view path) const { return open_dataset(path).read_int64s(); }
  Array<std::int32_t> read_int32s(std::string_view path) const { return open_dataset(path).read_int32s(); }
  std::string read_string_dataset(std::string_view path) const { return open_dataset(path).read_string(); }

 protected:
  using Object::Object;
  std::string child_path(std::string_view rel) const;
};

class File : public Group {
 public:
  File() = default;
  File(File&& other) noexcept;
  File& operator=(File&& other) noexcept;
  ~File();

  // New file at `path`, truncating any existing one.
  static File create(const std::filesystem::path& path);
  // New file written as "<path>.part"; commit() renames it to `path`. Closed or destroyed
  // without commit(), the .part file is removed and `path` is left untouched.
  static File create_temporary(const std::filesystem::path& path);
  static File open_read(const std::filesystem::path& path);
  static File open_rw(const std::filesystem::path& path);

  // Push all data and metadata to the OS.
  void flush();
  // Temporary files only: flush, close, fsync, then atomically rename "<path>.part" -> path.
  void commit();
  // Flush and close now, reporting errors (the destructor flushes and closes too but has to
  // swallow errors). An uncommitted temporary file is discarded instead.
  void close();

  bool is_open() const noexcept { return handle_.valid(); }
  bool is_temporary() const noexcept { return temporary_; }
  // The final path, and where the bytes are now (".part" until a temporary file is committed).
  const std::filesystem::path& final_path() const noexcept { return final_path_; }
  std::filesystem::path disk_path() const;

 private:
  File(detail::Handle h, std::shared_ptr<detail::FileState> state, std::filesystem::path final_path,
       bool temporary);
  void discard() noexcept;
  void release() noexcept;  // flush quietly and close, or discard an uncommitted temporary

  std::filesystem::path final_path_;
  bool temporary_ = false;
  bool committed_ = false;
};

// Create `path` atomically: fill(File&) writes into "<path>.part", which is renamed to `path`
// only if fill returns normally; if it throws, the .part file is removed and the exception
// propagates.
template <class Fill>
void write_atomically(const std::filesystem::path& path, Fill&& fill) {
  File file = File::create_temporary(path);
  std::forward<Fill>(fill)(file);
  file.commit();
}

}  // namespace ajx::io
