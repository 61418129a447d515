#include "numerics/euler.hpp"

#include "numerics/hermite.hpp"

namespace ajx::numerics {

double Euler::attempt(const System& f, double t, const Vec& y, double h, Vec& y_new,
                      const Tolerances& /*tol*/) {
  y0_ = y;  // first: y_new may alias y
  cache_.get(f, t, y0_, f0_, rhs_evals_);
  t_ = t;
  h_ = h;
  y_new = y0_ + h * f0_;
  y1_ = y_new;
  have_f1_ = false;
  return 0.0;
}

void Euler::accept(const System& /*f*/) {}

void Euler::dense(const System& f, double theta, Vec& out) {
  if (!have_f1_) {
    // f1 = f(t1, y1), shared with the next step's k1 through the cache.
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

void Euler::reset() { cache_.block(); }

}  // namespace ajx::numerics
