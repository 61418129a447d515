#include "io/hdf5_file.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <filesystem>
#include <limits>
#include <numeric>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using ajx::io::Dataset;
using ajx::io::Dims;
using ajx::io::DType;
using ajx::io::File;
using ajx::io::Group;
using ajx::io::Hdf5Error;

namespace {

// A fresh directory per test, removed afterwards.
class Hdf5FileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           (std::string("ajx_hdf5_test_") + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add, ec);
    fs::remove_all(dir_, ec);
  }
  fs::path file(const std::string& name) const { return dir_ / name; }

  fs::path dir_;
};

template <class Fn>
std::string error_message(Fn&& fn) {
  try {
    fn();
  } catch (const Hdf5Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected Hdf5Error";
  return {};
}

bool h5dump_available() { return std::system("command -v h5dump >/dev/null 2>&1") == 0; }

}  // namespace

TEST_F(Hdf5FileTest, AttributesOfEveryTypeRoundTrip) {
  const fs::path p = file("attrs.h5");
  const std::string toml = "[run]\nname = \"x\"\n# ünïcode\ndt = 1e-3\n";
  {
    File f = File::create(p);
    f.set_attribute("title", "astrojax run");
    f.set_attribute("config_toml", std::string_view(toml));
    f.set_attribute("empty", "");
    f.set_attribute("g", 9.81);
    f.set_attribute("seed", std::int64_t{-1234567890123});
    f.set_attribute("small_int", 7);  // int goes through the int64 overload
    f.set_attribute("vec", std::vector<double>{1.0, -2.5, 3e-300});
    f.set_attribute("empty_vec", std::vector<double>{});
    f.set_attribute("g", 9.80665);  // replaces
    Group g = f.create_group("params/drive");
    g.set_attribute("units", "m");
    g.set_attribute("omega", 12.5);
  }
  File f = File::open_read(p);
  EXPECT_EQ(f.read_string_attribute("title"), "astrojax run");
  EXPECT_EQ(f.read_string_attribute("config_toml"), toml);
  EXPECT_EQ(f.read_string_attribute("empty"), "");
  EXPECT_EQ(f.read_double_attribute("g"), 9.80665);
  EXPECT_EQ(f.read_int64_attribute("seed"), -1234567890123);
  EXPECT_EQ(f.read_int64_attribute("small_int"), 7);
  EXPECT_EQ(f.read_doubles_attribute("vec"), (std::vector<double>{1.0, -2.5, 3e-300}));
  EXPECT_TRUE(f.read_doubles_attribute("empty_vec").empty());
  EXPECT_TRUE(f.has_attribute("title"));
  EXPECT_FALSE(f.has_attribute("nope"));
  // Numeric conversion on read.
  EXPECT_EQ(f.read_double_attribute("small_int"), 7.0);

  Group g = f.open_group("params/drive");
  EXPECT_EQ(g.path(), "/params/drive");
  EXPECT_EQ(g.read_string_attribute("units"), "m");
  EXPECT_EQ(g.read_double_attribute("omega"), 12.5);

  // Wrong kinds / missing attributes are errors naming the attribute.
  std::string msg = error_message([&] { (void)g.read_double_attribute("missing"); });
  EXPECT_NE(msg.find("H5Aopen"), std::string::npos) << msg;
  EXPECT_NE(msg.find("/params/drive@missing"), std::string::npos) << msg;
  EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
  msg = error_message([&] { (void)f.read_string_attribute("g"); });
  EXPECT_NE(msg.find("not a string"), std::string::npos) << msg;
  msg = error_message([&] { (void)f.read_double_attribute("vec"); });
  EXPECT_NE(msg.find("expected a single one"), std::string::npos) << msg;
}

TEST_F(Hdf5FileTest, GroupsNestedAndExists) {
  File f = File::create(file("groups.h5"));
  EXPECT_TRUE(f.exists("/"));
  EXPECT_FALSE(f.exists("a"));
  Group b = f.create_group("a/b");
  EXPECT_EQ(b.path(), "/a/b");
  EXPECT_TRUE(f.exists("a"));
  EXPECT_TRUE(f.exists("a/b"));
  EXPECT_TRUE(f.exists("/a/b"));
  EXPECT_FALSE(f.exists("a/b/c"));
  EXPECT_FALSE(f.exists("x/y/z"));
  Group c = b.create_group("c");
  EXPECT_EQ(c.path(), "/a/b/c");
  EXPECT_TRUE(b.exists("c"));
  EXPECT_TRUE(f.exists("a/b/c"));

  // A dataset is a link too, but one cannot descend into it.
  b.write_dataset("d", std::vector<double>{1, 2});
  EXPECT_TRUE(f.exists("a/b/d"));
  EXPECT_FALSE(f.exists("a/b/d/e"));

  // create fails on an existing group; require opens it.
  std::string msg = error_message([&] { f.create_group("a/b"); });
  EXPECT_NE(msg.find("H5Gcreate2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'/a/b'"), std::string::npos) << msg;
  Group again = f.require_group("a/b");
  EXPECT_EQ(again.path(), "/a/b");
  Group fresh = f.require_group("new/one");
  EXPECT_TRUE(f.exists("new/one"));
  msg = error_message([&] { (void)f.open_group("missing/group"); });
  EXPECT_NE(msg.find("H5Gopen2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("/missing/group"), std::string::npos) << msg;
}

TEST_F(Hdf5FileTest, WholeDatasetsRoundTrip) {
  const fs::path p = file("datasets.h5");
  const std::vector<double> m = {1.0, 2.0, 3.0, 4.0, 5.0, 6.0};  // 2 x 3
  const std::vector<std::int64_t> i64 = {std::numeric_limits<std::int64_t>::min(), 0,
                                         std::numeric_limits<std::int64_t>::max()};
  const std::vector<std::int32_t> i32 = {-7, 8, 9, 10};  // 2 x 2
  const std::string text(100000, 'x');
  {
    File f = File::create(p);
    Dataset d = f.write_dataset("results/matrix", m, {2, 3});
    EXPECT_EQ(d.path(), "/results/matrix");
    d.set_attribute("units", "m/s");
    d.set_attribute("description", "velocity of bob 1");
    d.set_attribute("scale", std::vector<double>{0.5, 2.0});
    f.write_dataset("results/i64", i64);
    f.write_dataset("results/i32", i32, {2, 2});
    f.write_dataset("results/scalar", std::vector<double>{42.0}, {});
    f.write_dataset("results/empty", std::vector<double>{}, {0, 3});
    f.write_string_dataset("config/toml", text);
    f.write_string_dataset("config/short", "a = 1\n");
    f.flush();
  }
  File f = File::open_read(p);
  auto a = f.read_doubles("results/matrix");
  EXPECT_EQ(a.dims, (Dims{2, 3}));
  EXPECT_EQ(a.data, m);
  EXPECT_EQ(a.rows(), 2u);
  EXPECT_EQ(a.cols(), 3u);
  EXPECT_EQ(a(1, 2), 6.0);

  Dataset d = f.open_dataset("results/matrix");
  EXPECT_EQ(d.dims(), (Dims{2, 3}));
  EXPECT_EQ(d.read_string_attribute("units"), "m/s");
  EXPECT_EQ(d.read_string_attribute("description"), "velocity of bob 1");
  EXPECT_EQ(d.read_doubles_attribute("scale"), (std::vector<double>{0.5, 2.0}));

  auto b = f.read_int64s("results/i64");
  EXPECT_EQ(b.dims, (Dims{3}));
  EXPECT_EQ(b.data, i64);
  auto c = f.read_int32s("results/i32");
  EXPECT_EQ(c.dims, (Dims{2, 2}));
  EXPECT_EQ(c.data, i32);
  auto c_as_double = f.read_doubles("results/i32");  // converted by HDF5
  EXPECT_EQ(c_as_double.data, (std::vector<double>{-7, 8, 9, 10}));
  auto s = f.read_doubles("results/scalar");
  EXPECT_TRUE(s.dims.empty());
  EXPECT_EQ(s.data, (std::vector<double>{42.0}));
  auto e = f.read_doubles("results/empty");
  EXPECT_EQ(e.dims, (Dims{0, 3}));
  EXPECT_TRUE(e.data.empty());
  EXPECT_EQ(e.cols(), 3u);
  EXPECT_EQ(f.read_string_dataset("config/toml"), text);
  EXPECT_EQ(f.read_string_dataset("config/short"), "a = 1\n");
}

TEST_F(Hdf5FileTest, DatasetArgumentAndDuplicateErrors) {
  const fs::path p = file("errors.h5");
  File f = File::create(p);
  EXPECT_THROW(f.write_dataset("bad", std::vector<double>{1, 2, 3}, {2, 2}), std::invalid_argument);
  f.write_dataset("trajectory/r1", std::vector<double>{1, 2, 3}, {1, 3});
  std::string msg = error_message([&] { f.write_dataset("trajectory/r1", std::vector<double>{1}); });
  EXPECT_NE(msg.find("H5Dcreate2 failed for '/trajectory/r1' in " + p.string()), std::string::npos) << msg;
  msg = error_message([&] { (void)f.read_doubles("trajectory/nope"); });
  EXPECT_NE(msg.find("H5Dopen2 failed for '/trajectory/nope'"), std::string::npos) << msg;
  msg = error_message([&] { (void)f.read_string_dataset("trajectory/r1"); });
  EXPECT_NE(msg.find("not a string"), std::string::npos) << msg;
}

TEST_F(Hdf5FileTest, OpeningMissingFileThrowsWithPath) {
  const fs::path p = file("does_not_exist.h5");
  for (auto open : {&File::open_read, &File::open_rw}) {
    std::string msg = error_message([&] { (void)open(p); });
    EXPECT_NE(msg.find("H5Fopen"), std::string::npos) << msg;
    EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
  }
  // Not an HDF5 file at all.
  const fs::path junk = file("junk.h5");
  { std::ofstream(junk) << "not hdf5"; }
  std::string msg = error_message([&] { (void)File::open_read(junk); });
  EXPECT_NE(msg.find(junk.string()), std::string::npos) << msg;
}

TEST_F(Hdf5FileTest, WritingIntoUnwritableDirectoryThrowsWithPath) {
  const fs::path missing_dir = file("no_such_dir") / "run.h5";
  std::string msg = error_message([&] { (void)File::create(missing_dir); });
  EXPECT_NE(msg.find("H5Fcreate"), std::string::npos) << msg;
  EXPECT_NE(msg.find(missing_dir.string()), std::string::npos) << msg;
  msg = error_message([&] { (void)File::create_temporary(missing_dir); });
  EXPECT_NE(msg.find(missing_dir.string()), std::string::npos) << msg;
}

TEST_F(Hdf5FileTest, WritingIntoReadOnlyDirectoryThrowsWithPath) {
  if (::geteuid() == 0) GTEST_SKIP() << "running as root: permission bits are not enforced";
  const fs::path ro = file("read_only");
  fs::create_directories(ro);
  fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec);
  const std::string msg = error_message([&] { (void)File::create(ro / "run.h5"); });
  EXPECT_NE(msg.find((ro / "run.h5").string()), std::string::npos) << msg;
}

TEST_F(Hdf5FileTest, TemporaryFileWithoutCommitLeavesNothing) {
  const fs::path p = file("run.h5");
  const fs::path part = file("run.h5.part");
  {
    File f = File::create_temporary(p);
    EXPECT_TRUE(f.is_temporary());
    EXPECT_EQ(f.disk_path(), part);
    EXPECT_EQ(f.final_path(), p);
    auto t = f.write_dataset("trajectory/r1", std::vector<double>{1, 2, 3}, {1, 3});
    f.flush();
    EXPECT_TRUE(fs::exists(part));
    EXPECT_FALSE(fs::exists(p));
  }  // destroyed without commit (the dataset outlives the file here: harmless)
  EXPECT_FALSE(fs::exists(part));
  EXPECT_FALSE(fs::exists(p));

  // An existing final file is left untouched by an abandoned temporary.
  { File::create(p).set_attribute("version", 1); }
  {
    File f = File::create_temporary(p);
    f.set_attribute("version", 2);
    f.close();  // explicit close without commit discards as well
    EXPECT_FALSE(fs::exists(part));
  }
  EXPECT_EQ(File::open_read(p).read_int64_attribute("version"), 1);

  // write_atomically: an exception inside the callback leaves nothing new.
  fs::remove(p);
  EXPECT_THROW(ajx::io::write_atomically(p,
                                         [](File& f) {
                                           f.set_attribute("x", 1.0);
                                           throw std::runtime_error("simulated crash");
                                         }),
               std::runtime_error);
  EXPECT_FALSE(fs::exists(part));
  EXPECT_FALSE(fs::exists(p));
}

TEST_F(Hdf5FileTest, TemporaryFileCommitRenames) {
  const fs::path p = file("run.h5");
  const fs::path part = file("run.h5.part");
  {
    File f = File::create_temporary(p);
    std::vector<double> rows;
    for (int i = 0; i < 10; ++i) rows.insert(rows.end(), {1.0 * i, 0, 0});
    auto r1 = f.write_dataset("trajectory/r1", std::span<const double>(rows), {10, 3});
    f.write_string_dataset("config", "x = 1");
    File moved = std::move(f);  // ownership of the temporary moves with the object
    moved.commit();
    EXPECT_FALSE(fs::exists(part));
    EXPECT_TRUE(fs::exists(p));
    EXPECT_EQ(moved.disk_path(), p);
    EXPECT_FALSE(moved.is_open());
    // The dataset was closed with the file: using it is a clean error.
    EXPECT_THROW(r1.set_attribute("units", "m"), Hdf5Error);
    EXPECT_THROW(moved.commit(), std::logic_error);
  }
  EXPECT_TRUE(fs::exists(p));  // destructor after commit keeps the file
  File f = File::open_read(p);
  EXPECT_EQ(f.read_doubles("trajectory/r1").dims, (Dims{10, 3}));
  EXPECT_EQ(f.read_string_dataset("config"), "x = 1");

  // write_atomically replaces an existing file only on success.
  ajx::io::write_atomically(p, [](File& out) { out.set_attribute("generation", 2); });
  EXPECT_EQ(File::open_read(p).read_int64_attribute("generation"), 2);
  EXPECT_FALSE(fs::exists(part));
}

TEST_F(Hdf5FileTest, H5dumpReadsTheFile) {
  if (!h5dump_available()) GTEST_SKIP() << "h5dump not on PATH";
  const fs::path p = file("dump.h5");
  {
    File f = File::create(p);
    f.set_attribute("config_toml", "[run]\nt_end = 10.0\n");
    auto t = f.create_filled("trajectory/r1", {20, 3}, DType::Float64, 0.0, {8, 3}, 6);
    t.set_attribute("units", "m");
    for (int i = 0; i < 20; ++i)
      t.write_region({std::size_t(i), 0}, {1, 3}, std::vector<double>{0.25 * i, 1.0, 2.0});
    f.write_dataset("ints", std::vector<std::int32_t>{1, 2, 3, 4, 5, 6}, {3, 2});
  }
  const fs::path out = file("dump.txt");
  const std::string cmd = "h5dump '" + p.string() + "' > '" + out.string() + "' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream in(out);
  const std::string dump((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(dump.find("DATASET \"r1\""), std::string::npos) << dump;
  EXPECT_NE(dump.find("( 20, 3 ) / ( 20, 3 )"), std::string::npos) << dump;
  EXPECT_NE(dump.find("4.75"), std::string::npos) << dump;
  EXPECT_NE(dump.find("\"m\""), std::string::npos) << dump;
  EXPECT_NE(dump.find("t_end = 10.0"), std::string::npos) << dump;
}

TEST_F(Hdf5FileTest, FilledDatasetsTakeRegionsAndReadFillElsewhere) {
  const fs::path p = file("filled.h5");
  {
    File f = File::create(p);
    auto d = f.create_filled("r/x", {3, 4, 2}, DType::Float64, std::numeric_limits<double>::quiet_NaN(), {1, 4, 2}, 4);
    const std::vector<double> block{1, 2, 3, 4, 5, 6};  // one (1, 3, 2) block
    d.write_region({1, 1, 0}, {1, 3, 2}, std::span<const double>(block));
    auto c = f.create_filled("r/c", {3, 4}, DType::Int32, -1.0, {1, 4});
    const std::vector<std::int32_t> row{7, 8, 9, 10};
    c.write_region({2, 0}, {1, 4}, std::span<const std::int32_t>(row));
    EXPECT_THROW(c.write_region({0, 0}, {1, 3}, std::span<const std::int32_t>(row)), std::invalid_argument);
    f.flush();
  }
  File f = File::open_read(p);
  const auto x = f.read_doubles("r/x");
  ASSERT_EQ(x.dims, (Dims{3, 4, 2}));
  for (std::size_t i = 0; i < x.data.size(); ++i) {
    const std::size_t a = i / 8, b = (i / 2) % 4, k = i % 2;
    if (a == 1 && b >= 1) {
      EXPECT_EQ(x.data[i], double(2 * (b - 1) + k + 1)) << i;
    } else {
      EXPECT_TRUE(std::isnan(x.data[i])) << i;
    }
  }
  const auto c = f.read_int32s("r/c");
  EXPECT_EQ(c.data, (std::vector<std::int32_t>{-1, -1, -1, -1, -1, -1, -1, -1, 7, 8, 9, 10}));
}

TEST_F(Hdf5FileTest, ChunksEncodedOutsideHdf5ReadBackThroughItsFilters) {
  // encode_chunk must reproduce HDF5's own shuffle + deflate pipeline byte for byte in
  // meaning: what write_chunk stores, HDF5 reads back through its filters exactly, and a chunk
  // written by write_region holds the same values.
  const fs::path p = file("chunks.h5");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> v(12);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::sin(0.3 * double(i)) * 1e3 + double(i);
  v[11] = nan;  // padding past a window's samples
  {
    File f = File::create(p);
    auto direct = f.create_filled("direct", {2, 3, 12}, DType::Float64, nan, {1, 1, 12}, 4);
    auto region = f.create_filled("region", {2, 3, 12}, DType::Float64, nan, {1, 1, 12}, 4);
    direct.write_chunk({1, 2, 0}, ajx::io::encode_chunk(std::span<const double>(v), 4));
    region.write_region({1, 2, 0}, {1, 1, 12}, std::span<const double>(v));
    f.flush();
  }
  File f = File::open_read(p);
  const auto a = f.read_doubles("direct"), b = f.read_doubles("region");
  ASSERT_EQ(a.data.size(), 72u);
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    if (std::isnan(b.data[i])) {
      EXPECT_TRUE(std::isnan(a.data[i])) << i;
    } else {
      EXPECT_EQ(a.data[i], b.data[i]) << i;  // bit-exact: the filters are lossless
    }
  }
  EXPECT_EQ(a.data[5 * 12 + 3], v[3]);
}

TEST_F(Hdf5FileTest, Float32ChunksEncodedOutsideHdf5ReadBackAsTheFloatsWritten) {
  // The float32 sample columns: a chunk of floats through shuffle (4 bytes) + deflate reads
  // back, converted to double, as exactly the floats written; NaN padding stays NaN.
  const fs::path p = file("chunks32.h5");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> v(12);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = float(std::sin(0.3 * double(i)) * 1e3 + double(i));
  v[10] = v[11] = nan;
  {
    File f = File::create(p);
    auto d = f.create_filled("direct", {2, 12}, DType::Float32, std::numeric_limits<double>::quiet_NaN(), {1, 12}, 1);
    d.write_chunk({1, 0}, ajx::io::encode_chunk(std::span<const float>(v), 1));
    f.flush();
  }
  File f = File::open_read(p);
  const auto a = f.read_doubles("direct");
  ASSERT_EQ(a.data.size(), 24u);
  for (std::size_t i = 0; i < 12; ++i) {
    EXPECT_TRUE(std::isnan(a.data[i])) << i;  // the chunk never written: the fill value
    if (std::isnan(v[i]))
      EXPECT_TRUE(std::isnan(a.data[12 + i])) << i;
    else
      EXPECT_EQ(a.data[12 + i], double(v[i])) << i;
  }
}

TEST_F(Hdf5FileTest, AByteChangedOnDiskFailsItsChecksum) {
  // Whole arrays and filled datasets without deflate carry a Fletcher32 per
  // chunk: one byte changed in the stored values makes the read throw instead of returning a
  // wrong value. The values are found in the file by their bytes (they are stored raw).
  const fs::path p = file("sums.h5");
  const auto values = [](double base) {
    std::vector<double> v(30);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = base + 0.125 * double(i);
    return v;
  };
  const std::vector<double> whole = values(1234.5), filled = values(-777.25), table = values(4242.75);
  {
    File f = File::create(p);
    f.write_dataset("whole", std::span<const double>(whole), Dims{10, 3});
    f.create_filled("filled", {2, 30}, DType::Float64, 0.0, {1, 30})
        .write_region({1, 0}, {1, 30}, std::span<const double>(filled));
    Group g = f.create_group("g");
    g.write_dataset("table", std::span<const double>(table), Dims{10, 3});
    EXPECT_TRUE(f.create_filled("deflated", {2, 8}, DType::Float64, 0.0, {1, 8}, 4).checksummed());
    f.close();
  }
  std::vector<char> bytes;
  {
    std::ifstream in(p, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  for (const auto& [name, v] : {std::pair{"whole", whole}, {"filled", filled}, {"g/table", table}}) {
    SCOPED_TRACE(name);
    EXPECT_TRUE(File::open_read(p).open_dataset(name).checksummed());
    EXPECT_EQ(File::open_read(p).read_doubles(name).data.size() % v.size(), 0u);
    const char* first = reinterpret_cast<const char*>(&v[7]);
    const auto at = std::search(bytes.begin(), bytes.end(), first, first + sizeof(double));
    ASSERT_NE(at, bytes.end());
    std::vector<char> flipped = bytes;
    flipped[std::size_t(at - bytes.begin()) + 3] ^= 0x10;
    const fs::path q = file(std::string("flipped_") + (name[0] == 'g' ? "table" : name) + ".h5");
    std::ofstream(q, std::ios::binary).write(flipped.data(), std::streamsize(flipped.size()));
    try {
      (void)File::open_read(q).read_doubles(name);
      ADD_FAILURE() << "a changed byte was read back without an error";
    } catch (const Hdf5Error& e) {
      EXPECT_NE(std::string(e.what()).find("Fletcher32"), std::string::npos) << e.what();
    }
  }
}

// Format 3's lists: 1-D attributes and datasets of variable-length UTF-8 strings, any item
// (newlines, NUL-free control characters, empty strings, an empty list) read back as written.
TEST_F(Hdf5FileTest, StringListsRoundTrip) {
  const std::vector<std::string> items{"first", "two\nlines", "", "c_D × 1.2 — µ", std::string(10240, 'x')};
  const std::vector<std::string> none;
  {
    File f = File::create(file("s.h5"));
    f.set_attribute("items", std::span<const std::string>(items));
    f.set_attribute("none", std::span<const std::string>(none));
    f.write_dataset("names", std::span<const std::string>(items));
    const std::vector<std::int8_t> flags{1, 0, -1};
    f.write_dataset("flags", std::span<const std::int8_t>(flags));
  }
  const File f = File::open_read(file("s.h5"));
  EXPECT_EQ(f.read_strings_attribute("items"), items);
  EXPECT_EQ(f.read_strings_attribute("none"), none);
  EXPECT_EQ(f.attribute_dims("items"), Dims{items.size()});
  EXPECT_EQ(f.attribute_type_class("items"), ajx::io::TypeClass::String);
  EXPECT_EQ(f.open_dataset("names").read_strings(), items);
  EXPECT_EQ(f.open_dataset("flags").type_class(), ajx::io::TypeClass::Integer);
  EXPECT_EQ(f.read_int32s("flags").data, (std::vector<std::int32_t>{1, 0, -1}));
}
