#include "numerics/stepper.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "numerics/dop853.hpp"
#include "numerics/dopri5.hpp"
#include "numerics/euler.hpp"
#include "numerics/radau_iia.hpp"
#include "numerics/rk4.hpp"

namespace ajx::numerics {

std::string_view stepper_names() { return "euler, rk4, dopri5, dop853, radau_iia"; }

std::unique_ptr<Stepper> make_stepper(std::string_view name) {
  if (name == "euler") return std::make_unique<Euler>();
  if (name == "rk4") return std::make_unique<Rk4>();
  if (name == "dopri5") return std::make_unique<Dopri5>();
  if (name == "dop853") return std::make_unique<Dop853>();
  if (name == "radau_iia") return std::make_unique<RadauIIA>();
  throw std::invalid_argument("unknown integrator '" + std::string(name) +
                              "' (allowed: " + std::string(stepper_names()) + ")");
}

// sqrt( (1/n) sum_i (err_i / (atol + rtol max(|y_i|, |y_new_i|)))^2 )
double error_norm(const Vec& err, const Vec& y, const Vec& y_new, const Tolerances& tol) {
  const auto n = err.size();
  if (n == 0) return 0.0;
  double sum = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double sk = tol.atol + tol.rtol * std::max(std::abs(y[i]), std::abs(y_new[i]));
    const double r = err[i] / sk;
    sum += r * r;
  }
  return std::sqrt(sum / static_cast<double>(n));
}

}  // namespace ajx::numerics
