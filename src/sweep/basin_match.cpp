#include "sweep/basin_match.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
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
  // ρ1, ρ2 and s are one configuration of the string: the orbit's extent in it is its largest swing.
  const double extent = std::max({swing(w.rho1_std), swing(w.rho2_std), swing(w.s_std)});
  m.h = {disagree + d.omega, (extent + d.radius * std::abs(w.rho1)) / l, (extent + d.radius * std::abs(w.rho2)) / l,
         (extent + d.L1 * l) / l};
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

// A cluster's reach about its centroid c: max over members of |x − c| + h, the union of their bands.
MatchPoint reach(std::span<const MatchSample> s, const std::vector<std::size_t>& members, const MatchPoint& c) {
  MatchPoint r{};
  for (std::size_t i : members)
    for (std::size_t k = 0; k < kNumMatchFeatures; ++k)
      if (!std::isnan(s[i].x[k])) r[k] = std::max(r[k], std::abs(s[i].x[k] - c[k]) + s[i].h[k]);
  return r;
}

struct LevelAttractor {
  std::int32_t cls;
  MatchPoint centre, reach;
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
    {
      const MatchPoint c = centroid(s, members);
      out.push_back({cls, c, reach(s, members, c), std::move(members)});
    }
  }
  return out;
}

// A label where it was last seen: its class, centroid and reach there, and that level's ω_m.
struct LastSeen {
  std::int32_t cls;
  MatchPoint centre, reach;
  double omega;  // [rad/s]
};

// An attractor against a label last seen |Δ ln ω_m| = dlnw away: per feature, the centroids'
// difference in units of what may separate two sightings of one orbit, their two reaches plus
// the largest change along a family, |Δy| <= |y| |Δ ln ω_m| (ln ω_ball: |Δ ln ω_ball| <= |Δ ln ω_m|).
// `bound` is the largest of these ratios (one orbit when <= 1; infinite when only one of them has
// a feature), `rank` their root sum of squares, which orders the candidates.
struct StepDistance {
  double bound = 0.0, rank = 0.0;
};
StepDistance step_distance(const LevelAttractor& a, const LastSeen& b, double dlnw) {
  StepDistance D;
  for (std::size_t k = 0; k < kNumMatchFeatures; ++k) {
    const double x = a.centre[k], y = b.centre[k];
    if (std::isnan(x) || std::isnan(y)) {
      if (std::isnan(x) != std::isnan(y)) return {INFINITY, INFINITY};
      continue;
    }
    const double change = dlnw * (k == 0 ? 1.0 : std::max(std::abs(x), std::abs(y)));
    const double allowed = a.reach[k] + b.reach[k] + change;
    const double q = allowed > 0.0 ? std::abs(x - y) / allowed : (x == y ? 0.0 : INFINITY);
    D.bound = std::max(D.bound, q);
    D.rank += q * q;
  }
  D.rank = std::sqrt(D.rank);
  return D;
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
    std::map<std::int32_t, LastSeen> seen;               // label -> where it was last seen
    for (std::size_t l : rows) {
      std::vector<LevelAttractor> now = level_attractors(samples, at_level[l], split);
      std::vector<std::tuple<double, std::size_t, std::int32_t>> pairs;  // (rank, now, label)
      for (std::size_t a = 0; a < now.size(); ++a) {
        const bool apart = std::size_t(now[a].cls) < split.size() && split[std::size_t(now[a].cls)];
        if (!apart) {
          auto [it, fresh] = unsplit_label.try_emplace(now[a].cls, std::int32_t(out.attractors.size()));
          if (fresh) out.attractors.push_back({part, now[a].cls, 0, ""}), ++letters[now[a].cls];
          now[a].label = it->second;
          continue;
        }
        for (const auto& [label, last] : seen)
          if (last.cls == now[a].cls) {
            const StepDistance D = step_distance(now[a], last, std::abs(std::log(levels[l].omega / last.omega)));
            if (D.bound <= 1.0) pairs.emplace_back(D.rank, a, label);
          }
      }
      std::sort(pairs.begin(), pairs.end());
      std::set<std::int32_t> taken;
      for (const auto& [rank, a, label] : pairs)
        if (now[a].label < 0 && !taken.count(label)) now[a].label = label, taken.insert(label);
      for (LevelAttractor& a : now)
        if (a.label < 0) {
          a.label = std::int32_t(out.attractors.size());
          out.attractors.push_back({part, a.cls, letters[a.cls]++, ""});
        }
      for (LevelAttractor& a : now) {
        for (std::size_t i : a.members) out.label[i] = a.label;
        seen[a.label] = {a.cls, a.centre, a.reach, levels[l].omega};
      }
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
