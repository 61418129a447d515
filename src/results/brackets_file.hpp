// /brackets of a sweep file (format 5, written only when the sweep has [bisect] chains): every
// bisection probe and each chain's bracket (sweep/bisection.hpp; layout in
// docs/reference/file-format.md). Made with every value "not computed" when the file is made,
// filled probe by probe through SweepFile::write_task, checked by SweepReader.
#pragma once
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "io/hdf5_file.hpp"
#include "results/sweep_result.hpp"
#include "sweep/bisection.hpp"
#include "sweep/plan.hpp"
#include "sweep/thresholds.hpp"

namespace ajx::results {

inline constexpr const char* kThresholdNames = "0 omega_rise,1 omega_fall,2 omega_1,3 omega_2";

// Which row of /brackets/probes each task writes and which row of /brackets each chain owns.
struct BracketsLayout {
  std::vector<std::int64_t> probe_row;  // per task: its row, -1 for a task that is not a probe
  std::vector<std::int64_t> chain_row;  // per chain: its row, -1 for a chain that is not a bisection
  std::size_t probes = 0, chains = 0;
  bool guided = false;  // a chain's probes go next to a predicted threshold: /brackets/guide

  explicit BracketsLayout(const sweep::SweepPlan& plan) : probe_row(plan.n_tasks, -1), chain_row(plan.chains(), -1) {
    for (std::size_t c = 0; c < plan.chains(); ++c) {
      if (!plan.bisect[c]) continue;
      guided = guided || plan.bisect[c]->guide != sweep::BisectSpec::Guide::Middle;
      chain_row[c] = std::int64_t(chains++);
      for (std::size_t k = 0; k < plan.spans[c].size(); ++k) probe_row[plan.first_task[c] + k] = std::int64_t(probes++);
    }
  }
  bool empty() const { return chains == 0; }
};

inline std::vector<std::string> stat_names() {
  std::vector<std::string> out;
  for (const WindowStat& s : kStats) out.push_back(std::string(s.name) + " [" + s.units + "]");
  return out;
}
inline std::vector<std::string> power_names() {
  std::vector<std::string> out;
  for (const WindowPower& s : kPowers) out.push_back(std::string(s.name) + " [" + s.units + "]");
  return out;
}

// The group, its per-chain layout (what the bisection asks for) and the results not computed.
inline void create_brackets(io::File& f, const sweep::SweepPlan& plan, const BracketsLayout& L) {
  if (L.empty()) return;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  io::Group g = f.create_group("brackets");
  g.set_attribute("description", "thresholds by bisection on held levels: one row per bisection chain; each probe in "
                                 "/brackets/probes");
  std::vector<std::int64_t> chain;
  std::vector<std::int32_t> threshold, probes;
  std::vector<double> from, to, width, start;
  for (std::size_t c = 0; c < plan.chains(); ++c) {
    if (!plan.bisect[c]) continue;
    const sweep::BisectSpec& b = *plan.bisect[c];
    chain.push_back(std::int64_t(c));
    threshold.push_back(std::int32_t(b.threshold));
    probes.push_back(std::int32_t(plan.spans[c].size()));
    from.push_back(b.from);
    to.push_back(b.to);
    width.push_back(b.width);
    start.push_back(b.start_omega);
  }
  const std::size_t B = L.chains, P = L.probes;
  g.write_dataset("chain", std::span<const std::int64_t>(chain)).set_attribute("description", "the chain (index into /chains)");
  g.write_dataset("threshold", std::span<const std::int32_t>(threshold)).set_attribute("names", kThresholdNames);
  g.write_dataset("planned_probes", std::span<const std::int32_t>(probes))
      .set_attribute("description", L.guided ? "probes planned: n + 2 with n = ceil(log2(|to - from|/width)), 2 n + 2 "
                                               "for a chain with guide = held_orbit"
                                             : "probes planned: 2 + ceil(log2(|to - from|/width))");
  const auto put = [&](const char* name, const std::vector<double>& v, const char* what) {
    auto d = g.write_dataset(name, std::span<const double>(v));
    d.set_attribute("units", "rad/s");
    d.set_attribute("description", what);
  };
  put("from", from, "the first level, on the known side");
  put("to", to, "the far end of the range");
  put("width", width, "the width asked for");
  put("start_omega", start, "ω_m of the seed at t = 0");
  const io::Dims b1{B}, p1{P};
  const auto filled = [&](io::Group& at, const char* name, const io::Dims& dims, io::DType type, double fill, const char* attr,
                          const char* what) {
    auto d = at.create_filled(name, dims, type, fill, dims);
    d.set_attribute(attr, what);
  };
  filled(g, "known_omega", b1, io::DType::Float64, nan, "units", "rad/s");
  filled(g, "other_omega", b1, io::DType::Float64, nan, "units", "rad/s");
  filled(g, "known_class", b1, io::DType::Int32, -1.0, "description", "class at known_omega, the threshold's known side (-1: none)");
  filled(g, "other_class", b1, io::DType::Int32, -1.0, "description", "class at other_omega, past the threshold (-1: none)");
  filled(g, "status", b1, io::DType::Int32, -1.0, "names", "-1 not computed," "0 running,1 converged,2 start not on the known side,3 no crossing in the range,4 a probe failed");
  if (L.guided)
    filled(g, "guide", b1, io::DType::Float64, nan, "units", "rad/s");  // guide = held_orbit's prediction (NaN: none)
  io::Group pg = g.create_group("probes");
  pg.set_attribute("description", "every probe: its held level, class and statistics, and the bracket after it");
  std::vector<std::int64_t> pchain, pindex;
  for (std::size_t c = 0; c < plan.chains(); ++c)
    if (plan.bisect[c])
      for (std::size_t k = 0; k < plan.spans[c].size(); ++k) {
        pchain.push_back(std::int64_t(c));
        pindex.push_back(std::int64_t(k));
      }
  pg.write_dataset("chain", std::span<const std::int64_t>(pchain));
  pg.write_dataset("index", std::span<const std::int64_t>(pindex)).set_attribute("description", "0 the start level, 1 the far end, then the midpoints");
  filled(pg, "omega_m", p1, io::DType::Float64, nan, "units", "rad/s");
  filled(pg, "class", p1, io::DType::Int32, -1.0, "description", "the probe window's orbit class; -1 not computed or not run");
  filled(pg, "ran", p1, io::DType::Int32, -1.0, "description", "-1 not computed, 0 not run (the bracket was settled), 1 ran");
  filled(pg, "known_side", p1, io::DType::Int32, -1.0, "description", "1 on the threshold's known side, 0 past it, -1 not computed");
  filled(pg, "known_omega", p1, io::DType::Float64, nan, "units", "rad/s");
  filled(pg, "other_omega", p1, io::DType::Float64, nan, "units", "rad/s");
  filled(pg, "status", p1, io::DType::Int32, -1.0, "description", "the bracket's status after the probe, as /brackets/status");
  pg.create_filled("stats", {P, kNumStats}, io::DType::Float64, nan, {1, kNumStats})
      .set_attribute("columns", std::span<const std::string>(stat_names()));
  pg.create_filled("powers", {P, kNumPowers}, io::DType::Float64, nan, {1, kNumPowers})
      .set_attribute("columns", std::span<const std::string>(power_names()));
}

// One probe's row, and its chain's bracket as it stands after the probe. `ds` opens a dataset.
inline void write_probe(const std::function<io::Dataset&(const std::string&)>& ds, const BracketsLayout& L,
                        std::size_t task, std::size_t chain, const ProbeRecord& p) {
  const std::size_t i = std::size_t(L.probe_row.at(task)), b = std::size_t(L.chain_row.at(chain));
  const auto one = [&](const std::string& name, std::size_t row, auto v) {
    ds(name).write_region({row}, {1}, std::span<const decltype(v)>(&v, 1));
  };
  one("brackets/probes/omega_m", i, p.omega);
  one("brackets/probes/class", i, p.row.cls);
  one("brackets/probes/ran", i, p.ran);
  one("brackets/probes/known_side", i, p.ran ? p.known_side : std::int32_t(-1));
  one("brackets/probes/known_omega", i, p.known_omega);
  one("brackets/probes/other_omega", i, p.other_omega);
  one("brackets/probes/status", i, p.status);
  ds("brackets/probes/stats").write_region({i, 0}, {1, kNumStats}, std::span<const double>(p.row.stats));
  ds("brackets/probes/powers").write_region({i, 0}, {1, kNumPowers}, std::span<const double>(p.powers));
  one("brackets/known_omega", b, p.known_omega);
  one("brackets/other_omega", b, p.other_omega);
  one("brackets/known_class", b, p.known_class);
  one("brackets/other_class", b, p.other_class);
  one("brackets/status", b, p.status);
  if (L.guided && !p.carry.empty()) one("brackets/guide", b, sweep::decode_carry(p.carry).guide);
}

}  // namespace ajx::results
