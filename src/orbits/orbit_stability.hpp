// Linear stability of a locked orbit: the eigenvalues of the co-rotating dynamics
// (corotating_frame.hpp) linearised at the equilibrium and restricted to the constraint
// manifold of the mode that holds it (stuck at s or on the bottom stop: L1, L2 fixed, 4
// degrees of freedom; sliding without friction: L1 + L2 = l, 5). With N an orthonormal basis
// of ker J (J the 2×6 or 1×6 constraint Jacobian), the tangent space {J δq = 0, J δq̇ = 0} is
// invariant, and the restricted matrix is B = diag(N, N)ᵀ A diag(N, N), A = ∂(dz/dt)/∂z.
// Eigenvalues in the frame: Re λ > 0 grows as e^{Re λ t}; Im λ is the frequency of the
// growing oscillation seen from the co-rotating frame.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "orbits/corotating_frame.hpp"
#include "orbits/steady_orbit.hpp"

namespace ajx::orbits {

struct Stability {
  physics::Contact contact{};     // the mode linearised
  Eigen::VectorXcd eigenvalues;   // sorted by real part, largest first [1/s]
  double growth = 0.0;            // max Re λ [1/s]
  double frequency = 0.0;         // |Im λ| of that eigenvalue [rad/s]
  bool stable = false;            // growth < 0
  Eigen::Matrix<std::complex<double>, 12, 1> leading_mode;  // its eigenvector in z = (q, q̇)
};

// Frame coordinates of the equilibrium X: q = (p1, p2), q̇ = 0.
Vec12 frame_coordinates(const Vec9& X);

// The order of eigenvalues by real part, largest first; of a conjugate pair, Im > 0 first.
std::vector<int> growth_order(const Eigen::VectorXcd& ev);

// Re λ below which an eigenvalue counts as zero (the finite differences' noise): 1e-7 of the
// fastest rate of an orbit at ω, ω + √(g/l) [1/s].
double growth_noise(const physics::Model& m, double omega);

Stability stability(const OrbitProblem& pb, const Vec9& X);

}  // namespace ajx::orbits
