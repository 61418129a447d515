// Explicit Euler, y1 = y0 + h f(t0, y0): order 1, fixed step (a baseline at the paper's step
// h = 1/2000 s). Dense output: cubic Hermite (hermite.hpp).
#pragma once
#include "numerics/hermite.hpp"

namespace ajx::numerics {

class Euler final : public HermiteStepper {
 public:
  std::string_view name() const override { return "euler"; }
  int order() const override { return 1; }

 private:
  void advance(const System& f, double t, double h, Vec& y_new) override;
};

}  // namespace ajx::numerics
