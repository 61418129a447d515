// Classic 4-stage Runge-Kutta (Kutta 1901): order 4, fixed step.
// Dense output: cubic Hermite (hermite.hpp).
#pragma once
#include "numerics/hermite.hpp"

namespace ajx::numerics {

class Rk4 final : public HermiteStepper {
 public:
  std::string_view name() const override { return "rk4"; }
  int order() const override { return 4; }

 private:
  void advance(const System& f, double t, double h, Vec& y_new) override;
  Vec k2_, k3_, k4_, tmp_;
};

}  // namespace ajx::numerics
