#include "numerics/euler.hpp"

namespace ajx::numerics {

void Euler::advance(const System& /*f*/, double /*t*/, double h, Vec& y_new) { y_new = y0_ + h * f0_; }

}  // namespace ajx::numerics
