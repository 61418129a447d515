// Explicit Euler, y1 = y0 + h f(t0, y0): order 1, fixed step (the paper's baseline at
// h = 1/2000 s). Dense output: cubic Hermite on (y0, f0, y1, f1), f1 evaluated lazily.
#pragma once
#include "numerics/derivative_cache.hpp"
#include "numerics/stepper.hpp"

namespace ajx::numerics {

class Euler final : public Stepper {
 public:
  std::string_view name() const override { return "euler"; }
  int order() const override { return 1; }
  bool adaptive() const override { return false; }

  double attempt(const System& f, double t, const Vec& y, double h, Vec& y_new,
                 const Tolerances& tol) override;
  void accept(const System& f) override;
  void dense(const System& f, double theta, Vec& out) override;
  void reset() override;

 private:
  DerivativeCache cache_;
  double t_ = 0.0, h_ = 0.0;
  Vec y0_, y1_, f0_, f1_;
  bool have_f1_ = false;
};

}  // namespace ajx::numerics
