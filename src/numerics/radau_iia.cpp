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
constexpr int kMaxSplits = 10;      // at most 2^10 pieces of one step

}  // namespace

void RadauIIA::refresh(const System& f, double t, const Vec& y0, const Vec& f0, double h) {
  const Eigen::Index n = y0.size();
  J_.resize(n, n);
  tmp_ = y0;
  ftmp_.resize(n);
  // ∂f/∂y_j ≈ (f(y0 + δ_j e_j) - f0)/δ_j, δ_j = √eps max(|y0_j|, 1e-5).
  for (Eigen::Index j = 0; j < n; ++j) {
    const double d = std::sqrt(std::numeric_limits<double>::epsilon()) * std::max(std::abs(y0[j]), 1e-5);
    tmp_[j] = y0[j] + d;
    f(t, tmp_, ftmp_);
    J_.col(j) = (ftmp_ - f0) / d;
    tmp_[j] = y0[j];
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
bool RadauIIA::newton(const System& f, double t, const Vec& y0, double h, int max_iter) {
  const Eigen::Index n = y0.size();
  Z_.setZero(3 * n);
  F_.resize(3 * n);
  G_.resize(3 * n);
  const double scale = 1e-13 * (y0.cwiseAbs().maxCoeff() + 1e-3);
  for (int k = 1; k <= max_iter; ++k) {
    for (int i = 0; i < 3; ++i) {
      tmp_ = y0 + Z_.segment(i * n, n);
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

bool RadauIIA::solve(const System& f, double t, const Vec& y0, const Vec& f0, double h, Vec& y1, int depth) {
  const Eigen::Index n = y0.size();
  if (slow_ || lu_h_ != h || J_.rows() != n) refresh(f, t, y0, f0, h);
  bool ok = newton(f, t, y0, h, kMaxIterations);
  if (!ok) {  // a stale Jacobian (or a new mode): once more with a fresh one
    refresh(f, t, y0, f0, h);
    ok = newton(f, t, y0, h, kMaxIterations);
  }
  if (ok) {
    y1 = y0 + Z_.tail(n);  // stiffly accurate: y1 = Y_3
    return true;
  }
  slow_ = true;
  if (depth >= kMaxSplits) return false;
  // Two half steps; the middle state needs its own f for the second half's Jacobian.
  ++substeps_;
  Vec ymid(n), fmid(n);
  if (!solve(f, t, y0, f0, 0.5 * h, ymid, depth + 1)) return false;
  f(t + 0.5 * h, ymid, fmid);
  ++rhs_evals_;
  return solve(f, t + 0.5 * h, ymid, fmid, 0.5 * h, y1, depth + 1);
}

void RadauIIA::advance(const System& f, double t, double h, Vec& y_new) {
  const Eigen::Index n = y0_.size();
  tmp_.resize(n);
  ftmp_.resize(n);
  if (!solve(f, t, y0_, f0_, h, y_new, 0)) {
    // Newton did not converge even on the smallest piece: the driver sees a non-finite state
    // and reports the failure.
    y_new = Vec::Constant(n, std::numeric_limits<double>::quiet_NaN());
  }
}

}  // namespace ajx::numerics
