// Dormand-Prince 5(4) (RK5(4)7M): 7 stages, FSAL (k7 = f(t1, y1) is the next k1 unless
// reset()), 5th-order propagation (local extrapolation), embedded 4th-order error estimate,
// Hairer's 4th-order continuous extension for dense().
#pragma once
#include "numerics/derivative_cache.hpp"
#include "numerics/stepper.hpp"

namespace ajx::numerics {

class Dopri5 final : public Stepper {
 public:
  std::string_view name() const override { return "dopri5"; }
  int order() const override { return 5; }
  bool adaptive() const override { return true; }

  double attempt(const System& f, double t, const Vec& y, double h, Vec& y_new,
                 const Tolerances& tol) override;
  void accept(const System& f) override;
  void dense(const System& f, double theta, Vec& out) override;
  void reset() override;

 private:
  DerivativeCache cache_;
  double t_ = 0.0, h_ = 0.0;
  Vec y0_, y1_, k1_, k2_, k3_, k4_, k5_, k6_, k7_, tmp_, err_;
  Vec r2_, r3_, r4_, r5_;  // dense-output polynomial (r1 = y0)
  bool dense_ready_ = false;
};

}  // namespace ajx::numerics
