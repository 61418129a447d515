#include "numerics/dopri5.hpp"

namespace ajx::numerics {
namespace {

// Butcher tableau of Dormand & Prince, "A family of embedded Runge-Kutta formulae",
// J. Comput. Appl. Math. 6 (1980) 19-26; as printed in Hairer, Norsett & Wanner, Solving
// ODEs I, 2nd ed., Table II.5.2 (and their code dopri5.f).
constexpr double c2 = 1.0 / 5.0, c3 = 3.0 / 10.0, c4 = 4.0 / 5.0, c5 = 8.0 / 9.0;
constexpr double a21 = 1.0 / 5.0;
constexpr double a31 = 3.0 / 40.0, a32 = 9.0 / 40.0;
constexpr double a41 = 44.0 / 45.0, a42 = -56.0 / 15.0, a43 = 32.0 / 9.0;
constexpr double a51 = 19372.0 / 6561.0, a52 = -25360.0 / 2187.0, a53 = 64448.0 / 6561.0,
                 a54 = -212.0 / 729.0;
constexpr double a61 = 9017.0 / 3168.0, a62 = -355.0 / 33.0, a63 = 46732.0 / 5247.0,
                 a64 = 49.0 / 176.0, a65 = -5103.0 / 18656.0;
// 5th-order weights b = row 7 of A (FSAL), b2 = b7 = 0.
constexpr double a71 = 35.0 / 384.0, a73 = 500.0 / 1113.0, a74 = 125.0 / 192.0,
                 a75 = -2187.0 / 6784.0, a76 = 11.0 / 84.0;
// Error coefficients e = b - bhat (bhat: the embedded 4th-order weights).
constexpr double e1 = 71.0 / 57600.0, e3 = -71.0 / 16695.0, e4 = 71.0 / 1920.0,
                 e5 = -17253.0 / 339200.0, e6 = 22.0 / 525.0, e7 = -1.0 / 40.0;
// Dense output (Hairer's dopri5.f, Shampine 1986 style continuous extension of order 4):
// y(t0 + s h) = y0 + s (r2 + (1-s) (r3 + s (r4 + (1-s) r5))), with
// r2 = y1 - y0, r3 = h k1 - r2, r4 = r2 - h k7 - r3, r5 = h sum_i d_i k_i.
constexpr double d1 = -12715105075.0 / 11282082432.0, d3 = 87487479700.0 / 32700410799.0,
                 d4 = -10690763975.0 / 1880347072.0, d5 = 701980252875.0 / 199316789632.0,
                 d6 = -1453857185.0 / 822651844.0, d7 = 69997945.0 / 29380423.0;

}  // namespace

double Dopri5::attempt(const System& f, double t, const Vec& y, double h, Vec& y_new,
                       const Tolerances& tol) {
  const auto n = y.size();
  y0_ = y;  // first: y_new may alias y
  for (Vec* v : {&k2_, &k3_, &k4_, &k5_, &k6_, &k7_}) v->resize(n);
  cache_.get(f, t, y0_, k1_, rhs_evals_);

  tmp_ = y0_ + (h * a21) * k1_;
  f(t + c2 * h, tmp_, k2_);
  tmp_ = y0_ + h * (a31 * k1_ + a32 * k2_);
  f(t + c3 * h, tmp_, k3_);
  tmp_ = y0_ + h * (a41 * k1_ + a42 * k2_ + a43 * k3_);
  f(t + c4 * h, tmp_, k4_);
  tmp_ = y0_ + h * (a51 * k1_ + a52 * k2_ + a53 * k3_ + a54 * k4_);
  f(t + c5 * h, tmp_, k5_);
  tmp_ = y0_ + h * (a61 * k1_ + a62 * k2_ + a63 * k3_ + a64 * k4_ + a65 * k5_);
  f(t + h, tmp_, k6_);
  y1_ = y0_ + h * (a71 * k1_ + a73 * k3_ + a74 * k4_ + a75 * k5_ + a76 * k6_);
  f(t + h, y1_, k7_);
  rhs_evals_ += 6;

  err_ = h * (e1 * k1_ + e3 * k3_ + e4 * k4_ + e5 * k5_ + e6 * k6_ + e7 * k7_);
  t_ = t;
  h_ = h;
  dense_ready_ = false;
  y_new = y1_;
  return error_norm(err_, y0_, y1_, tol);
}

// FSAL: k7 = f(t0 + h, y1) starts the next step.
void Dopri5::accept(const System& /*f*/) { cache_.offer(t_ + h_, y1_, k7_); }

void Dopri5::dense(const System& /*f*/, double theta, Vec& out) {
  if (!dense_ready_) {
    r2_ = y1_ - y0_;
    r3_ = h_ * k1_ - r2_;
    r4_ = r2_ - h_ * k7_ - r3_;
    r5_ = h_ * (d1 * k1_ + d3 * k3_ + d4 * k4_ + d5 * k5_ + d6 * k6_ + d7 * k7_);
    dense_ready_ = true;
  }
  const double s = theta, s1 = 1.0 - theta;
  out = y0_ + s * (r2_ + s1 * (r3_ + s * (r4_ + s1 * r5_)));
}

void Dopri5::reset() { cache_.block(); }

}  // namespace ajx::numerics
