#include "orbits/orbit_stability.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "physics/contact_modes.hpp"

namespace ajx::orbits {

Vec12 frame_coordinates(const Vec9& X) {
  Vec12 z = Vec12::Zero();
  z.head<6>() = X.head<6>();
  return z;
}

std::vector<int> growth_order(const Eigen::VectorXcd& ev) {
  std::vector<int> order(ev.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    if (ev(a).real() != ev(b).real()) return ev(a).real() > ev(b).real();
    return ev(a).imag() > ev(b).imag();
  });
  return order;
}

double growth_noise(const physics::Model& m, double omega) {
  return 1e-7 * (omega + std::sqrt(m.p.gravity / m.p.string_length));
}

Stability stability(const OrbitProblem& pb, const Vec9& X) {
  const physics::Model& m = pb.model;
  Stability st;
  st.contact = holding_contact(m, pb.closure, X(8));
  const Vec12 z0 = frame_coordinates(X);
  const physics::TopKinematics top = corotating_top(m.p.drive_radius, pb.omega);
  const physics::Constraints c = physics::constraints(m, st.contact, top, lab_state(z0, pb.omega));
  // Orthonormal basis of ker J: the right singular vectors beyond the rank n.
  Eigen::MatrixXd J = c.J.topRows(c.n);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(J, Eigen::ComputeFullV);
  const Eigen::MatrixXd N = svd.matrixV().rightCols(6 - c.n);
  const int k = int(N.cols());
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(12, 2 * k);
  P.block(0, 0, 6, k) = N;
  P.block(6, k, 6, k) = N;
  // Central differences along the tangent directions, steps ε^(1/3) of the shorter link L
  // (positions) and of L ω (velocities): the error is O(h²) relative, like leaving the
  // manifold at second order.
  const double l = std::min(X(8), m.p.string_length - X(8)), h = std::cbrt(std::numeric_limits<double>::epsilon());
  const double vscale = l * std::max(pb.omega, std::sqrt(m.p.gravity / l));
  Eigen::MatrixXd B(2 * k, 2 * k);
  for (int j = 0; j < 2 * k; ++j) {
    const double hj = h * (j < k ? l : vscale);
    const Vec12 dz = hj * P.col(j);
    const Vec12 fp = corotating_rhs(m, pb.omega, st.contact, z0 + dz);
    const Vec12 fm = corotating_rhs(m, pb.omega, st.contact, z0 - dz);
    B.col(j) = P.transpose() * ((fp - fm) / (2.0 * hj));
  }
  Eigen::EigenSolver<Eigen::MatrixXd> es(B);
  const Eigen::VectorXcd ev = es.eigenvalues();
  const std::vector<int> order = growth_order(ev);
  st.eigenvalues.resize(ev.size());
  for (int i = 0; i < int(ev.size()); ++i) st.eigenvalues(i) = ev(order[i]);
  st.growth = st.eigenvalues(0).real();
  st.frequency = std::abs(st.eigenvalues(0).imag());
  st.stable = st.growth < 0.0;
  st.leading_mode = P.cast<std::complex<double>>() * es.eigenvectors().col(order[0]);
  return st;
}

}  // namespace ajx::orbits
