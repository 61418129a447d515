// Damped Newton for F(x) = 0 in N unknowns, the one root finder of the orbit solvers
// (orbits/steady_orbit, orbits/lagging_orbit):
//   J = ∂F/∂x by central differences, steps h·d_j with h = ε^(1/3) (error O(h²) + O(ε/h), least
//       there) and d the unknowns' scales;
//   Δx = −J⁻¹F by the caller's linear solve (rank-revealing where a symmetry leaves a direction
//       free), shrunk by the caller's limit far from the root;
//   backtracking: Δx halved up to 12 times until max|F| falls; no descent ends the iteration
//       (the round-off floor, or divergence).
// Converged when max|F| <= tol.
#pragma once
#include <Eigen/Core>
#include <cmath>
#include <limits>

namespace ajx::numerics {

template <int N>
struct NewtonRoot {
  Eigen::Matrix<double, N, 1> x;
  double residual = 0.0;  // max |F| at x
  int iterations = 0;
  bool converged = false;
};

// ∂F/∂x by central differences with steps h·scale(j).
template <int N, class F>
Eigen::Matrix<double, N, N> central_jacobian(const F& f, const Eigen::Matrix<double, N, 1>& x,
                                             const Eigen::Matrix<double, N, 1>& scale) {
  const double h = std::cbrt(std::numeric_limits<double>::epsilon());
  Eigen::Matrix<double, N, N> J;
  for (int j = 0; j < N; ++j) {
    Eigen::Matrix<double, N, 1> xp = x, xm = x;
    xp(j) += h * scale(j);
    xm(j) -= h * scale(j);
    J.col(j) = (f(xp) - f(xm)) / (2.0 * h * scale(j));
  }
  return J;
}

// `solve(J, F)` returns −J⁻¹F; `limit(dx)` shrinks a step that goes too far (or returns it).
template <int N, class F, class Solve, class Limit>
NewtonRoot<N> damped_newton(const F& f, Eigen::Matrix<double, N, 1> x, const Eigen::Matrix<double, N, 1>& scale,
                            double tol, int max_iterations, const Solve& solve, const Limit& limit) {
  using Vec = Eigen::Matrix<double, N, 1>;
  constexpr double inf = std::numeric_limits<double>::infinity();
  const auto size = [](const Vec& r) { return r.allFinite() ? r.template lpNorm<Eigen::Infinity>() : inf; };
  Vec r = f(x);
  double norm = size(r);
  int it = 0;
  for (; it < max_iterations && norm > tol && std::isfinite(norm); ++it) {
    Vec dx = solve(central_jacobian<N>(f, x, scale), r);
    if (!dx.allFinite()) break;
    dx = limit(dx);
    double t = 1.0, trial_norm = inf;
    Vec trial;
    for (int k = 0; k < 12; ++k, t *= 0.5) {
      trial = x + t * dx;
      trial_norm = size(f(trial));
      if (trial_norm < norm) break;
    }
    if (!(trial_norm < norm)) break;
    x = trial;
    norm = trial_norm;
    r = f(x);
  }
  return {x, norm, it, norm <= tol};
}

}  // namespace ajx::numerics
