#include "results/basin_file.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fmt/format.h>

#include "physics/state_row.hpp"
#include "results/sweep_result.hpp"
#include "sweep/basin.hpp"
#include "sweep/orbit_classes.hpp"

namespace ajx::results {

namespace {

constexpr std::size_t K = sweep::kNumOrbitClasses;
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

const char* stat_units(const char* name) {
  for (const WindowStat& s : kStats)
    if (std::strcmp(s.name, name) == 0) return s.units;
  return "";
}

}  // namespace

bool has_basins(const sweep::SweepPlan& plan) {
  return std::any_of(plan.starts.begin(), plan.starts.end(), [](const sweep::ChainStart& s) { return s.sample >= 0; });
}

void write_basin_layout(io::File& f, const config::SweepConfig& cfg, const sweep::SweepPlan& plan) {
  if (!has_basins(plan)) return;
  const std::vector<sweep::PlanPart> parts = config::plan_parts(cfg);
  std::vector<std::int64_t> chain, first;
  std::vector<std::int32_t> level, sample, lpart, lsamples, lfamily;
  std::vector<double> start, omega, tolerance;
  for (std::size_t c = 0; c < plan.chains(); ++c) {
    const sweep::ChainStart& s = plan.starts[c];
    if (s.sample < 0) continue;
    if (s.sample == 0) {  // a level's samples are consecutive chains, from sample 0
      const sweep::BasinSpec& b = *parts[plan.part[c]].spec.basin;
      first.push_back(std::int64_t(chain.size()));
      lpart.push_back(std::int32_t(plan.part[c]));
      lsamples.push_back(b.samples);
      lfamily.push_back(std::int32_t(b.family));
      omega.push_back(s.omega);
      tolerance.push_back(b.match_tolerance);
    }
    chain.push_back(std::int64_t(c));
    level.push_back(std::int32_t(first.size() - 1));
    sample.push_back(s.sample);
    const std::vector<double> row = physics::state_row(*s.state);
    start.insert(start.end(), row.begin(), row.end());
  }
  const std::size_t S = chain.size(), L = first.size();
  io::Group g = f.create_group("basins");
  g.set_attribute("description", "basin sampling: every drawn start, its final class and features; per level the "
                                 "fraction of each class with its 95 % Wilson interval");
  g.write_dataset("chain", std::span<const std::int64_t>(chain)).set_attribute("description", "the sample's chain");
  g.write_dataset("level", std::span<const std::int32_t>(level)).set_attribute("description", "its row of /basins/levels");
  g.write_dataset("sample", std::span<const std::int32_t>(sample)).set_attribute("description", "its index in its level");
  g.write_dataset("start", std::span<const double>(start), io::Dims{S, physics::kStateCols})
      .set_attribute("columns", std::span<const std::string>(physics::state_column_names()));
  g.create_filled("class", {S}, io::DType::Int32, -1.0, {S})
      .set_attribute("description", "the class of the sample's measured window; -1 = not computed");
  std::vector<std::string> columns;
  for (const char* name : kBasinFeatures) columns.push_back(fmt::format("{} [{}]", name, stat_units(name)));
  g.create_filled("features", {S, kNumBasinFeatures}, io::DType::Float64, nan, {S, kNumBasinFeatures})
      .set_attribute("columns", std::span<const std::string>(columns));
  io::Group lg = g.create_group("levels");
  lg.write_dataset("part", std::span<const std::int32_t>(lpart)).set_attribute("description", "the (group, variant) part: /resolved/<part>");
  lg.write_dataset("omega_m", std::span<const double>(omega)).set_attribute("units", "rad/s");
  lg.write_dataset("first", std::span<const std::int64_t>(first)).set_attribute("description", "its first sample's row");
  lg.write_dataset("samples", std::span<const std::int32_t>(lsamples)).set_attribute("description", "N, the starts drawn");
  std::vector<std::string> families(std::begin(sweep::kBasinFamilyNames), std::end(sweep::kBasinFamilyNames));
  lg.write_dataset("family", std::span<const std::int32_t>(lfamily)).set_attribute("names", std::span<const std::string>(families));
  lg.write_dataset("match_tolerance", std::span<const double>(tolerance))
      .set_attribute("description", "orbits of one class are one attractor across levels within this scaled feature distance");
  lg.create_filled("done", {L}, io::DType::Int32, 0.0, {L}).set_attribute("description", "samples classified");
  lg.create_filled("count", {L, K}, io::DType::Int32, 0.0, {L, K}).set_attribute("description", "samples per class (/classes)");
  for (const char* name : {"fraction", "lower", "upper"})
    lg.create_filled(name, {L, K}, io::DType::Float64, nan, {L, K})
        .set_attribute("description", std::string(name) == "fraction" ? "count / done"
                                                                      : "the 95 % Wilson score interval of the fraction");
}

void write_basin_results(io::File& f) {
  if (!f.exists("basins")) return;
  const auto chain = f.read_int64s("basins/chain").data;
  const auto level = f.read_int32s("basins/level").data;
  const std::size_t S = chain.size(), L = f.open_dataset("basins/levels/omega_m").dims()[0];
  const io::Array<std::int32_t> cls = f.read_int32s("windows/class");
  const std::size_t W = cls.cols();
  std::vector<std::int32_t> sample_class(S), done(L, 0), count(L * K, 0);
  std::vector<double> features(S * kNumBasinFeatures), fraction(L * K, nan), lower(L * K, nan), upper(L * K, nan);
  std::vector<io::Array<double>> stats;
  for (const char* name : kBasinFeatures) stats.push_back(f.read_doubles(std::string("windows/") + name));
  for (std::size_t i = 0; i < S; ++i) {
    const std::size_t w = std::size_t(chain[i]) * W;  // a basin chain's one window
    sample_class[i] = cls.data[w];
    for (std::size_t k = 0; k < kNumBasinFeatures; ++k) features[i * kNumBasinFeatures + k] = stats[k].data[w];
    if (cls.data[w] < 0) continue;
    ++done[std::size_t(level[i])];
    ++count[std::size_t(level[i]) * K + std::size_t(cls.data[w])];
  }
  for (std::size_t l = 0; l < L; ++l)
    for (std::size_t k = 0; k < K; ++k) {
      if (done[l] == 0) continue;
      const std::size_t i = l * K + k;
      fraction[i] = double(count[i]) / done[l];
      const sweep::Interval ci = sweep::wilson_interval(count[i], done[l]);
      lower[i] = ci.lo;
      upper[i] = ci.hi;
    }
  f.open_dataset("basins/class").write_region({0}, {S}, std::span<const std::int32_t>(sample_class));
  f.open_dataset("basins/features").write_region({0, 0}, {S, kNumBasinFeatures}, std::span<const double>(features));
  f.open_dataset("basins/levels/done").write_region({0}, {L}, std::span<const std::int32_t>(done));
  f.open_dataset("basins/levels/count").write_region({0, 0}, {L, K}, std::span<const std::int32_t>(count));
  f.open_dataset("basins/levels/fraction").write_region({0, 0}, {L, K}, std::span<const double>(fraction));
  f.open_dataset("basins/levels/lower").write_region({0, 0}, {L, K}, std::span<const double>(lower));
  f.open_dataset("basins/levels/upper").write_region({0, 0}, {L, K}, std::span<const double>(upper));
  f.flush();
}

}  // namespace ajx::results
