#include "io/hdf5_file.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <libdeflate.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fmt/format.h>
#include <map>
#include <memory>
#include <system_error>
#include <type_traits>

namespace ajx::io {

static_assert(std::is_same_v<hid_t, std::int64_t>, "hid_t must be int64_t (HDF5 >= 1.10)");

namespace fs = std::filesystem;
using Kind = detail::Handle::Kind;
using detail::Handle;

namespace {

// The largest chunk of a checksummed whole array (write_dataset): a read of one element
// decodes and checks its whole chunk.
constexpr std::size_t kChecksumChunkBytes = std::size_t(1) << 20;

// What a failing call was acting on, for the error message.
struct Where {
  std::string_view file;
  std::string_view path;
};

herr_t keep_innermost(unsigned /*n*/, const H5E_error2_t* err, void* out) {
  if (err != nullptr && err->desc != nullptr && err->desc[0] != '\0') {
    *static_cast<std::string*>(out) = err->desc;
  }
  return 0;
}

// The most specific description on HDF5's error stack (the deepest frame), e.g.
// "unable to open file: name = 'x.h5', errno = 2, error message = 'No such file or directory'...".
std::string innermost_error() {
  std::string msg;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, keep_innermost, &msg);
  H5Eclear2(H5E_DEFAULT);
  return msg;
}

[[noreturn]] void fail(std::string_view call, Where w) {
  std::string detail = innermost_error();
  std::string msg = fmt::format("{} failed for '{}' in {}", call, w.path, w.file);
  if (!detail.empty()) {
    msg += ": ";
    msg += detail;
  }
  throw Hdf5Error(msg);
}

[[noreturn]] void fail_plain(std::string_view what, Where w) {
  throw Hdf5Error(fmt::format("'{}' in {} {}", w.path, w.file, what));
}

hid_t check_id(hid_t id, std::string_view call, Where w) {
  if (id < 0) fail(call, w);
  return id;
}

void check(herr_t status, std::string_view call, Where w) {
  if (status < 0) fail(call, w);
}

bool check_tri(htri_t status, std::string_view call, Where w) {
  if (status < 0) fail(call, w);
  return status > 0;
}

Handle own(hid_t id, Kind kind, std::string_view call, Where w) { return Handle(check_id(id, call, w), kind); }

void init_library() {
  static const bool initialised = [] {
    // Every handle is closed by its owner. The library's own clean-up at exit would only close
    // again a file whose close failed (a full disk), and HDF5 1.10 crashes doing that. Only
    // effective before the library starts, hence once, first.
    H5dont_atexit();
    H5open();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)initialised;
}

hid_t mem_type_of(DType t) {
  switch (t) {
    case DType::Float64: return H5T_NATIVE_DOUBLE;
    case DType::Float32: return H5T_NATIVE_FLOAT;
    case DType::Int64: return H5T_NATIVE_INT64;
    case DType::Int32: return H5T_NATIVE_INT32;
    case DType::Int8: return H5T_NATIVE_INT8;
  }
  return -1;
}

hid_t file_type_of(DType t) {
  switch (t) {
    case DType::Float64: return H5T_IEEE_F64LE;
    case DType::Float32: return H5T_IEEE_F32LE;
    case DType::Int64: return H5T_STD_I64LE;
    case DType::Int32: return H5T_STD_I32LE;
    case DType::Int8: return H5T_STD_I8LE;
  }
  return -1;
}

std::vector<hsize_t> to_hsize(const Dims& dims) { return {dims.begin(), dims.end()}; }

std::size_t element_count(const Dims& dims) {
  std::size_t n = 1;
  for (std::size_t d : dims) n *= d;
  return n;
}

Handle make_space(const Dims& dims, Where w) {
  if (dims.empty()) return own(H5Screate(H5S_SCALAR), Kind::Dataspace, "H5Screate", w);
  auto h = to_hsize(dims);
  return own(H5Screate_simple(static_cast<int>(h.size()), h.data(), nullptr), Kind::Dataspace, "H5Screate_simple", w);
}

Handle utf8_string_type(Where w) {
  Handle t = own(H5Tcopy(H5T_C_S1), Kind::Datatype, "H5Tcopy", w);
  check(H5Tset_size(t.get(), H5T_VARIABLE), "H5Tset_size", w);
  check(H5Tset_cset(t.get(), H5T_CSET_UTF8), "H5Tset_cset", w);
  return t;
}

// Link creation properties: create missing intermediate groups.
Handle intermediate_lcpl(Where w) {
  Handle p = own(H5Pcreate(H5P_LINK_CREATE), Kind::PropertyList, "H5Pcreate", w);
  check(H5Pset_create_intermediate_group(p.get(), 1), "H5Pset_create_intermediate_group", w);
  return p;
}

Dims space_dims(hid_t space, Where w) {
  int rank = H5Sget_simple_extent_ndims(space);
  if (rank < 0) fail("H5Sget_simple_extent_ndims", w);
  std::vector<hsize_t> h(static_cast<std::size_t>(rank));
  if (rank > 0) check(H5Sget_simple_extent_dims(space, h.data(), nullptr), "H5Sget_simple_extent_dims", w);
  return {h.begin(), h.end()};
}

std::size_t space_points(hid_t space, Where w) {
  hssize_t n = H5Sget_simple_extent_npoints(space);
  if (n < 0) fail("H5Sget_simple_extent_npoints", w);
  return static_cast<std::size_t>(n);
}

// Reading is the same for attributes and datasets up to the names of the calls.
struct Source {
  hid_t id;
  bool attribute;
  Where w;

  Handle type() const {
    return attribute ? own(H5Aget_type(id), Kind::Datatype, "H5Aget_type", w)
                     : own(H5Dget_type(id), Kind::Datatype, "H5Dget_type", w);
  }
  Handle space() const {
    return attribute ? own(H5Aget_space(id), Kind::Dataspace, "H5Aget_space", w)
                     : own(H5Dget_space(id), Kind::Dataspace, "H5Dget_space", w);
  }
  void read(hid_t mem_type, void* buf) const {
    if (attribute) {
      check(H5Aread(id, mem_type, buf), "H5Aread", w);
    } else {
      check(H5Dread(id, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf), "H5Dread", w);
    }
  }
};

template <class T>
hid_t native_of() {
  if constexpr (std::is_same_v<T, double>) return H5T_NATIVE_DOUBLE;
  if constexpr (std::is_same_v<T, std::int64_t>) return H5T_NATIVE_INT64;
  if constexpr (std::is_same_v<T, std::int32_t>) return H5T_NATIVE_INT32;
  if constexpr (std::is_same_v<T, std::int8_t>) return H5T_NATIVE_INT8;
}

template <class T>
Array<T> read_numeric(const Source& src) {
  Handle space = src.space();
  Array<T> out;
  out.dims = space_dims(space.get(), src.w);
  out.data.resize(space_points(space.get(), src.w));
  if (!out.data.empty()) src.read(native_of<T>(), out.data.data());
  return out;
}

template <class T>
T read_scalar(const Source& src) {
  Handle space = src.space();
  std::size_t n = space_points(space.get(), src.w);
  if (n != 1) fail_plain(fmt::format("holds {} values, expected a single one", n), src.w);
  T value{};
  src.read(native_of<T>(), &value);
  return value;
}

// The memory type of variable-length strings read from `type`, in its character set.
Handle variable_string_type(const Handle& type, Where w) {
  Handle mem = own(H5Tcopy(H5T_C_S1), Kind::Datatype, "H5Tcopy", w);
  check(H5Tset_size(mem.get(), H5T_VARIABLE), "H5Tset_size", w);
  H5T_cset_t cset = H5Tget_cset(type.get());
  if (cset < 0) fail("H5Tget_cset", w);
  check(H5Tset_cset(mem.get(), cset), "H5Tset_cset", w);
  return mem;
}

std::string read_string_from(const Source& src) {
  Handle type = src.type();
  H5T_class_t cls = H5Tget_class(type.get());
  if (cls == H5T_NO_CLASS) fail("H5Tget_class", src.w);
  if (cls != H5T_STRING) fail_plain("is not a string", src.w);
  Handle space = src.space();
  std::size_t n = space_points(space.get(), src.w);
  if (n != 1) fail_plain(fmt::format("holds {} strings, expected a single one", n), src.w);

  if (check_tri(H5Tis_variable_str(type.get()), "H5Tis_variable_str", src.w)) {
    Handle mem = variable_string_type(type, src.w);
    char* ptr = nullptr;
    src.read(mem.get(), &ptr);
    std::string out = ptr != nullptr ? std::string(ptr) : std::string();
    check(H5Dvlen_reclaim(mem.get(), space.get(), H5P_DEFAULT, &ptr), "H5Dvlen_reclaim", src.w);
    return out;
  }

  std::size_t size = H5Tget_size(type.get());
  if (size == 0) fail("H5Tget_size", src.w);
  Handle mem = own(H5Tcopy(type.get()), Kind::Datatype, "H5Tcopy", src.w);
  std::string buf(size, '\0');
  src.read(mem.get(), buf.data());
  std::size_t end = buf.find('\0');
  if (end != std::string::npos) buf.resize(end);
  if (H5Tget_strpad(mem.get()) == H5T_STR_SPACEPAD) {
    std::size_t last = buf.find_last_not_of(' ');
    buf.resize(last == std::string::npos ? 0 : last + 1);
  }
  return buf;
}

std::vector<std::string> read_strings_from(const Source& src) {
  Handle type = src.type();
  H5T_class_t cls = H5Tget_class(type.get());
  if (cls == H5T_NO_CLASS) fail("H5Tget_class", src.w);
  if (cls != H5T_STRING) fail_plain("is not a string", src.w);
  Handle space = src.space();
  const std::size_t n = space_points(space.get(), src.w);
  std::vector<std::string> out;
  if (n == 0) return out;
  if (check_tri(H5Tis_variable_str(type.get()), "H5Tis_variable_str", src.w)) {
    Handle mem = variable_string_type(type, src.w);
    std::vector<char*> ptrs(n, nullptr);
    src.read(mem.get(), ptrs.data());
    for (char* p : ptrs) out.emplace_back(p != nullptr ? p : "");
    check(H5Dvlen_reclaim(mem.get(), space.get(), H5P_DEFAULT, ptrs.data()), "H5Dvlen_reclaim", src.w);
    return out;
  }
  const std::size_t size = H5Tget_size(type.get());
  if (size == 0) fail("H5Tget_size", src.w);
  Handle mem = own(H5Tcopy(type.get()), Kind::Datatype, "H5Tcopy", src.w);
  std::string buf(size * n, '\0');
  src.read(mem.get(), buf.data());
  for (std::size_t i = 0; i < n; ++i) {
    std::string item = buf.substr(i * size, size);
    item.resize(std::min(item.find('\0'), item.size()));
    out.push_back(item);
  }
  return out;
}

TypeClass type_class_of(const Source& src) {
  Handle type = src.type();
  switch (H5Tget_class(type.get())) {
    case H5T_INTEGER: return TypeClass::Integer;
    case H5T_FLOAT: return TypeClass::Float;
    case H5T_STRING: return TypeClass::String;
    case H5T_NO_CLASS: fail("H5Tget_class", src.w);
    default: return TypeClass::Other;
  }
}

std::string attr_path(const Object& obj, std::string_view name) { return fmt::format("{}@{}", obj.path(), name); }

// Create (replacing any previous one) and write an attribute.
void write_attribute(const Object& obj, std::string_view name, hid_t file_type, hid_t mem_type, const Handle& space,
                     const void* buf) {
  std::string n(name);
  std::string where_path = attr_path(obj, name);
  Where w{obj.file_name(), where_path};
  hid_t loc = obj.native_handle();
  if (check_tri(H5Aexists(loc, n.c_str()), "H5Aexists", w)) check(H5Adelete(loc, n.c_str()), "H5Adelete", w);
  Handle attr = own(H5Acreate2(loc, n.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT), Kind::Attribute,
                    "H5Acreate2", w);
  check(H5Awrite(attr.get(), mem_type, buf), "H5Awrite", w);
  if (!attr.close()) fail("H5Aclose", w);
}

// Open an attribute and apply `fn` to a Source over it.
template <class Fn>
auto with_attribute(const Object& obj, std::string_view name, Fn&& fn) {
  std::string n(name);
  std::string where_path = attr_path(obj, name);
  Where w{obj.file_name(), where_path};
  Handle attr = own(H5Aopen(obj.native_handle(), n.c_str(), H5P_DEFAULT), Kind::Attribute, "H5Aopen", w);
  return fn(Source{attr.get(), true, w});
}

// Create a dataset and write all of it. A non-empty array is chunked (whole rows, up to
// kChecksumChunkBytes a chunk) with HDF5's Fletcher32 checksum on each chunk, so that a byte
// changed on disk makes the read fail instead of returning a wrong value; an empty array or a
// scalar cannot be chunked and is stored contiguous.
Handle create_and_write(const Group& g, std::string_view path, const std::string& full_path, const void* data,
                        std::size_t n, const Dims& dims, hid_t file_type, hid_t mem_type) {
  Where w{g.file_name(), full_path};
  if (element_count(dims) != n) {
    throw std::invalid_argument(fmt::format("write_dataset '{}' in {}: {} values do not fill dims [{}]", full_path,
                                            g.file_name(), n, fmt::join(dims, ", ")));
  }
  Handle space = make_space(dims, w);
  Handle dcpl = own(H5Pcreate(H5P_DATASET_CREATE), Kind::PropertyList, "H5Pcreate", w);
  if (n > 0 && !dims.empty()) {
    auto chunk = to_hsize(dims);
    const std::size_t row_bytes = H5Tget_size(file_type) * (n / dims[0]);
    chunk[0] = std::clamp<hsize_t>(kChecksumChunkBytes / row_bytes, 1, dims[0]);
    check(H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()), "H5Pset_chunk", w);
    check(H5Pset_fletcher32(dcpl.get()), "H5Pset_fletcher32", w);
  }
  Handle lcpl = intermediate_lcpl(w);
  std::string p(path);
  Handle ds = own(H5Dcreate2(g.native_handle(), p.c_str(), file_type, space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT),
                  Kind::Dataset, "H5Dcreate2", w);
  if (n > 0) check(H5Dwrite(ds.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "H5Dwrite", w);
  return ds;
}

// fsync a file or directory; directories best-effort (some file systems refuse).
void sync_path(const fs::path& p, bool directory) {
  int fd = ::open(p.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) {
    if (directory) return;
    throw Hdf5Error(fmt::format("open for fsync failed for {}: {}", p.string(), std::strerror(errno)));
  }
  int rc = ::fsync(fd);
  int err = errno;
  ::close(fd);
  if (rc != 0 && !directory) throw Hdf5Error(fmt::format("fsync failed for {}: {}", p.string(), std::strerror(err)));
}

fs::path part_path(const fs::path& final_path) {
  fs::path p = final_path;
  p += ".part";
  return p;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// FileState: shared by a File and every object obtained from it.

namespace detail {

struct FileState {
  explicit FileState(std::string n) : name(std::move(n)) {}

  std::string name;
  bool open = true;
};

}  // namespace detail

using detail::FileState;

const std::string& Object::file_name() const noexcept {
  static const std::string none;
  return file_ ? file_->name : none;
}

// ---------------------------------------------------------------------------------------------
// Handle

namespace detail {

Handle& Handle::operator=(Handle&& other) noexcept {
  if (this != &other) {
    reset();
    id_ = std::exchange(other.id_, -1);
    kind_ = other.kind_;
  }
  return *this;
}

bool Handle::close() noexcept {
  if (id_ < 0) return true;
  hid_t id = std::exchange(id_, -1);
  herr_t rc = -1;
  switch (kind_) {
    case Kind::File: rc = H5Fclose(id); break;
    case Kind::Group: rc = H5Gclose(id); break;
    case Kind::Dataset: rc = H5Dclose(id); break;
    case Kind::Dataspace: rc = H5Sclose(id); break;
    case Kind::Datatype: rc = H5Tclose(id); break;
    case Kind::Attribute: rc = H5Aclose(id); break;
    case Kind::PropertyList: rc = H5Pclose(id); break;
  }
  return rc >= 0;
}

void Handle::reset() noexcept {
  if (id_ < 0) return;
  // Objects of a file closed with H5F_CLOSE_STRONG are already gone.
  if (H5Iis_valid(id_) <= 0) {
    id_ = -1;
    return;
  }
  (void)close();
}

}  // namespace detail

// ---------------------------------------------------------------------------------------------
// Object: attributes

void Object::set_attribute(std::string_view name, std::string_view value) {
  std::string where_path = attr_path(*this, name);
  Where w{file_name(), where_path};
  Handle type = utf8_string_type(w);
  Handle space = make_space({}, w);
  std::string copy(value);
  const char* ptr = copy.c_str();
  write_attribute(*this, name, type.get(), type.get(), space, &ptr);
}

void Object::set_attribute(std::string_view name, double value) {
  std::string where_path = attr_path(*this, name);
  Handle space = make_space({}, Where{file_name(), where_path});
  write_attribute(*this, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, space, &value);
}

void Object::set_attribute(std::string_view name, std::int64_t value) {
  std::string where_path = attr_path(*this, name);
  Handle space = make_space({}, Where{file_name(), where_path});
  write_attribute(*this, name, H5T_STD_I64LE, H5T_NATIVE_INT64, space, &value);
}

void Object::set_attribute(std::string_view name, std::span<const double> values) {
  std::string where_path = attr_path(*this, name);
  Handle space = make_space({values.size()}, Where{file_name(), where_path});
  static const double dummy = 0.0;  // HDF5 rejects a null buffer even for zero elements
  write_attribute(*this, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, space,
                  values.empty() ? &dummy : values.data());
}

void Object::set_attribute(std::string_view name, std::span<const std::string> values) {
  std::string where_path = attr_path(*this, name);
  Where w{file_name(), where_path};
  Handle type = utf8_string_type(w);
  Handle space = make_space({values.size()}, w);
  std::vector<const char*> ptrs;
  for (const std::string& v : values) ptrs.push_back(v.c_str());
  static const char* const dummy = "";  // HDF5 rejects a null buffer even for zero elements
  write_attribute(*this, name, type.get(), type.get(), space, ptrs.empty() ? &dummy : ptrs.data());
}

std::vector<std::string> Object::read_strings_attribute(std::string_view name) const {
  return with_attribute(*this, name, [](const Source& s) { return read_strings_from(s); });
}

TypeClass Object::attribute_type_class(std::string_view name) const {
  return with_attribute(*this, name, [](const Source& s) { return type_class_of(s); });
}

Dims Object::attribute_dims(std::string_view name) const {
  return with_attribute(*this, name, [](const Source& s) {
    Handle space = s.space();
    return space_dims(space.get(), s.w);
  });
}

bool Object::has_attribute(std::string_view name) const {
  std::string n(name);
  std::string where_path = attr_path(*this, name);
  return check_tri(H5Aexists(handle_.get(), n.c_str()), "H5Aexists", Where{file_name(), where_path});
}

std::string Object::read_string_attribute(std::string_view name) const {
  return with_attribute(*this, name, [](const Source& s) { return read_string_from(s); });
}

double Object::read_double_attribute(std::string_view name) const {
  return with_attribute(*this, name, [](const Source& s) { return read_scalar<double>(s); });
}

std::int64_t Object::read_int64_attribute(std::string_view name) const {
  return with_attribute(*this, name, [](const Source& s) { return read_scalar<std::int64_t>(s); });
}

std::vector<double> Object::read_doubles_attribute(std::string_view name) const {
  return with_attribute(*this, name, [](const Source& s) { return read_numeric<double>(s).data; });
}

// ---------------------------------------------------------------------------------------------
// Dataset

Dims Dataset::dims() const {
  Where w{file_name(), path_};
  Handle space = own(H5Dget_space(handle_.get()), Kind::Dataspace, "H5Dget_space", w);
  return space_dims(space.get(), w);
}

TypeClass Dataset::type_class() const { return type_class_of(Source{handle_.get(), false, {file_name(), path_}}); }

std::vector<std::string> Dataset::read_strings() const {
  return read_strings_from(Source{handle_.get(), false, {file_name(), path_}});
}

bool Dataset::checksummed() const {
  Where w{file_name(), path_};
  Handle dcpl = own(H5Dget_create_plist(handle_.get()), Kind::PropertyList, "H5Dget_create_plist", w);
  unsigned flags = 0;
  std::size_t n = 0;
  const auto has = [&](H5Z_filter_t f) {
    return H5Pget_filter_by_id2(dcpl.get(), f, &flags, &n, nullptr, 0, nullptr, nullptr) >= 0;
  };
  return has(H5Z_FILTER_FLETCHER32) || has(H5Z_FILTER_DEFLATE);  // (HDF5's error printing is off)
}

Array<double> Dataset::read_doubles() const { return read_numeric<double>(Source{handle_.get(), false, {file_name(), path_}}); }

Array<std::int64_t> Dataset::read_int64s() const {
  return read_numeric<std::int64_t>(Source{handle_.get(), false, {file_name(), path_}});
}

Array<std::int32_t> Dataset::read_int32s() const {
  return read_numeric<std::int32_t>(Source{handle_.get(), false, {file_name(), path_}});
}

std::string Dataset::read_string() const { return read_string_from(Source{handle_.get(), false, {file_name(), path_}}); }

// ---------------------------------------------------------------------------------------------
// Group

std::string Group::child_path(std::string_view rel) const {
  if (!rel.empty() && rel.front() == '/') return std::string(rel);
  if (path_ == "/") return fmt::format("/{}", rel);
  return fmt::format("{}/{}", path_, rel);
}

bool Group::exists(std::string_view path) const {
  Where w{file_name(), child_path(path)};
  if (!handle_.valid()) fail_plain("is not open", w);
  // Walk component by component: H5Lexists fails (rather than answering false) when an
  // intermediate component is missing or not a group.
  std::string cur = (!path.empty() && path.front() == '/') ? "/" : "";
  std::size_t pos = 0;
  bool first = true;
  while (pos <= path.size()) {
    std::size_t next = path.find('/', pos);
    if (next == std::string_view::npos) next = path.size();
    std::string_view comp = path.substr(pos, next - pos);
    pos = next + 1;
    if (comp.empty() || comp == ".") continue;
    if (!first) {
      // The previous component must resolve to a group to descend into it.
      H5O_info_t info;
      check(H5Oget_info_by_name2(handle_.get(), cur.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT),
            "H5Oget_info_by_name2", w);
      if (info.type != H5O_TYPE_GROUP) return false;
    }
    if (!cur.empty() && cur.back() != '/') cur += '/';
    cur += comp;
    if (!check_tri(H5Lexists(handle_.get(), cur.c_str(), H5P_DEFAULT), "H5Lexists", w)) return false;
    if (!check_tri(H5Oexists_by_name(handle_.get(), cur.c_str(), H5P_DEFAULT), "H5Oexists_by_name", w)) return false;
    first = false;
  }
  return true;  // empty path or "/" : this group or the root
}

Group Group::create_group(std::string_view path) {
  std::string full = child_path(path);
  Where w{file_name(), full};
  Handle lcpl = intermediate_lcpl(w);
  std::string p(path);
  Handle g = own(H5Gcreate2(handle_.get(), p.c_str(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT), Kind::Group,
                 "H5Gcreate2", w);
  return Group(std::move(g), file_, std::move(full));
}

void Group::remove(std::string_view path) {
  std::string full = child_path(path);
  std::string p(path);
  check(H5Ldelete(handle_.get(), p.c_str(), H5P_DEFAULT), "H5Ldelete", Where{file_name(), full});
}

Group Group::open_group(std::string_view path) const {
  std::string full = child_path(path);
  std::string p(path);
  Handle g = own(H5Gopen2(handle_.get(), p.c_str(), H5P_DEFAULT), Kind::Group, "H5Gopen2", Where{file_name(), full});
  return Group(std::move(g), file_, std::move(full));
}

Group Group::require_group(std::string_view path) { return exists(path) ? open_group(path) : create_group(path); }

Dataset Group::create_filled(std::string_view path, const Dims& dims, DType dtype, double fill, const Dims& chunk,
                             int deflate) {
  std::string full = child_path(path);
  Where w{file_name(), full};
  if (chunk.size() != dims.size() || dims.empty())
    throw std::invalid_argument(fmt::format("create_filled '{}' in {}: chunk and dims need the same, non-zero rank",
                                            full, file_name()));
  Handle space = make_space(dims, w);
  Handle dcpl = own(H5Pcreate(H5P_DATASET_CREATE), Kind::PropertyList, "H5Pcreate", w);
  auto c = to_hsize(chunk);
  for (std::size_t i = 0; i < c.size(); ++i) c[i] = std::max<hsize_t>(1, std::min<hsize_t>(c[i], dims[i]));
  check(H5Pset_chunk(dcpl.get(), static_cast<int>(c.size()), c.data()), "H5Pset_chunk", w);
  check(H5Pset_fill_value(dcpl.get(), H5T_NATIVE_DOUBLE, &fill), "H5Pset_fill_value", w);
  check(H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_ALLOC), "H5Pset_fill_time", w);
  if (deflate > 0) {
    check(H5Pset_shuffle(dcpl.get()), "H5Pset_shuffle", w);
    check(H5Pset_deflate(dcpl.get(), static_cast<unsigned>(std::min(deflate, 9))), "H5Pset_deflate", w);
  } else {
    // Uncompressed chunks get a Fletcher32 each; a deflated chunk is checked by its zlib
    // stream's Adler-32 (and is written whole by write_chunk, which bypasses HDF5's filters).
    check(H5Pset_fletcher32(dcpl.get()), "H5Pset_fletcher32", w);
  }
  Handle lcpl = intermediate_lcpl(w);
  std::string p(path);
  Handle ds = own(H5Dcreate2(handle_.get(), p.c_str(), file_type_of(dtype), space.get(), lcpl.get(), dcpl.get(),
                             H5P_DEFAULT),
                  Kind::Dataset, "H5Dcreate2", w);
  return Dataset(std::move(ds), file_, std::move(full));
}

namespace {
void write_region_impl(const Dataset& d, hid_t native, const Dims& offset, const Dims& count, const void* data,
                       std::size_t n, hid_t mem_type) {
  Where w{d.file_name(), d.path()};
  if (offset.size() != count.size() || element_count(count) != n)
    throw std::invalid_argument(fmt::format("write_region '{}' in {}: {} values do not fill a block [{}] at [{}]",
                                            d.path(), d.file_name(), n, fmt::join(count, ", "),
                                            fmt::join(offset, ", ")));
  if (n == 0) return;
  Handle file_space = own(H5Dget_space(native), Kind::Dataspace, "H5Dget_space", w);
  const auto start = to_hsize(offset), cnt = to_hsize(count);
  check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr, cnt.data(), nullptr),
        "H5Sselect_hyperslab", w);
  Handle mem_space = make_space(count, w);
  check(H5Dwrite(native, mem_type, mem_space.get(), file_space.get(), H5P_DEFAULT, data), "H5Dwrite", w);
}
}  // namespace

void Dataset::write_region(const Dims& offset, const Dims& count, std::span<const double> data) {
  write_region_impl(*this, handle_.get(), offset, count, data.data(), data.size(), H5T_NATIVE_DOUBLE);
}
void Dataset::write_chunk(const Dims& offset, std::span<const std::byte> filtered) {
  Where w{file_name(), path()};
  const auto start = to_hsize(offset);
  // Filter mask 0: every filter of the pipeline was applied.
  check(H5Dwrite_chunk(handle_.get(), H5P_DEFAULT, 0, start.data(), filtered.size(), filtered.data()),
        "H5Dwrite_chunk", w);
}

namespace {
// Shuffle (H5Z_FILTER_SHUFFLE): byte j of every element together, j = 0..B-1; then deflate
// (H5Z_FILTER_DEFLATE): a zlib stream, which libdeflate writes as zlib's compress2 would in
// format (HDF5 inflates it with zlib), at about half the instructions at level 1.
std::vector<std::byte> shuffle_deflate(const unsigned char* in, std::size_t n, std::size_t B, int deflate) {
  std::vector<unsigned char> shuffled(n * B);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < B; ++j) shuffled[j * n + i] = in[i * B + j];
  using Compressor = std::unique_ptr<libdeflate_compressor, decltype(&libdeflate_free_compressor)>;
  // One compressor per thread and level: allocating one costs more than a small chunk.
  thread_local std::map<int, Compressor> compressors;
  const int level = std::clamp(deflate, 1, 9);
  auto it = compressors.find(level);
  if (it == compressors.end())
    it = compressors.emplace(level, Compressor(libdeflate_alloc_compressor(level), &libdeflate_free_compressor)).first;
  if (!it->second) throw Hdf5Error("encode_chunk: libdeflate could not allocate a compressor");
  std::vector<std::byte> out(libdeflate_zlib_compress_bound(it->second.get(), shuffled.size()));
  const std::size_t size =
      libdeflate_zlib_compress(it->second.get(), shuffled.data(), shuffled.size(), out.data(), out.size());
  if (size == 0) throw Hdf5Error("encode_chunk: libdeflate's zlib_compress failed");
  out.resize(size);
  return out;
}
}  // namespace

std::vector<std::byte> encode_chunk(std::span<const double> values, int deflate) {
  return shuffle_deflate(reinterpret_cast<const unsigned char*>(values.data()), values.size(), sizeof(double), deflate);
}
std::vector<std::byte> encode_chunk(std::span<const float> values, int deflate) {
  return shuffle_deflate(reinterpret_cast<const unsigned char*>(values.data()), values.size(), sizeof(float), deflate);
}

void Dataset::write_region(const Dims& offset, const Dims& count, std::span<const std::int32_t> data) {
  write_region_impl(*this, handle_.get(), offset, count, data.data(), data.size(), H5T_NATIVE_INT32);
}
void Dataset::write_region(const Dims& offset, const Dims& count, std::span<const std::int64_t> data) {
  write_region_impl(*this, handle_.get(), offset, count, data.data(), data.size(), H5T_NATIVE_INT64);
}

Dataset Group::write_dataset(std::string_view path, std::span<const double> data, const Dims& dims) {
  std::string full = child_path(path);
  Handle ds = create_and_write(*this, path, full, data.data(), data.size(), dims, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE);
  return Dataset(std::move(ds), file_, std::move(full));
}

Dataset Group::write_dataset(std::string_view path, std::span<const std::int64_t> data, const Dims& dims) {
  std::string full = child_path(path);
  Handle ds = create_and_write(*this, path, full, data.data(), data.size(), dims, H5T_STD_I64LE, H5T_NATIVE_INT64);
  return Dataset(std::move(ds), file_, std::move(full));
}

Dataset Group::write_dataset(std::string_view path, std::span<const std::int32_t> data, const Dims& dims) {
  std::string full = child_path(path);
  Handle ds = create_and_write(*this, path, full, data.data(), data.size(), dims, H5T_STD_I32LE, H5T_NATIVE_INT32);
  return Dataset(std::move(ds), file_, std::move(full));
}

Dataset Group::write_dataset(std::string_view path, std::span<const std::int8_t> data) {
  std::string full = child_path(path);
  Handle ds = create_and_write(*this, path, full, data.data(), data.size(), {data.size()}, H5T_STD_I8LE, H5T_NATIVE_INT8);
  return Dataset(std::move(ds), file_, std::move(full));
}

Dataset Group::write_dataset(std::string_view path, std::span<const std::string> data) {
  std::string full = child_path(path);
  Where w{file_name(), full};
  Handle type = utf8_string_type(w);
  Handle space = make_space({data.size()}, w);
  Handle lcpl = intermediate_lcpl(w);
  std::string p(path);
  Handle ds = own(H5Dcreate2(handle_.get(), p.c_str(), type.get(), space.get(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT),
                  Kind::Dataset, "H5Dcreate2", w);
  std::vector<const char*> ptrs;
  for (const std::string& v : data) ptrs.push_back(v.c_str());
  if (!ptrs.empty()) check(H5Dwrite(ds.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data()), "H5Dwrite", w);
  return Dataset(std::move(ds), file_, std::move(full));
}

Dataset Group::write_string_dataset(std::string_view path, std::string_view text) {
  std::string full = child_path(path);
  Where w{file_name(), full};
  Handle type = utf8_string_type(w);
  Handle space = make_space({}, w);
  Handle lcpl = intermediate_lcpl(w);
  std::string p(path);
  Handle ds = own(H5Dcreate2(handle_.get(), p.c_str(), type.get(), space.get(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT),
                  Kind::Dataset, "H5Dcreate2", w);
  std::string copy(text);
  const char* ptr = copy.c_str();
  check(H5Dwrite(ds.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &ptr), "H5Dwrite", w);
  return Dataset(std::move(ds), file_, std::move(full));
}

Dataset Group::open_dataset(std::string_view path) const {
  std::string full = child_path(path);
  std::string p(path);
  Handle ds = own(H5Dopen2(handle_.get(), p.c_str(), H5P_DEFAULT), Kind::Dataset, "H5Dopen2", Where{file_name(), full});
  return Dataset(std::move(ds), file_, std::move(full));
}

// ---------------------------------------------------------------------------------------------
// File

namespace {

enum class OpenMode { Create, Read, ReadWrite };

Handle open_file(const fs::path& disk, OpenMode mode) {
  init_library();
  std::string name = disk.string();
  Where w{name, "/"};
  // Strong close degree: closing the file closes every object in it, so the file is complete
  // on disk as soon as the File is closed (needed before a temporary file is renamed).
  Handle fapl = own(H5Pcreate(H5P_FILE_ACCESS), Kind::PropertyList, "H5Pcreate", w);
  check(H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG), "H5Pset_fclose_degree", w);
  switch (mode) {
    case OpenMode::Create:
      return own(H5Fcreate(name.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), Kind::File, "H5Fcreate", w);
    case OpenMode::Read:
      return own(H5Fopen(name.c_str(), H5F_ACC_RDONLY, fapl.get()), Kind::File, "H5Fopen", w);
    case OpenMode::ReadWrite:
      return own(H5Fopen(name.c_str(), H5F_ACC_RDWR, fapl.get()), Kind::File, "H5Fopen", w);
  }
  throw std::logic_error("open_file: bad mode");
}

}  // namespace

File::File(Handle h, std::shared_ptr<FileState> state, fs::path final_path, bool temporary)
    : Group(std::move(h), std::move(state), "/"), final_path_(std::move(final_path)), temporary_(temporary) {}

File::File(File&& other) noexcept
    : Group(std::move(other)),
      final_path_(std::move(other.final_path_)),
      temporary_(std::exchange(other.temporary_, false)),
      committed_(std::exchange(other.committed_, false)) {}

File& File::operator=(File&& other) noexcept {
  if (this != &other) {
    release();
    Group::operator=(std::move(other));
    final_path_ = std::move(other.final_path_);
    temporary_ = std::exchange(other.temporary_, false);
    committed_ = std::exchange(other.committed_, false);
  }
  return *this;
}

File::~File() { release(); }

void File::release() noexcept {
  if (temporary_ && !committed_) {
    discard();
  } else if (file_ && handle_.valid()) {
    file_->open = false;
    handle_.reset();
  }
}

File File::create(const fs::path& path) {
  return File(open_file(path, OpenMode::Create), std::make_shared<FileState>(path.string()), path, false);
}

File File::create_temporary(const fs::path& path) {
  fs::path part = part_path(path);
  return File(open_file(part, OpenMode::Create), std::make_shared<FileState>(part.string()), path, true);
}

File File::open_read(const fs::path& path) {
  return File(open_file(path, OpenMode::Read), std::make_shared<FileState>(path.string()), path, false);
}

File File::open_rw(const fs::path& path) {
  return File(open_file(path, OpenMode::ReadWrite), std::make_shared<FileState>(path.string()), path, false);
}

fs::path File::disk_path() const { return temporary_ && !committed_ ? part_path(final_path_) : final_path_; }

void File::flush() {
  check(H5Fflush(handle_.get(), H5F_SCOPE_GLOBAL), "H5Fflush", Where{file_name(), "/"});
}

void File::discard() noexcept {
  if (file_) file_->open = false;
  handle_.reset();
  std::error_code ec;
  fs::remove(part_path(final_path_), ec);
  temporary_ = false;
}

void File::commit() {
  if (!temporary_ || committed_) {
    throw std::logic_error(fmt::format("File::commit: {} is not an uncommitted temporary file", final_path_.string()));
  }
  if (!handle_.valid()) throw std::logic_error(fmt::format("File::commit: {} is closed", file_name()));
  Where w{file_name(), "/"};
  check(H5Fflush(handle_.get(), H5F_SCOPE_GLOBAL), "H5Fflush", w);
  file_->open = false;
  if (!handle_.close()) fail("H5Fclose", w);
  fs::path part = part_path(final_path_);
  sync_path(part, false);
  std::error_code ec;
  fs::rename(part, final_path_, ec);
  if (ec) throw Hdf5Error(fmt::format("rename failed for {} -> {}: {}", part.string(), final_path_.string(), ec.message()));
  committed_ = true;
  file_->name = final_path_.string();
  fs::path dir = final_path_.parent_path();
  sync_path(dir.empty() ? fs::path(".") : dir, true);
}

void File::close() {
  if (temporary_ && !committed_) {
    discard();
    return;
  }
  if (!handle_.valid()) return;
  file_->open = false;
  if (!handle_.close()) fail("H5Fclose", Where{file_name(), "/"});
}

}  // namespace ajx::io
