// Hairer's DOP853: explicit Runge-Kutta of order 8 (12 stages, FSAL-like reuse of f(t1, y1)),
// error estimate combining the embedded 5th- and 3rd-order results as in dop853.f, and a
// 7th-order dense output needing 3 extra stages, computed lazily (only when dense() is first
// called for a step).
#pragma once
#include "numerics/derivative_cache.hpp"
#include "numerics/stepper.hpp"

namespace ajx::numerics {

class Dop853 final : public Stepper {
 public:
  std::string_view name() const override { return "dop853"; }
  int order() const override { return 8; }
  bool adaptive() const override { return true; }

  double attempt(const System& f, double t, const Vec& y, double h, Vec& y_new,
                 const Tolerances& tol) override;
  void accept(const System& f) override;
  void dense(const System& f, double theta, Vec& out) override;
  // The cubic Hermite interpolant through (y0, f0) and (y1, f1): the first four terms of the
  // dense output, with no extra stage (f1 is the next step's k1).
  bool cheap_interpolant(const System& f, double theta, Vec& out) override;
  bool dense_excursion(const System& f, Vec& e) override;
  void reset() override;

 private:
  template <int N>
  double attempt_n(const System& f, double t, const Vec& y, double h, Vec& y_new, const Tolerances& tol);
  void prepare_dense(const System& f);
  void prepare_hermite(const System& f);

  DerivativeCache cache_;
  double t_ = 0.0, h_ = 0.0;
  Vec y0_, y1_, tmp_;
  Vec k1_, k2_, k3_, k4_, k5_, k6_, k7_, k8_, k9_, k10_, k11_, k12_;
  Vec k13_, k14_, k15_, k16_;  // f(t1, y1) and the 3 extra dense-output stages
  Vec r_[8];                   // dense-output polynomial (cont(1..8) of dop853.f)
  bool dense_ready_ = false;
  bool hermite_ready_ = false;  // r_[0..3] hold the Hermite terms (also true once dense_ready_)
};

}  // namespace ajx::numerics
