#include "results/sweep_result.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "io/hdf5_file.hpp"
#include "sweep/codec.hpp"

namespace ajx::results {

WindowRow window_row(const sweep::OrbitClassification& c) {
  const auto& s = c.stats;
  WindowRow r;
  r.cls = static_cast<std::int32_t>(c.cls);
  for (std::size_t k = 0; k < kNumStats; ++k) r.stats[k] = kStats[k].of(c);
  std::copy(std::begin(s.mode_fraction), std::end(s.mode_fraction), r.mode_fraction.begin());
  return r;
}

void round_to_stored(sweep::WindowRecord& rec) {
  std::vector<double>* columns[] = {&rec.t, &rec.omega_m, &rec.L1, &rec.T1, &rec.T2, nullptr, &rec.r1, &rec.r2};
  for (std::size_t k = 0; k < kNumSampleColumns; ++k)
    if (kSampleFloat32[k] && columns[k])
      for (double& v : *columns[k]) v = double(float(v));
}

namespace {

// One column's first `values` entries as a chunk of `size` (NaN beyond), in its stored type.
template <class T>
std::vector<std::byte> chunk_of(std::span<const double> values, std::size_t size) {
  std::vector<T> chunk(size, std::numeric_limits<T>::quiet_NaN());
  std::copy(values.begin(), values.end(), chunk.begin());
  return io::encode_chunk(std::span<const T>(chunk), kSampleDeflate);
}
}  // namespace

TaskResult make_result(const sweep::ChainSetup& chain, sweep::TaskOutput out, std::size_t cap) {
  for (sweep::WindowRecord& rec : out.windows) round_to_stored(rec);
  const std::vector<sweep::OrbitClassification> classes = sweep::classify_windows(chain, out);
  TaskResult r;
  for (std::size_t i = 0; i < out.windows.size(); ++i) {
    const sweep::WindowRecord& rec = out.windows[i];
    WindowResult w;
    w.index = rec.index;
    w.count = std::int32_t(std::min(rec.size(), cap));
    w.row = window_row(classes[i]);
    const sweep::WindowPowers p = sweep::window_powers(rec);
    for (std::size_t k = 0; k < kNumPowers; ++k) w.powers[k] = kPowers[k].of(p);
    const auto n = std::size_t(w.count);
    if (n > 0) {
      std::vector<double> mode(rec.mode.begin(), rec.mode.begin() + long(n));
      const std::vector<double>* columns[] = {&rec.t, &rec.omega_m, &rec.L1, &rec.T1, &rec.T2, &mode, &rec.r1, &rec.r2};
      for (std::size_t k = 0; k < kNumSampleColumns; ++k) {
        const std::size_t width = k < 6 ? 1 : 3;  // r1 and r2: three components per sample
        const std::span<const double> values(columns[k]->data(), width * n);
        w.chunks.push_back(kSampleFloat32[k] ? chunk_of<float>(values, width * cap) : chunk_of<double>(values, width * cap));
      }
    }
    r.windows.push_back(std::move(w));
  }
  out.windows.clear();
  r.summary = std::move(out);
  return r;
}

std::vector<std::byte> encode(const TaskResult& r) {
  sweep::ByteWriter w;
  w.put_vector(sweep::encode(r.summary));
  w.put<std::uint64_t>(r.windows.size());
  for (const WindowResult& x : r.windows) {
    w.put(x.index);
    w.put(x.count);
    w.put(x.row.cls);
    w.put(x.row.stats);
    w.put(x.row.mode_fraction);
    w.put(x.powers);
    w.put<std::uint64_t>(x.chunks.size());
    for (const auto& c : x.chunks) w.put_vector(c);
  }
  return w.take();
}

TaskResult decode_result(std::span<const std::byte> bytes) {
  sweep::ByteReader rd(bytes.data(), bytes.size());
  TaskResult r;
  r.summary = sweep::decode_output(rd.get_vector<std::byte>());
  r.windows.resize(rd.get<std::uint64_t>());
  for (WindowResult& x : r.windows) {
    x.index = rd.get<std::int32_t>();
    x.count = rd.get<std::int32_t>();
    x.row.cls = rd.get<std::int32_t>();
    x.row.stats = rd.get<decltype(x.row.stats)>();
    x.row.mode_fraction = rd.get<decltype(x.row.mode_fraction)>();
    x.powers = rd.get<decltype(x.powers)>();
    x.chunks.resize(rd.get<std::uint64_t>());
    for (auto& c : x.chunks) c = rd.get_vector<std::byte>();
  }
  if (!rd.done()) throw std::runtime_error("sweep result: trailing bytes");
  return r;
}

}  // namespace ajx::results
