#include "physics/hand.hpp"

#include <cmath>
#include <numbers>

namespace ajx::physics {

HandOffset HandPath::offset(double t) const {
  HandOffset o{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  if (!holds(t)) return o;
  constexpr double pi = std::numbers::pi;
  const double T = duration, tau = t / T;
  // w = sin²(πτ), w' = π sin 2πτ, w'' = 2π² cos 2πτ (primes: d/dτ)
  const double s = std::sin(pi * tau), w = s * s, w1 = pi * std::sin(2 * pi * tau), w2 = 2 * pi * pi * std::cos(2 * pi * tau);
  Eigen::Vector3d h = Eigen::Vector3d::Zero(), h1 = h, h2 = h;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const double f = 2 * pi * double(k + 1), c = std::cos(f * tau), sn = std::sin(f * tau);
    h += p[k] * c + q[k] * sn;
    h1 += f * (q[k] * c - p[k] * sn);
    h2 -= f * f * (p[k] * c + q[k] * sn);
  }
  // d = w h; ḋ = (w' h + w h')/T; d̈ = (w'' h + 2 w' h' + w h'')/T²
  o.d = w * h;
  o.d_dot = (w1 * h + w * h1) / T;
  o.d_ddot = (w2 * h + 2 * w1 * h1 + w * h2) / (T * T);
  return o;
}

double HandPath::speed_bound() const {
  double H0 = 0.0, H1 = 0.0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const double a = p[k].norm() + q[k].norm();
    H0 += a;
    H1 += 2 * std::numbers::pi * double(k + 1) * a;
  }
  return duration > 0.0 ? (std::numbers::pi * H0 + H1) / duration : 0.0;
}

}  // namespace ajx::physics
