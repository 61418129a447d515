// f(t, y) at the start of a step, remembered with its key (t, y) so that a step can start
// from a derivative that is already known: the FSAL stage of the previous step, the f1 an
// interpolant evaluated lazily, or k1 again after a rejected attempt. The key is compared
// bitwise (n <= 32 doubles, negligible next to one RHS call), so a caller that changes y
// without telling the stepper still gets a correct k1. A change of f itself (mode switch)
// cannot be seen: block() (from Stepper::reset) forbids any reuse until a fresh evaluation.
#pragma once
#include "numerics/vector.hpp"

namespace ajx::numerics {

class DerivativeCache {
 public:
  // Copies f(t, y) into out, from the cache when the key matches, else by one RHS call
  // (counted in evals) that then becomes the cached value.
  void get(const System& f, double t, const Vec& y, Vec& out, long& evals) {
    if (valid_ && t == t_ && y.size() == y_.size() && (y.array() == y_.array()).all()) {
      out = fy_;
      return;
    }
    out.resize(y.size());
    f(t, y, out);
    ++evals;
    t_ = t;
    y_ = y;
    fy_ = out;
    valid_ = true;
    blocked_ = false;
  }

  // A derivative known from elsewhere: fy = f(t, y). Ignored while blocked.
  void offer(double t, const Vec& y, const Vec& fy) {
    if (blocked_) return;
    t_ = t;
    y_ = y;
    fy_ = fy;
    valid_ = true;
  }

  // True when (t, y) is the cached key; then value() is f(t, y).
  bool holds(double t, const Vec& y) const {
    return valid_ && t == t_ && y.size() == y_.size() && (y.array() == y_.array()).all();
  }
  const Vec& value() const { return fy_; }

  // Drop the cached value and refuse offers until the next fresh evaluation in get().
  void block() {
    valid_ = false;
    blocked_ = true;
  }

 private:
  double t_ = 0.0;
  Vec y_, fy_;
  bool valid_ = false;
  bool blocked_ = false;
};

}  // namespace ajx::numerics
