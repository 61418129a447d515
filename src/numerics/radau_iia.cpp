#include "numerics/radau_iia.hpp"

#include <cmath>
#include <limits>

namespace ajx::numerics {

namespace {

// The Radau IIA tableau, s = 3, with √6.
const double s6 = std::sqrt(6.0);
const double kC[3] = {(4.0 - s6) / 10.0, (4.0 + s6) / 10.0, 1.0};
const double kA[3][3] = {{(88.0 - 7.0 * s6) / 360.0, (296.0 - 169.0 * s6) / 1800.0, (-2.0 + 3.0 * s6) / 225.0},
                         {(296.0 + 169.0 * s6) / 1800.0, (88.0 + 7.0 * s6) / 360.0, (-2.0 - 3.0 * s6) / 225.0},
                         {(16.0 - s6) / 36.0, (16.0 + s6) / 36.0, 1.0 / 9.0}};
constexpr int kFastIterations = 6;  // more than this: refresh J for the next step
constexpr int kMaxIterations = 12;

}  // namespace

void RadauIIA::refresh(const System& f, double t, double h) {
  const Eigen::Index n = y0_.size();
  J_.resize(n, n);
  tmp_ = y0_;
  ftmp_.resize(n);
  // ∂f/∂y_j ≈ (f(y0 + δ_j e_j) - f0)/δ_j, δ_j = √eps max(|y0_j|, 1e-5).
  for (Eigen::Index j = 0; j < n; ++j) {
    const double d = std::sqrt(std::numeric_limits<double>::epsilon()) * std::max(std::abs(y0_[j]), 1e-5);
    tmp_[j] = y0_[j] + d;
    f(t, tmp_, ftmp_);
    J_.col(j) = (ftmp_ - f0_) / d;
    tmp_[j] = y0_[j];
  }
  rhs_evals_ += n;
  ++jacobians_;
  // I - h (A ⊗ J)
  Eigen::MatrixXd M = Eigen::MatrixXd::Identity(3 * n, 3 * n);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) M.block(i * n, j * n, n, n) -= (h * kA[i][j]) * J_;
  lu_.compute(M);
  lu_h_ = h;
  slow_ = false;
}

// Simplified Newton on G(Z) = Z - h (A ⊗ I) F(Z) = 0 from Z = 0. Converged when the update
// is at round-off level of the state: |ΔZ|∞ <= 1e-13 (|y0|∞ + 1e-3).
bool RadauIIA::newton(const System& f, double t, double h, int max_iter) {
  const Eigen::Index n = y0_.size();
  Z_.setZero(3 * n);
  F_.resize(3 * n);
  G_.resize(3 * n);
  const double scale = 1e-13 * (y0_.cwiseAbs().maxCoeff() + 1e-3);
  for (int k = 1; k <= max_iter; ++k) {
    for (int i = 0; i < 3; ++i) {
      tmp_ = y0_ + Z_.segment(i * n, n);
      f(t + kC[i] * h, tmp_, ftmp_);
      F_.segment(i * n, n) = ftmp_;
    }
    rhs_evals_ += 3;
    ++newton_;
    for (int i = 0; i < 3; ++i)
      G_.segment(i * n, n) =
          Z_.segment(i * n, n) - h * (kA[i][0] * F_.head(n) + kA[i][1] * F_.segment(n, n) + kA[i][2] * F_.tail(n));
    const Eigen::VectorXd dZ = lu_.solve(-G_);
    Z_ += dZ;
    if (!dZ.allFinite()) return false;
    if (dZ.cwiseAbs().maxCoeff() <= scale) {
      slow_ = k > kFastIterations;
      return true;
    }
  }
  return false;
}

void RadauIIA::advance(const System& f, double t, double h, Vec& y_new) {
  const Eigen::Index n = y0_.size();
  tmp_.resize(n);
  ftmp_.resize(n);
  if (slow_ || lu_h_ != h || J_.rows() != n) refresh(f, t, h);
  bool ok = newton(f, t, h, kMaxIterations);
  if (!ok) {  // a stale Jacobian (or a new mode): once more with a fresh one
    refresh(f, t, h);
    ok = newton(f, t, h, kMaxIterations);
  }
  if (!ok) {
    // Newton did not converge: the driver sees a non-finite state and reports the failure.
    y_new = Vec::Constant(n, std::numeric_limits<double>::quiet_NaN());
    slow_ = true;
    return;
  }
  y_new = y0_ + Z_.tail(n);  // stiffly accurate: y1 = Y_3
}

}  // namespace ajx::numerics
