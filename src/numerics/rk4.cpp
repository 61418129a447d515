#include "numerics/rk4.hpp"

namespace ajx::numerics {

// k1 = f(t, y), k2 = f(t + h/2, y + h/2 k1), k3 = f(t + h/2, y + h/2 k2),
// k4 = f(t + h, y + h k3), y1 = y + h/6 (k1 + 2 k2 + 2 k3 + k4).
void Rk4::advance(const System& f, double t, double h, Vec& y_new) {
  const auto n = y0_.size();
  k2_.resize(n);
  k3_.resize(n);
  k4_.resize(n);
  const double hh = 0.5 * h;
  tmp_ = y0_ + hh * f0_;
  f(t + hh, tmp_, k2_);
  tmp_ = y0_ + hh * k2_;
  f(t + hh, tmp_, k3_);
  tmp_ = y0_ + h * k3_;
  f(t + h, tmp_, k4_);
  rhs_evals_ += 3;
  y_new = y0_ + (h / 6.0) * (f0_ + 2.0 * (k2_ + k3_) + k4_);
}

}  // namespace ajx::numerics
