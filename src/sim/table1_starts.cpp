#include "sim/table1_starts.hpp"

#include <array>
#include <cmath>
#include <fmt/format.h>
#include <stdexcept>

namespace ajx::sim {

namespace {

// One column of Table 1 [cm], in the table's own axes: x1, y1, z1, x2, y2, z2 at steps 0 and 1.
struct Column {
  std::array<double, 6> q0, q1;
};

// The flower orbits' columns as printed (the circular ones depend on θ, below).
constexpr std::array<Column, 4> kFlower{{
    {{3.937, -0.426, -51.755, 21.817, 9.257, -60.846}, {3.568, -0.014, -51.783, 22.251, 8.569, -60.846}},
    {{3.837, -0.416, -51.775, 21.817, 9.257, -60.846}, {3.568, -0.014, -51.783, 22.251, 8.569, -60.846}},
    {{3.937, -0.406, -51.775, 22.817, 9.257, -60.846}, {3.568, -0.014, -51.783, 22.251, 8.569, -60.846}},
    {{3.837, -0.426, -51.775, 22.817, 9.257, -60.846}, {3.468, -0.014, -51.783, 22.251, 8.569, -60.846}},
}};

// Circular orbits 1 and 2 at the per-step angle θ.
Column circular(int which, double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  if (which == 1)
    return {{-14.427, 0.0, -52.483, 11.924, 0.0, -62.353},
            {-14.427 * c, 14.427 * s, -52.483, 11.924 * c, -11.924 * s, -62.353}};
  return {{-14.426, 0.0, -52.484, 11.924, 0.0, -62.353},
          {-14.427 * c, 14.428 * s, -52.483, 11.924 * c, -11.924 * s, -62.353}};
}

// cm -> m, y mirrored.
physics::Vec3 point(const std::array<double, 6>& q, int ball) {
  const int o = 3 * ball;
  return 0.01 * physics::Vec3(q[o], -q[o + 1], q[o + 2]);
}

}  // namespace

const std::vector<std::string>& table1_orbits() {
  static const std::vector<std::string> names{"circular1", "circular2", "flower1", "flower2", "flower3", "flower4"};
  return names;
}

PairStart table1_pair(std::string_view name, double omega, double h) {
  Column col;
  if (name == "circular1" || name == "circular2")
    col = circular(name == "circular1" ? 1 : 2, omega * h);
  else if (name.size() == 7 && name.substr(0, 6) == "flower" && name[6] >= '1' && name[6] <= '4')
    col = kFlower[std::size_t(name[6] - '1')];
  else
    throw std::invalid_argument(fmt::format("unknown Table 1 orbit '{}'; allowed: {}", name,
                                            fmt::join(table1_orbits(), ", ")));
  PairStart p;
  p.r1_0 = point(col.q0, 0);
  p.r2_0 = point(col.q0, 1);
  p.r1_1 = point(col.q1, 0);
  p.r2_1 = point(col.q1, 1);
  return p;
}

}  // namespace ajx::sim
