// Radau IIA, 3 stages, order 5 (Hairer & Wanner, Solving ODEs II, IV.5): implicit, L-stable
// and stiffly accurate (y1 is the last stage), at a fixed step. For the stiff regularised
// friction tanh(ṡ/ε) as ε -> 0, where explicit methods need h ~ ε. Stages Z_i = Y_i - y0 solve
//   Z = h (A ⊗ I) F(Z),  F_i = f(t + c_i h, y0 + Z_i),
// by simplified Newton with the matrix I - h A ⊗ J (3n x 3n, Eigen's partial-pivoting LU),
// J = ∂f/∂y by forward differences at the step start. J and the LU are kept while Newton
// converges fast and recomputed when it slows (a stale J changes the cost, not the result).
// Where Newton fails even with a fresh J (a near-discontinuous f, e.g. tanh(ṡ/ε) with tiny ε),
// the step is taken as two half steps, recursively up to 2^10 pieces, and counted.
// Dense output: cubic Hermite (hermite.hpp), as for the other fixed-step methods.
#pragma once
#include <Eigen/Dense>

#include "numerics/hermite.hpp"

namespace ajx::numerics {

class RadauIIA final : public HermiteStepper {
 public:
  std::string_view name() const override { return "radau_iia"; }
  int order() const override { return 5; }
  long newton_iterations() const { return newton_; }
  long jacobians() const { return jacobians_; }
  long substeps() const { return substeps_; }  // steps split because Newton failed

 private:
  void advance(const System& f, double t, double h, Vec& y_new) override;
  void refresh(const System& f, double t, const Vec& y0, const Vec& f0, double h);  // J at (t, y0), LU for h
  bool newton(const System& f, double t, const Vec& y0, double h, int max_iter);
  bool solve(const System& f, double t, const Vec& y0, const Vec& f0, double h, Vec& y1, int depth);

  Eigen::MatrixXd J_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  double lu_h_ = 0.0;     // h of the factorised matrix (0: none)
  bool slow_ = true;      // last Newton was slow: refresh before the next step
  Eigen::VectorXd Z_, F_, G_;
  Vec tmp_, ftmp_;
  Vec fsub_;
  long newton_ = 0, jacobians_ = 0, substeps_ = 0;
};

}  // namespace ajx::numerics
