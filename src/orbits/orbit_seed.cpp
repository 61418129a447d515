#include "orbits/orbit_seed.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <string>

#include "orbits/orbit_families.hpp"
#include "orbits/orbit_stability.hpp"
#include "physics/parameter_table.hpp"

namespace ajx::orbits {

std::optional<SeedOrbit> solve_locked_orbit_seed(const physics::Model& m, double omega) {
  const auto depth = [](const SteadyOrbit& o) { return std::min(o.margins.up, o.margins.down); };
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
  if (best || !m.layers.bottom_stop) return best;
  for (const auto& o : orbits_at({m, omega, Closure::BottomStop, 0.0})) {
    if (!o.admissible) continue;
    const bool st = is_stable(o);
    if (!best || (st && !best->stable)) best = SeedOrbit{o, st, 3};
  }
  return best;
}

namespace {
// Every input of the solve, bit for bit: each parameter and layer of the table
// (physics/parameter_table.hpp) and ω_m. Equal keys, equal inputs.
std::string seed_key(const physics::Model& m, double omega) {
  std::string key;
  const auto put = [&](double v) {
    const auto bits = std::bit_cast<std::uint64_t>(v);
    key.append(reinterpret_cast<const char*>(&bits), sizeof bits);
  };
  put(omega);
  for (const double v : physics::parameter_row(m.p)) put(v);
  for (const physics::LayerInfo& layer : physics::layer_table()) {
    if (layer.kind == physics::LayerInfo::Kind::Number) put(m.layers.*layer.number);
    else key += layer.value(m.layers) + '\0';
  }
  return key;
}

// The solved seeds of this process, oldest evicted first past kCapacity (a map's chains of one
// grid point, and its probes' restarts, ask for the same seed).
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
  std::optional<SeedOrbit> seed = solve_locked_orbit_seed(m, omega);  // outside the lock: threads solve in parallel
  cache.insert(key, seed);
  return seed;
}

}  // namespace ajx::orbits
