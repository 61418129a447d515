// Fixed-step methods with a cubic Hermite dense output on (y0, f0, y1, f1):
// p(θ) = h00 y0 + h10 h f0 + h01 y1 + h11 h f1, θ in [0, 1], with
// h00 = (1-θ)²(1+2θ), h10 = θ(1-θ)², h01 = θ²(3-2θ), h11 = θ²(θ-1).
// Interpolation error O(h⁴) (order 3) when y0, y1 are exact. f0 is the first stage of the
// step; f1 = f(t1, y1) is evaluated lazily and shared with the next step's first stage.
#pragma once
#include "numerics/derivative_cache.hpp"
#include "numerics/stepper.hpp"

namespace ajx::numerics {

inline void hermite_cubic(double s, double h, const Vec& y0, const Vec& f0, const Vec& y1,
                          const Vec& f1, Vec& out) {
  const double s1 = 1.0 - s;
  const double h00 = s1 * s1 * (1.0 + 2.0 * s);
  const double h10 = s * s1 * s1 * h;
  const double h01 = s * s * (3.0 - 2.0 * s);
  const double h11 = -s * s * s1 * h;
  out = h00 * y0 + h10 * f0 + h01 * y1 + h11 * f1;
}

// The part every fixed-step method shares: step bookkeeping, the first stage from the
// derivative cache, and the Hermite interpolant. A method supplies only its tableau.
class HermiteStepper : public Stepper {
 public:
  bool adaptive() const final { return false; }

  double attempt(const System& f, double t, const Vec& y, double h, Vec& y_new,
                 const Tolerances& /*tol*/) final {
    y0_ = y;  // first: y_new may alias y
    cache_.get(f, t, y0_, f0_, rhs_evals_);
    t_ = t;
    h_ = h;
    advance(f, t, h, y_new);
    y1_ = y_new;
    have_f1_ = false;
    return 0.0;
  }
  void accept(const System& /*f*/) final {}
  void dense(const System& f, double theta, Vec& out) final {
    if (!have_f1_) {
      const double t1 = t_ + h_;
      if (cache_.holds(t1, y1_)) {
        f1_ = cache_.value();
      } else {
        f1_.resize(y1_.size());
        f(t1, y1_, f1_);
        ++rhs_evals_;
        cache_.offer(t1, y1_, f1_);
      }
      have_f1_ = true;
    }
    hermite_cubic(theta, h_, y0_, f0_, y1_, f1_, out);
  }
  void reset() final { cache_.block(); }

 protected:
  // One step from (t, y0_) with f0_ = f(t, y0_) already known; counts its own evaluations.
  virtual void advance(const System& f, double t, double h, Vec& y_new) = 0;

  Vec y0_, f0_;

 private:
  DerivativeCache cache_;
  double t_ = 0.0, h_ = 0.0;
  Vec y1_, f1_;
  bool have_f1_ = false;
};

}  // namespace ajx::numerics
