#include "sweep/thresholds.hpp"

#include <numbers>

namespace ajx::sweep {

std::string_view to_string(Threshold t) {
  switch (t) {
    case Threshold::Rise: return "omega_rise";
    case Threshold::Fall: return "omega_fall";
    case Threshold::Omega1: return "omega_1";
    case Threshold::Omega2: return "omega_2";
  }
  return "?";
}

double paper_value(Threshold t) {
  constexpr double pi = std::numbers::pi;
  switch (t) {
    case Threshold::Rise: return 12.63 * pi;
    case Threshold::Fall: return 3.24 * pi;
    case Threshold::Omega1: return 4.80 * pi;
    case Threshold::Omega2: return 15.00 * pi;
  }
  return 0.0;
}

namespace {
Bracket bracket(const ClassedWindow& a, const ClassedWindow& b) {
  return {a.omega_mean(), b.omega_mean(), a.index, b.index};
}
// The first window after i on the same leg (direction dir) that is not unsettled; w.size() if
// the leg ends first. A change of class seen through unsettled windows is bracketed by it.
std::size_t next_settled(const std::vector<ClassedWindow>& w, std::size_t i, int dir) {
  std::size_t j = i + 1;
  while (j < w.size() && w[j].direction == dir && w[j].cls == OrbitClass::NotSettled) ++j;
  return j < w.size() && w[j].direction == dir ? j : w.size();
}
}  // namespace

std::optional<Bracket> find_threshold(Threshold t, const std::vector<ClassedWindow>& w) {
  const std::size_t n = w.size();
  std::optional<Bracket> found;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const ClassedWindow &a = w[i], &b = w[i + 1];
    if (a.cls == OrbitClass::Failed || b.cls == OrbitClass::Failed) continue;
    switch (t) {
      case Threshold::Rise:  // the first climb from fallen on a rising ramp
        if (a.direction > 0 && b.direction > 0 && a.cls == OrbitClass::Fallen && b.cls != OrbitClass::Fallen)
          return bracket(a, b);
        break;
      case Threshold::Fall:  // the first fall onto the ball after a circular orbit, on the way down
        if (a.direction < 0 && circular(a.cls)) {
          const std::size_t j = next_settled(w, i, a.direction);
          if (j < n && w[j].cls == OrbitClass::Fallen) return bracket(a, w[j]);
        }
        break;
      case Threshold::Omega1:  // the last loss of the locked orbit on the way up
        if (a.direction > 0 && b.direction > 0 && a.cls == OrbitClass::LockedCircular &&
            b.cls != OrbitClass::LockedCircular)
          found = bracket(a, b);
        break;
      case Threshold::Omega2:  // the last circular orbit on the way up that gives way to a flower
        // (through unsettled windows): ω2 (docs/guide/thresholds.md). A lock lost to a lag, through an
        // unsettled window, is ω1's business, not this.
        if (a.direction > 0 && circular(a.cls)) {
          const std::size_t j = next_settled(w, i, a.direction);
          if (j < n && w[j].cls == OrbitClass::Flower) found = bracket(a, w[j]);
        }
        break;
    }
  }
  return found;
}

}  // namespace ajx::sweep
