// Classic 4-stage Runge-Kutta (Kutta 1901): order 4, fixed step.
// Dense output: cubic Hermite on (y0, f0, y1, f1), f1 evaluated lazily.
#pragma once
#include "numerics/derivative_cache.hpp"
#include "numerics/stepper.hpp"

namespace ajx::numerics {

class Rk4 final : public Stepper {
 public:
  std::string_view name() const override { return "rk4"; }
  int order() const override { return 4; }
  bool adaptive() const override { return false; }

  double attempt(const System& f, double t, const Vec& y, double h, Vec& y_new,
                 const Tolerances& tol) override;
  void accept(const System& f) override;
  void dense(const System& f, double theta, Vec& out) override;
  void reset() override;

 private:
  DerivativeCache cache_;
  double t_ = 0.0, h_ = 0.0;
  Vec y0_, y1_, k1_, k2_, k3_, k4_, tmp_, f1_;
  bool have_f1_ = false;
};

}  // namespace ajx::numerics
