#include "orbits/orbit_seed.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <deque>
#include <limits>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "orbits/orbit_families.hpp"
#include "orbits/orbit_stability.hpp"
#include "physics/parameter_table.hpp"

namespace ajx::orbits {

namespace {
// Rule 3: a stable orbit on the bottom stop, else any admissible one there.
std::optional<SeedOrbit> bottom_seed(const physics::Model& m, double omega) {
  std::optional<SeedOrbit> best;
  if (!m.layers.bottom_stop) return best;
  for (const auto& o : orbits_at({m, omega, Closure::BottomStop, 0.0})) {
    if (!o.admissible) continue;
    const bool st = stability({m, omega, o.closure, o.s}, unknowns(o)).stable;
    if (!best || (st && !best->stable)) best = SeedOrbit{o, st, 3};
  }
  return best;
}

// One row of the seed's grid: the stuck orbits at one bead position s, and per orbit its growth
// rate (max Re λ, NaN where the orbit is not admissible, hence no candidate).
struct Row {
  std::vector<SteadyOrbit> orbits;
  std::vector<double> growth;
  bool exact = false;  // solved by orbits_at itself
};

// A row solved cheaply: Newton from a 12 × 12 grid of planar starts (orbits_at: 24 × 24), the
// drag's homotopy given up at steps of 1/64 (orbits_at: 1/4096). The orbits are orbits_at's to
// round-off wherever both find them. (At most 20 or 30 iterations a solve, not 60, missed
// orbits of the homotopy near the axis: R = 1.3 mm at 12π.)
constexpr SolveEffort kQuickRow{12, 1.0 / 64};

double depth(const SteadyOrbit& o) { return std::min(o.margins.up, o.margins.down); }
int rank_of(double growth) { return growth < 0 ? 1 : 2; }  // rule 1 (stable) or 2

// The rule over the rows as they stand, in the order of solve_locked_orbit_seed: (row, orbit).
std::optional<std::pair<std::size_t, std::size_t>> best_of(const std::vector<Row>& rows) {
  std::optional<std::pair<std::size_t, std::size_t>> best;
  for (std::size_t k = 0; k < rows.size(); ++k)
    for (std::size_t i = 0; i < rows[k].orbits.size(); ++i) {
      if (std::isnan(rows[k].growth[i])) continue;
      const int rank = rank_of(rows[k].growth[i]);
      if (!best) {
        best = std::pair{k, i};
        continue;
      }
      const int best_rank = rank_of(rows[best->first].growth[best->second]);
      if (rank < best_rank || (rank == best_rank && depth(rows[k].orbits[i]) > depth(rows[best->first].orbits[best->second])))
        best = std::pair{k, i};
    }
  return best;
}

// Whether a quick row may decide against the best b: it holds an orbit whose rank and depth come
// within `near` of b's, or whose test of the rule (a cone margin, the smaller tension, the
// growth rate) is within `near` of its sign change.
bool rivals(const Row& row, const SteadyOrbit& b, int b_rank, double near, double near_rate) {
  for (std::size_t i = 0; i < row.orbits.size(); ++i) {
    const SteadyOrbit& o = row.orbits[i];
    if (std::abs(o.margins.up) < near || std::abs(o.margins.down) < near || std::min(o.T1, o.T2) < near) return true;
    if (std::isnan(row.growth[i])) continue;
    if (std::abs(row.growth[i]) < near_rate) return true;
    if (rank_of(row.growth[i]) <= b_rank && depth(o) > depth(b) - near) return true;
  }
  return false;
}
}  // namespace

std::optional<SeedOrbit> scan_locked_orbit_seed(const physics::Model& m, double omega) {
  const std::vector<double> grid = stuck_grid(m, kSeedGridPoints);
  std::vector<Row> rows(grid.size());
  const auto fill = [&](std::size_t k, bool exact) {
    const OrbitProblem pb{m, omega, Closure::Stuck, grid[k]};
    Row& row = rows[k];
    row.orbits = orbits_at(pb, exact ? SolveEffort{} : kQuickRow);
    row.exact = exact;
    row.growth.clear();
    for (const auto& o : row.orbits)
      row.growth.push_back(o.admissible ? stability({m, omega, o.closure, o.s}, unknowns(o)).growth
                                        : std::numeric_limits<double>::quiet_NaN());
  };
  for (std::size_t k = 0; k < grid.size(); ++k) fill(k, false);
  // Forces and rates far below what a quick row's round-off could move.
  const double near = 1e-9 * scales(m).force, near_rate = 1e-9 * (omega + std::sqrt(m.p.gravity / m.p.string_length));
  for (;;) {
    const auto best = best_of(rows);
    if (!best) return bottom_seed(m, omega);
    const SteadyOrbit& b = rows[best->first].orbits[best->second];
    const int b_rank = rank_of(rows[best->first].growth[best->second]);
    std::vector<std::size_t> redo;
    for (std::size_t k = 0; k < rows.size(); ++k)
      if (!rows[k].exact && (k == best->first || rivals(rows[k], b, b_rank, near, near_rate))) redo.push_back(k);
    if (redo.empty()) return SeedOrbit{b, b_rank == 1, b_rank};
    for (const std::size_t k : redo) fill(k, true);
  }
}

std::optional<SeedOrbit> solve_locked_orbit_seed(const physics::Model& m, double omega) {
  const auto is_stable = [&](const SteadyOrbit& o) { return stability({m, omega, o.closure, o.s}, unknowns(o)).stable; };
  std::optional<SeedOrbit> best;
  const auto consider = [&](const SteadyOrbit& o, int rank, bool stable) {
    if (!best || rank < best->rank || (rank == best->rank && depth(o) > depth(best->orbit))) best = SeedOrbit{o, stable, rank};
  };
  for (const double s : stuck_grid(m, kSeedGridPoints))
    for (const auto& o : orbits_at({m, omega, Closure::Stuck, s})) {
      if (!o.admissible) continue;
      const bool st = is_stable(o);
      consider(o, st ? 1 : 2, st);
    }
  return best ? best : bottom_seed(m, omega);
}

namespace {
// Every input of the solve, bit for bit: each parameter and layer of the table
// (physics/parameter_table.hpp) and ω_m. Equal keys, equal inputs.
std::string seed_key(const physics::Model& m, double omega) {
  std::string key;
  const auto put = [&](double v) {  // the double's bytes (emscripten's libc++ has no std::bit_cast)
    char bytes[sizeof v];
    std::memcpy(bytes, &v, sizeof v);
    key.append(bytes, sizeof v);
  };
  put(omega);
  for (const double v : physics::parameter_row(m.p)) put(v);
  for (const physics::LayerInfo& layer : physics::layer_table()) {
    if (layer.kind == physics::LayerInfo::Kind::Number) put(m.layers.*layer.number);
    else key += layer.value(m.layers) + '\0';
  }
  return key;
}

// The solved seeds of this process, oldest evicted first past kCapacity (the chains of one grid
// point that start at the same ω_m ask for the same seed).
class SeedCache {
 public:
  std::optional<std::optional<SeedOrbit>> find(const std::string& key) {
    const std::lock_guard lock(mutex_);
    const auto it = seeds_.find(key);
    if (it == seeds_.end()) return std::nullopt;
    return it->second;
  }
  void insert(const std::string& key, const std::optional<SeedOrbit>& seed) {
    const std::lock_guard lock(mutex_);
    if (!seeds_.emplace(key, seed).second) return;
    order_.push_back(key);
    if (order_.size() > kCapacity) {
      seeds_.erase(order_.front());
      order_.pop_front();
    }
  }

 private:
  static constexpr std::size_t kCapacity = 4096;
  std::mutex mutex_;
  std::map<std::string, std::optional<SeedOrbit>> seeds_;
  std::deque<std::string> order_;
};
}  // namespace

std::optional<SeedOrbit> locked_orbit_seed(const physics::Model& m, double omega) {
  static SeedCache cache;
  const std::string key = seed_key(m, omega);
  if (auto hit = cache.find(key)) return *hit;
  std::optional<SeedOrbit> seed = scan_locked_orbit_seed(m, omega);  // outside the lock: threads solve in parallel
  cache.insert(key, seed);
  return seed;
}

}  // namespace ajx::orbits
