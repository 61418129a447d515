#include "numerics/rk4.hpp"

#include "numerics/hermite.hpp"

namespace ajx::numerics {

// k1 = f(t, y), k2 = f(t + h/2, y + h/2 k1), k3 = f(t + h/2, y + h/2 k2),
// k4 = f(t + h, y + h k3), y1 = y + h/6 (k1 + 2 k2 + 2 k3 + k4).
double Rk4::attempt(const System& f, double t, const Vec& y, double h, Vec& y_new,
                    const Tolerances& /*tol*/) {
  const auto n = y.size();
  y0_ = y;  // first: y_new may alias y
  k2_.resize(n);
  k3_.resize(n);
  k4_.resize(n);
  cache_.get(f, t, y0_, k1_, rhs_evals_);
  const double hh = 0.5 * h;
  tmp_ = y0_ + hh * k1_;
  f(t + hh, tmp_, k2_);
  tmp_ = y0_ + hh * k2_;
  f(t + hh, tmp_, k3_);
  tmp_ = y0_ + h * k3_;
  f(t + h, tmp_, k4_);
  rhs_evals_ += 3;
  y_new = y0_ + (h / 6.0) * (k1_ + 2.0 * (k2_ + k3_) + k4_);
  t_ = t;
  h_ = h;
  y1_ = y_new;
  have_f1_ = false;
  return 0.0;
}

void Rk4::accept(const System& /*f*/) {}

void Rk4::dense(const System& f, double theta, Vec& out) {
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
  hermite_cubic(theta, h_, y0_, k1_, y1_, f1_, out);
}

void Rk4::reset() { cache_.block(); }

}  // namespace ajx::numerics
