// The state vector seen by the integrators: a flat column of doubles.
// Fixed capacity, dynamic length: no heap allocation in the hot loop.
#pragma once
#include <Eigen/Core>
#include <functional>

namespace ajx::numerics {

inline constexpr int kMaxDim = 32;
using Vec = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxDim, 1>;

// Calls fn.template operator()<N>() with N = n when n is a state size compiled as fixed-size
// kernels (15: the Astrojax state, 17: with the motor's ledger, 19: with the string's tie,
// physics/state.hpp), else with N = Eigen::Dynamic. The steppers use it to combine their stages
// on Eigen::Map<Matrix<double, N, 1>> views: unrolled element-wise loops, the same arithmetic
// per element.
template <class Fn>
decltype(auto) with_state_size(Eigen::Index n, Fn&& fn) {
  switch (n) {
    case 15:
      return fn.template operator()<15>();
    case 17:
      return fn.template operator()<17>();
    case 19:
      return fn.template operator()<19>();
    default:
      return fn.template operator()<Eigen::Dynamic>();
  }
}

// The system: a pure function dy/dt = f(t, y) (Boost.Odeint's concept, without its policies).
using System = std::function<void(double t, const Vec& y, Vec& dydt)>;

}  // namespace ajx::numerics
