#include "sim/step_bound.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "physics/state.hpp"

namespace ajx::sim {

double guard_rate(const physics::Parameters& p, const physics::TopKinematics& top, const numerics::Vec& y) {
  using namespace physics::idx;
  const double R2 = p.drive_radius * p.drive_radius;
  double rel = 0.0, centrifugal = 0.0;
  for (int b : {r1, r2}) {
    const double x = y(b), yy = y(b + 1), vx = y(b + 6), vy = y(b + 7);
    const double rho2 = x * x + yy * yy;
    const double theta_dot = (x * vy - yy * vx) / std::max(rho2, R2);
    rel = std::max(rel, std::abs(top.omega - theta_dot));
    centrifugal = std::max(centrifugal, theta_dot * theta_dot * std::sqrt(rho2));
  }
  const physics::Vec3 p1 = y.segment<3>(r1), p2 = y.segment<3>(r2);
  const double L_short = std::min((p1 - top.a).norm(), (p2 - p1).norm());
  const double g_eff = std::hypot(p.gravity, centrifugal);
  const double swing = std::sqrt(g_eff / std::max(L_short, 1e-4 * p.string_length));
  return std::max(rel, swing);
}

double guard_step_bound(const physics::Parameters& p, const physics::TopKinematics& top, const numerics::Vec& y,
                        int event_samples) {
  return (event_samples + 1) * kRadiansPerStep / guard_rate(p, top, y);
}

bool has_change_bound(physics::Guard g) {
  using physics::Guard;
  switch (g) {
    case Guard::LandBottom:
    case Guard::WatchBottom:
    case Guard::ReachBall:
    case Guard::LandTop:
    case Guard::WatchTop:
    case Guard::ReachTop:
    case Guard::Taut:
      return true;
    default:
      return false;
  }
}

double guard_change_bound(physics::Guard g, double top_travel, const numerics::Vec& e) {
  using namespace physics::idx;
  using physics::Guard;
  const double d1 = e.segment<3>(r1).norm(), d2 = e.segment<3>(r2).norm();
  switch (g) {
    case Guard::LandBottom:
    case Guard::WatchBottom:
    case Guard::ReachBall:
      return d1 + d2;
    case Guard::LandTop:
    case Guard::WatchTop:
    case Guard::ReachTop:
      return d1 + top_travel;
    case Guard::Taut:
      return 2.0 * d1 + d2 + top_travel;
    default:
      return std::numeric_limits<double>::infinity();
  }
}

bool corotates(const physics::TopKinematics& top, const numerics::Vec& y) {
  using namespace physics::idx;
  double lab = 0.0, turning = 0.0;
  for (int b : {r1, r2}) {
    const double x = y(b), yy = y(b + 1), vx = y(b + 6), vy = y(b + 7);
    lab += std::hypot(vx, vy);
    turning += std::hypot(vx + top.omega * yy, vy - top.omega * x);
  }
  return turning < lab;
}

}  // namespace ajx::sim
