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

TaskResult probe_result(sweep::Probe p) {
  TaskResult r;
  ProbeRecord& rec = r.probe.emplace();
  rec.ran = p.ran ? 1 : 0;
  rec.omega = p.omega;
  rec.known_side = p.known_side ? 1 : 0;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (p.ran && p.decided) {  // decided before its window (sweep/probe_verdict.hpp): a class, no statistics
    rec.row.cls = static_cast<std::int32_t>(p.classification.cls);
    rec.row.stats.fill(nan);
    rec.row.mode_fraction.fill(nan);
    rec.powers.fill(nan);
  } else if (p.ran) {
    rec.row = window_row(p.classification);
    const sweep::WindowPowers w = sweep::window_powers(p.out.windows.front());
    for (std::size_t k = 0; k < kNumPowers; ++k) rec.powers[k] = kPowers[k].of(w);
  } else {
    rec.row.stats.fill(nan);
    rec.row.mode_fraction.fill(nan);
    rec.powers.fill(nan);
  }
  rec.known_omega = p.next.known_omega;
  rec.other_omega = p.next.other_omega;
  rec.known_class = p.next.known_class;
  rec.other_class = p.next.other_class;
  rec.status = std::int32_t(p.next.status);
  rec.carry = sweep::encode(p.next);
  p.out.windows.clear();
  if (p.out.ok) p.out.final_state = p.next.known;  // /tasks/final_state: where the next probe starts
  r.summary = std::move(p.out);
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
  if (r.probe) {  // after the windows: a record without it reads as before
    const ProbeRecord& p = *r.probe;
    w.put<std::uint8_t>(1);
    w.put(p.ran);
    w.put(p.omega);
    w.put(p.known_side);
    w.put(p.row.cls);
    w.put(p.row.stats);
    w.put(p.row.mode_fraction);
    w.put(p.powers);
    w.put(p.known_omega);
    w.put(p.other_omega);
    w.put(p.known_class);
    w.put(p.other_class);
    w.put(p.status);
    w.put_vector(p.carry);
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
  if (!rd.done()) {
    if (rd.get<std::uint8_t>() != 1) throw std::runtime_error("sweep result: unknown trailing block");
    ProbeRecord& p = r.probe.emplace();
    p.ran = rd.get<std::int32_t>();
    p.omega = rd.get<double>();
    p.known_side = rd.get<std::int32_t>();
    p.row.cls = rd.get<std::int32_t>();
    p.row.stats = rd.get<decltype(p.row.stats)>();
    p.row.mode_fraction = rd.get<decltype(p.row.mode_fraction)>();
    p.powers = rd.get<decltype(p.powers)>();
    p.known_omega = rd.get<double>();
    p.other_omega = rd.get<double>();
    p.known_class = rd.get<std::int32_t>();
    p.other_class = rd.get<std::int32_t>();
    p.status = rd.get<std::int32_t>();
    p.carry = rd.get_vector<std::byte>();
  }
  if (!rd.done()) throw std::runtime_error("sweep result: trailing bytes");
  return r;
}

}  // namespace ajx::results
