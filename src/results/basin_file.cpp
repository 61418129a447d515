#include "results/basin_file.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fmt/format.h>

#include "physics/state_row.hpp"
#include "results/sweep_result.hpp"
#include "sweep/basin.hpp"
#include "sweep/basin_match.hpp"
#include "results/sweep_file.hpp"
#include "results/sweep_reader.hpp"
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

// The classifier's drift tolerances the windows were classified with (/windows@classifier_settings).
sweep::DriftTolerances drift_tolerances(io::File& f) {
  std::vector<std::string> used;
  const io::Group wg = f.open_group("windows");
  if (wg.has_attribute("classifier_settings")) {
    const std::string text = wg.read_string_attribute("classifier_settings");
    for (std::size_t pos = 0; text != "defaults" && pos <= text.size();) {
      const std::size_t end = std::min(text.find('\n', pos), text.size());
      if (end > pos) used.push_back(text.substr(pos, end - pos));
      pos = end + 1;
    }
  }
  const sweep::ClassifierSettings c = sweep::parse_classifier_settings(used);
  return {c.radius_drift_tol, c.omega_drift_tol, c.L1_drift_tol};
}

// The attractors (sweep/basin_match.hpp) of the samples' windows, written to /basins/attractor
// and /basins/attractors (replaced when present: `astrojax classify` writes them again).
void write_attractors(io::File& f, const std::vector<std::int64_t>& chain, const std::vector<std::int32_t>& level,
                      const std::vector<std::int32_t>& sample_class, std::size_t W, std::size_t L) {
  const std::size_t S = chain.size();
  const auto stat = [&](const char* name) { return f.read_doubles(std::string("windows/") + name); };
  const io::Array<double> w_ball = stat("omega_ball"), w_bead = stat("omega_ball_bead"), w_bottom = stat("omega_ball_bottom"),
                          rho1 = stat("radius_bead_mean"), rho1_std = stat("radius_bead_std"),
                          rho2 = stat("radius_bottom_mean"), rho2_std = stat("radius_bottom_std"), L1 = stat("L1_mean"),
                          L1_std = stat("L1_std");
  const io::Dataset md = f.open_dataset("chains/model");
  const StoredModels models = stored_models(md.read_strings_attribute("columns"), md.read_doubles());
  const sweep::DriftTolerances drift = drift_tolerances(f);
  std::vector<sweep::MatchSample> samples(S);
  for (std::size_t i = 0; i < S; ++i) {
    const std::size_t w = std::size_t(chain[i]) * W;
    const sweep::WindowFeatures wf{w_ball.data[w], w_bead.data[w],   w_bottom.data[w], rho1.data[w], rho1_std.data[w],
                                   rho2.data[w],   rho2_std.data[w], L1.data[w],       L1_std.data[w]};
    samples[i] = sweep::match_sample(level[i], sample_class[i], wf, drift, models.chains[std::size_t(chain[i])].string_length);
  }
  const auto part = f.read_int32s("basins/levels/part").data;
  const auto omega = f.read_doubles("basins/levels/omega_m").data;
  std::vector<sweep::MatchLevel> levels;
  for (std::size_t l = 0; l < L; ++l) levels.push_back({part[l], omega[l]});
  std::vector<std::string> names;
  bool split[K];
  for (std::size_t k = 0; k < K; ++k) {
    names.emplace_back(sweep::kOrbitClasses[k].name);
    split[k] = sweep::basin_split_class(sweep::OrbitClass(k));
  }
  const sweep::BasinMatch m = sweep::match_attractors(levels, samples, std::span<const bool>(split, K), names);
  const std::size_t A = m.attractors.size();
  std::vector<std::string> att_name;
  std::vector<std::int32_t> att_class, att_part, count(L * A, 0), done(L, 0);
  for (const sweep::Attractor& a : m.attractors) att_name.push_back(a.name), att_class.push_back(a.cls), att_part.push_back(a.part);
  for (std::size_t i = 0; i < S; ++i)
    if (m.label[i] >= 0) ++done[std::size_t(level[i])], ++count[std::size_t(level[i]) * A + std::size_t(m.label[i])];
  std::vector<double> fraction(L * A, nan), lower(L * A, nan), upper(L * A, nan);
  for (std::size_t l = 0; l < L; ++l)
    for (std::size_t a = 0; a < A && done[l] > 0; ++a) {
      const std::size_t i = l * A + a;
      const sweep::Interval ci = sweep::wilson_interval(count[i], done[l]);
      fraction[i] = double(count[i]) / done[l], lower[i] = ci.lo, upper[i] = ci.hi;
    }
  if (f.exists("basins/attractor")) f.remove("basins/attractor");
  if (f.exists("basins/attractors")) f.remove("basins/attractors");
  f.write_dataset("basins/attractor", std::span<const std::int32_t>(m.label))
      .set_attribute("description", "the sample's attractor: a row of /basins/attractors; -1 not computed");
  io::Group g = f.create_group("basins/attractors");
  g.set_attribute("description", "the attractors matched across ω_m (sweep/basin_match.hpp): one label per orbit "
                                 "carried along the levels of its part; per level the count, fraction and 95 % Wilson "
                                 "interval of the samples on each");
  g.write_dataset("name", std::span<const std::string>(att_name));
  g.write_dataset("class", std::span<const std::int32_t>(att_class)).set_attribute("description", "its class (/classes)");
  g.write_dataset("part", std::span<const std::int32_t>(att_part)).set_attribute("description", "its (group, variant) part");
  g.write_dataset("count", std::span<const std::int32_t>(count), io::Dims{L, A})
      .set_attribute("description", "levels × attractors: samples on each");
  g.write_dataset("fraction", std::span<const double>(fraction), io::Dims{L, A}).set_attribute("description", "count / done");
  g.write_dataset("lower", std::span<const double>(lower), io::Dims{L, A})
      .set_attribute("description", "the 95 % Wilson score interval of the fraction");
  g.write_dataset("upper", std::span<const double>(upper), io::Dims{L, A})
      .set_attribute("description", "the 95 % Wilson score interval of the fraction");
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
  std::vector<double> start, omega;
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
  write_attractors(f, chain, level, sample_class, W, L);
  f.flush();
}

sweep::StoredOrbit read_stored_orbit(const std::string& path, long chain, long window) {
  const auto fail = [&](const std::string& what) { throw std::runtime_error(fmt::format("{}: {}", path, what)); };
  const SweepReader in(path);
  const sweep::SweepPlan plan = config::make_plan(in.config());
  if (chain < 0 || std::size_t(chain) >= in.chains())
    fail(fmt::format("chain {} is not one of 0 to {}", chain, long(in.chains()) - 1));
  const std::size_t c = std::size_t(chain);
  const sweep::ChainSetup& setup = plan.setups[c];
  const std::size_t W = setup.protocol.windows.size();
  if (window < 0 || std::size_t(window) >= W) fail(fmt::format("window {} is not one of 0 to {} (chain {})", window, long(W) - 1, chain));
  const std::size_t k = std::size_t(window);
  const std::int32_t cls = in.classes()(c, k);
  if (cls < 0 || cls == std::int32_t(sweep::OrbitClass::Failed))
    fail(fmt::format("window {} of chain {} was {}", k, c, cls < 0 ? "never computed" : "failed"));
  const auto& spans = plan.spans[c];
  std::size_t t = 0;
  while (t + 1 < spans.size() && std::size_t(spans[t].first_window + spans[t].num_windows) <= k) ++t;
  if (std::size_t(spans[t].first_window + spans[t].num_windows) != k + 1)
    fail(fmt::format("window {} of chain {} does not end its task (windows {} to {}): its end state is not stored", k, c,
                     spans[t].first_window, spans[t].first_window + spans[t].num_windows - 1));
  const physics::State s = in.final_state(plan.first_task[c] + t);
  const physics::MotorSchedule schedule = setup.motor();
  const double psi = physics::has_tie(s.y) ? s.y(physics::idx::chi) : schedule.top(s.t).phi;  // the top's azimuth
  const double cs = std::cos(psi), sn = std::sin(psi);
  const auto back = [&](const physics::Vec3& x) { return physics::Vec3(cs * x.x() + sn * x.y(), -sn * x.x() + cs * x.y(), x.z()); };
  sweep::StoredOrbit o;
  o.file = path, o.chain = chain, o.window = window;
  o.r1 = back(s.r1()), o.r2 = back(s.r2()), o.v1 = back(s.v1()), o.v2 = back(s.v2());
  o.mode = s.contact.mode;
  o.string_length = setup.model.p.string_length;
  o.drive_radius = setup.model.p.drive_radius;
  o.omega_m = setup.protocol.windows[k].omega_end;
  return o;
}

}  // namespace ajx::results
