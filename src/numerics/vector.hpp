// The state vector seen by the integrators: a flat column of doubles.
// Fixed capacity, dynamic length: no heap allocation in the hot loop.
#pragma once
#include <Eigen/Core>
#include <functional>

namespace ajx::numerics {

inline constexpr int kMaxDim = 32;
using Vec = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxDim, 1>;

// The system: a pure function dy/dt = f(t, y) (Boost.Odeint's concept, without its policies).
using System = std::function<void(double t, const Vec& y, Vec& dydt)>;

}  // namespace ajx::numerics
