// SweepReader's check of /brackets (results/brackets_file.hpp): present only from format 5 and
// only for a sweep with bisections; every shape, code and index in range, every computed probe's
// level finite, each chain's probes consecutive.
#include <cmath>
#include <fmt/format.h>

#include "results/sweep_reader.hpp"
#include "sweep/bisection.hpp"
#include "sweep/orbit_classes.hpp"

namespace ajx::results {

namespace {
template <class T>
std::vector<T> as(const Array<std::int32_t>& a) {
  return std::vector<T>(a.data.begin(), a.data.end());
}
}  // namespace

void SweepReader::read_brackets() {
  if (!f_.exists("brackets")) return;
  if (version_ < 5) fail("brackets", fmt::format("present in a file of format {}; /brackets is new in format 5", version_));
  const std::size_t B = dataset("brackets/chain", 1, io::TypeClass::Integer).dims()[0];
  const std::size_t P = dataset("brackets/probes/chain", 1, io::TypeClass::Integer).dims()[0];
  BracketTable t;
  t.chain = as<std::int64_t>(ints("brackets/chain", {B}));
  t.threshold = ints("brackets/threshold", {B}).data;
  t.planned = ints("brackets/planned_probes", {B}).data;
  t.from = doubles("brackets/from", {B}).data;
  t.to = doubles("brackets/to", {B}).data;
  t.width = doubles("brackets/width", {B}).data;
  t.start_omega = doubles("brackets/start_omega", {B}).data;
  t.known_omega = doubles("brackets/known_omega", {B}).data;
  t.other_omega = doubles("brackets/other_omega", {B}).data;
  t.known_class = ints("brackets/known_class", {B}).data;
  t.other_class = ints("brackets/other_class", {B}).data;
  t.status = ints("brackets/status", {B}).data;
  if (f_.exists("brackets/guide")) t.guide = doubles("brackets/guide", {B}).data;
  BracketTable::Probes& p = t.probes;
  p.chain = as<std::int64_t>(ints("brackets/probes/chain", {P}));
  p.index = as<std::int64_t>(ints("brackets/probes/index", {P}));
  p.omega_m = doubles("brackets/probes/omega_m", {P}).data;
  p.known_omega = doubles("brackets/probes/known_omega", {P}).data;
  p.other_omega = doubles("brackets/probes/other_omega", {P}).data;
  p.cls = ints("brackets/probes/class", {P}).data;
  p.ran = ints("brackets/probes/ran", {P}).data;
  p.known_side = ints("brackets/probes/known_side", {P}).data;
  p.status = ints("brackets/probes/status", {P}).data;
  p.stats = doubles("brackets/probes/stats", {P, kNumStats});
  p.powers = doubles("brackets/probes/powers", {P, kNumPowers});

  const auto in_range = [&](const char* name, std::size_t i, std::int64_t v, std::int64_t lo, std::int64_t hi) {
    if (v < lo || v > hi) fail(name, fmt::format("at [{}]: {} is not one of {} to {}", i, v, lo, hi));
  };
  const auto ncls = std::int64_t(sweep::kNumOrbitClasses) - 1;
  std::size_t planned = 0;
  for (std::size_t b = 0; b < B; ++b) {
    in_range("brackets/chain", b, t.chain[b], 0, std::int64_t(C_) - 1);
    in_range("brackets/threshold", b, t.threshold[b], 0, 3);
    in_range("brackets/planned_probes", b, t.planned[b], 2, 64);
    in_range("brackets/known_class", b, t.known_class[b], -1, ncls);
    in_range("brackets/other_class", b, t.other_class[b], -1, ncls);
    in_range("brackets/status", b, t.status[b], -1, sweep::kMaxBisectStatus);
    for (const auto& [name, v] : {std::pair{"brackets/from", t.from[b]}, {"brackets/to", t.to[b]}, {"brackets/width", t.width[b]}})
      if (!std::isfinite(v)) fail(name, fmt::format("at [{}]: {}", b, v));
    planned += std::size_t(t.planned[b]);
  }
  if (planned != P) fail("brackets/probes/chain", fmt::format("{} probes, but /brackets/probes plans {}", P, planned));
  // Each bracket's probes in order, consecutive: 0, 1, ..., probes − 1.
  std::size_t i = 0;
  for (std::size_t b = 0; b < B; ++b)
    for (std::int64_t k = 0; k < t.planned[b]; ++k, ++i) {
      if (p.chain[i] != t.chain[b] || p.index[i] != k)
        fail("brackets/probes/index", fmt::format("at [{}]: chain {} probe {}, expected chain {} probe {}", i, p.chain[i],
                                                  p.index[i], t.chain[b], k));
      in_range("brackets/probes/class", i, p.cls[i], -1, ncls);
      in_range("brackets/probes/ran", i, p.ran[i], -1, 1);
      in_range("brackets/probes/known_side", i, p.known_side[i], -1, 1);
      in_range("brackets/probes/status", i, p.status[i], -1, sweep::kMaxBisectStatus);
      if (p.ran[i] == 1 && (!std::isfinite(p.omega_m[i]) || p.cls[i] < 0))
        fail("brackets/probes/omega_m", fmt::format("at [{}]: a probe that ran has level {} and class {}", i, p.omega_m[i], p.cls[i]));
    }
  brackets_ = std::move(t);
}

}  // namespace ajx::results
