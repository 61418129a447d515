#include "sweep/basin_match.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>

namespace ajx::sweep {

MatchSample match_sample(std::int32_t level, std::int32_t cls, const WindowFeatures& w, const DriftTolerances& d,
                         double string_length) {
  const double l = string_length;
  MatchSample m;
  m.level = level;
  m.cls = cls;
  m.x = {w.omega_ball > 0.0 ? std::log(w.omega_ball) : std::nan(""), w.rho1 / l, w.rho2 / l, w.s / l};
  const double disagree = std::isfinite(w.omega_bead) && std::isfinite(w.omega_bottom) && w.omega_ball > 0.0
                              ? std::abs(w.omega_bead - w.omega_bottom) / (2.0 * w.omega_ball)
                              : 0.0;
  const auto swing = [](double std) { return std::isfinite(std) ? std::sqrt(2.0) * std : 0.0; };
  m.h = {disagree + d.omega, (swing(w.rho1_std) + d.radius * std::abs(w.rho1)) / l,
         (swing(w.rho2_std) + d.radius * std::abs(w.rho2)) / l, (swing(w.s_std) + d.L1 * l) / l};
  for (double& h : m.h)
    if (!std::isfinite(h)) h = 0.0;
  return m;
}

bool same_orbit(const MatchSample& a, const MatchSample& b) {
  for (std::size_t k = 0; k < kNumMatchFeatures; ++k) {
    const bool na = std::isnan(a.x[k]), nb = std::isnan(b.x[k]);
    if (na || nb) {
      if (na != nb) return false;  // a feature one orbit has and the other lacks
      continue;
    }
    if (std::abs(a.x[k] - b.x[k]) > a.h[k] + b.h[k]) return false;
  }
  return true;
}

namespace {

// Union-find over the samples of one class at one level.
struct Sets {
  std::vector<std::size_t> up;
  explicit Sets(std::size_t n) : up(n) { std::iota(up.begin(), up.end(), 0); }
  std::size_t root(std::size_t i) {
    while (up[i] != i) i = up[i] = up[up[i]];
    return i;
  }
  void join(std::size_t a, std::size_t b) { up[root(a)] = root(b); }
};

// Single-linkage clusters of the samples `of` (indices into `s`), largest first. Sorted by s/l,
// a sample is compared only with those whose s/l is within its band plus the widest band.
std::vector<std::vector<std::size_t>> clusters(std::span<const MatchSample> s, std::vector<std::size_t> of) {
  std::sort(of.begin(), of.end(), [&](std::size_t a, std::size_t b) { return std::tie(s[a].x[3], a) < std::tie(s[b].x[3], b); });
  double widest = 0.0;
  for (std::size_t i : of) widest = std::max(widest, s[i].h[3]);
  Sets sets(of.size());
  for (std::size_t a = 0; a < of.size(); ++a)
    for (std::size_t b = a + 1; b < of.size() && !(s[of[b]].x[3] - s[of[a]].x[3] > s[of[a]].h[3] + widest); ++b)
      if (same_orbit(s[of[a]], s[of[b]])) sets.join(a, b);
  std::map<std::size_t, std::vector<std::size_t>> by_root;
  for (std::size_t a = 0; a < of.size(); ++a) by_root[sets.root(a)].push_back(of[a]);
  std::vector<std::vector<std::size_t>> out;
  for (auto& [r, members] : by_root) {
    std::sort(members.begin(), members.end());
    out.push_back(std::move(members));
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return a.size() != b.size() ? a.size() > b.size() : a.front() < b.front();
  });
  return out;
}

// The centroid of a cluster: each feature's mean over the members that have it (NaN if none).
MatchPoint centroid(std::span<const MatchSample> s, const std::vector<std::size_t>& members) {
  MatchPoint c{};
  for (std::size_t k = 0; k < kNumMatchFeatures; ++k) {
    double sum = 0.0;
    int n = 0;
    for (std::size_t i : members)
      if (!std::isnan(s[i].x[k])) sum += s[i].x[k], ++n;
    c[k] = n > 0 ? sum / n : std::nan("");
  }
  return c;
}

// Euclidean distance over the features both have; infinite when only one has a feature.
double distance(const MatchPoint& a, const MatchPoint& b) {
  double d2 = 0.0;
  for (std::size_t k = 0; k < kNumMatchFeatures; ++k) {
    if (std::isnan(a[k]) || std::isnan(b[k])) {
      if (std::isnan(a[k]) != std::isnan(b[k])) return INFINITY;
      continue;
    }
    d2 += (a[k] - b[k]) * (a[k] - b[k]);
  }
  return std::sqrt(d2);
}

struct LevelAttractor {
  std::int32_t cls;
  MatchPoint centre;
  std::vector<std::size_t> members;
  std::int32_t label = -1;
};

// The attractors of one level: per class, one (an unsplit class) or its clusters.
std::vector<LevelAttractor> level_attractors(std::span<const MatchSample> s, const std::vector<std::size_t>& at_level,
                                             std::span<const bool> split) {
  std::map<std::int32_t, std::vector<std::size_t>> by_class;
  for (std::size_t i : at_level)
    if (s[i].cls >= 0) by_class[s[i].cls].push_back(i);
  std::vector<LevelAttractor> out;
  for (auto& [cls, of] : by_class) {
    const bool apart = std::size_t(cls) < split.size() && split[std::size_t(cls)];
    for (auto& members : apart ? clusters(s, of) : std::vector<std::vector<std::size_t>>{of})
      out.push_back({cls, centroid(s, members), std::move(members)});
  }
  return out;
}

}  // namespace

BasinMatch match_attractors(std::span<const MatchLevel> levels, std::span<const MatchSample> samples,
                            std::span<const bool> split, std::span<const std::string> class_names) {
  BasinMatch out;
  out.label.assign(samples.size(), -1);
  std::vector<std::vector<std::size_t>> at_level(levels.size());
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (samples[i].level >= 0 && std::size_t(samples[i].level) < levels.size()) at_level[std::size_t(samples[i].level)].push_back(i);
  std::map<std::int32_t, std::vector<std::size_t>> parts;  // part -> its levels in rising ω_m
  for (std::size_t l = 0; l < levels.size(); ++l) parts[levels[l].part].push_back(l);
  for (auto& [part, rows] : parts) {
    std::stable_sort(rows.begin(), rows.end(), [&](std::size_t a, std::size_t b) { return levels[a].omega < levels[b].omega; });
    std::map<std::int32_t, int> letters;                 // attractors so far, per class
    std::map<std::int32_t, std::int32_t> unsplit_label;  // an unsplit class's one label
    std::vector<LevelAttractor> previous;
    for (std::size_t l : rows) {
      std::vector<LevelAttractor> now = level_attractors(samples, at_level[l], split);
      std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;  // (distance, now, previous)
      for (std::size_t a = 0; a < now.size(); ++a) {
        const bool apart = std::size_t(now[a].cls) < split.size() && split[std::size_t(now[a].cls)];
        if (!apart) {
          auto [it, fresh] = unsplit_label.try_emplace(now[a].cls, std::int32_t(out.attractors.size()));
          if (fresh) out.attractors.push_back({part, now[a].cls, 0, ""}), ++letters[now[a].cls];
          now[a].label = it->second;
          continue;
        }
        for (std::size_t b = 0; b < previous.size(); ++b)
          if (previous[b].cls == now[a].cls) {
            const double d = distance(now[a].centre, previous[b].centre);
            if (std::isfinite(d)) pairs.emplace_back(d, a, b);
          }
      }
      std::sort(pairs.begin(), pairs.end());
      std::vector<bool> taken(previous.size(), false);
      for (const auto& [d, a, b] : pairs)
        if (now[a].label < 0 && !taken[b]) now[a].label = previous[b].label, taken[b] = true;
      for (LevelAttractor& a : now)
        if (a.label < 0) {
          a.label = std::int32_t(out.attractors.size());
          out.attractors.push_back({part, a.cls, letters[a.cls]++, ""});
        }
      for (const LevelAttractor& a : now)
        for (std::size_t i : a.members) out.label[i] = a.label;
      previous = std::move(now);
    }
    for (Attractor& a : out.attractors)
      if (a.part == part) {
        const std::string& n = std::size_t(a.cls) < class_names.size() ? class_names[std::size_t(a.cls)] : "?";
        a.name = letters[a.cls] <= 1 ? n
                 : a.letter < 26    ? n + " " + char('A' + a.letter)
                                    : n + " " + std::to_string(a.letter);
      }
  }
  return out;
}

}  // namespace ajx::sweep
