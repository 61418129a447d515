// The sample chunks' compression measured on a sweep file's own samples: for every window and
// every /samples column, the chunk as a sweep writes it (byte shuffle, then deflate at level 1)
// in float64 and in float32 (t always float64), through zlib's compress2 and through libdeflate
// (io::encode_chunk). Prints the bytes out and the CPU time of each; asserts nothing.
// Run:  build/tests/bench/chunk_compression out/paper.h5
#include <zlib.h>

#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "results/sweep_result.hpp"
#include "io/hdf5_file.hpp"

namespace {

// Shuffle + zlib's compress2, the pipeline before libdeflate.
std::size_t zlib_chunk(const unsigned char* in, std::size_t n, std::size_t B) {
  std::vector<unsigned char> shuffled(n * B);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < B; ++j) shuffled[j * n + i] = in[i * B + j];
  uLongf size = compressBound(uLong(shuffled.size()));
  std::vector<unsigned char> out(size);
  compress2(out.data(), &size, shuffled.data(), uLong(shuffled.size()), ajx::results::kSampleDeflate);
  return size;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s SWEEP.h5\n", argv[0]);
    return 2;
  }
  using namespace ajx;
  const io::File f = io::File::open_read(argv[1]);
  // Every window's chunk of every column, as doubles (the chunk shape is a window's cap).
  std::vector<std::vector<double>> chunks;
  std::vector<bool> float32;
  for (std::size_t k = 0; k < results::kNumSampleColumns; ++k) {
    const auto a = f.read_doubles(std::string("samples/") + results::kSampleColumns[k]);
    std::size_t per = a.dims[2] * (a.dims.size() > 3 ? a.dims[3] : 1);
    for (std::size_t at = 0; at + per <= a.data.size(); at += per) {
      chunks.emplace_back(a.data.begin() + long(at), a.data.begin() + long(at + per));
      float32.push_back(results::kSampleFloat32[k]);
    }
  }
  std::printf("%zu chunks\n%-28s %12s %10s\n", chunks.size(), "pipeline", "bytes out", "CPU [s]");
  for (const bool narrow : {false, true})
    for (const bool zlib : {true, false}) {
      const std::clock_t t0 = std::clock();
      std::size_t bytes = 0;
      for (std::size_t c = 0; c < chunks.size(); ++c) {
        const std::vector<double>& v = chunks[c];
        if (narrow && float32[c]) {
          const std::vector<float> w(v.begin(), v.end());
          bytes += zlib ? zlib_chunk(reinterpret_cast<const unsigned char*>(w.data()), w.size(), 4)
                        : io::encode_chunk(std::span<const float>(w), results::kSampleDeflate).size();
        } else {
          bytes += zlib ? zlib_chunk(reinterpret_cast<const unsigned char*>(v.data()), v.size(), 8)
                        : io::encode_chunk(std::span<const double>(v), results::kSampleDeflate).size();
        }
      }
      std::printf("%-28s %12zu %10.3f\n",
                  (std::string(narrow ? "float32" : "float64") + (zlib ? " + zlib compress2" : " + libdeflate")).c_str(),
                  bytes, double(std::clock() - t0) / CLOCKS_PER_SEC);
    }
  return 0;
}
