#include "sweep/seeds.hpp"

#include <cstdint>
#include <random>
#include <stdexcept>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "orbits/orbit_seed.hpp"
#include "physics/contact_modes.hpp"
#include "sim/simulation.hpp"

namespace ajx::sweep {

physics::State seed_state(const physics::Model& m, const physics::MotorSchedule& schedule, const std::string& seed,
                          double omega, int perturbation, double kick) {
  using physics::Vec3;
  physics::State s;
  if (seed == "hanging") {
    s = sim::hanging_at_rest(m, schedule);
  } else if (seed == "circular_high") {
    const double scale = m.p.string_length / 0.826;  // Table 1 was measured on l = 0.826 m
    const Vec3 r1 = scale * Vec3(-0.14427, 0.0, -0.52483), r2 = scale * Vec3(0.11924, 0.0, -0.62353);
    const Vec3 w(0, 0, omega);
    s = sim::explicit_state(m, schedule, r1, r2, w.cross(r1), w.cross(r2), physics::Mode::Sliding, 0.0,
                            0.1 * m.p.string_length);
  } else if (seed == "locked_orbit") {
    // An equilibrium of the co-rotating frame (orbits/orbit_seed.hpp), turned to the top's phase.
    const auto o = orbits::locked_orbit_seed(m, omega);
    if (!o) throw std::invalid_argument(fmt::format("no locked orbit at ω_m = {} rad/s", omega));
    const physics::TopKinematics top = schedule.top(0.0);
    const Eigen::AngleAxisd turn(top.phi, Vec3::UnitZ());
    const Vec3 r1 = turn * o->orbit.p1, r2 = turn * o->orbit.p2, w(0, 0, omega);
    s = sim::explicit_state(m, schedule, r1, r2, w.cross(r1), w.cross(r2),
                            o->orbit.closure == orbits::Closure::BottomStop ? physics::Mode::BottomStop
                                                                             : physics::Mode::Stuck);
  } else {
    throw std::invalid_argument("unknown seed '" + seed + "'; allowed: hanging, circular_high, locked_orbit");
  }
  if (perturbation > 0) {
    // FNV-1a of the seed name: the same kicks on every platform.
    std::uint64_t h = 1469598103934665603ULL;
    for (unsigned char ch : seed) h = (h ^ ch) * 1099511628211ULL;
    std::mt19937_64 rng(h ^ (0x9e3779b97f4a7c15ULL * std::uint64_t(perturbation)));
    std::normal_distribution<double> N(0.0, kick);
    for (int k = 0; k < 6; ++k) s.y(physics::idx::v1 + k) += N(rng);
    const physics::TopKinematics top = schedule.top(s.t);
    physics::project_velocities(m, s.contact, top, s.y);
  }
  return s;
}

}  // namespace ajx::sweep
