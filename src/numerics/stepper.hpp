// One small interface for every one-step method. A stepper knows the Butcher tableau and
// its interpolant, nothing of the physics and nothing of step-size control or events
// (those live in integrate.hpp).
#pragma once
#include <memory>
#include <string>
#include <string_view>

#include "numerics/vector.hpp"

namespace ajx::numerics {

// Mixed error norm of Hairer-Norsett-Wanner: err_i / (atol + rtol max(|y_i|, |y_new_i|)),
// RMS over components. A step is accepted when the norm is <= 1.
struct Tolerances {
  double rtol = 1e-9;
  double atol = 1e-12;
};

class Stepper {
 public:
  virtual ~Stepper() = default;

  virtual std::string_view name() const = 0;
  // Order p of the propagated solution (global error O(h^p)).
  virtual int order() const = 0;
  // True when attempt() returns an embedded error estimate usable for step-size control.
  virtual bool adaptive() const = 0;

  // Attempt one step of size h from (t, y); the proposal goes to y_new. Returns the scaled
  // error norm (see Tolerances) for adaptive methods and 0 for fixed-step ones.
  // Counts its right-hand-side evaluations in rhs_evals().
  virtual double attempt(const System& f, double t, const Vec& y, double h, Vec& y_new,
                         const Tolerances& tol) = 0;

  // Called by the driver when the last attempt was accepted; from then on dense() may be
  // called for theta in [0, 1] over that step. May reuse the last stage for the next step
  // (FSAL) unless reset() is called first.
  virtual void accept(const System& f) = 0;

  // Interpolated solution at t + theta h of the last accepted step. Non-const because
  // some interpolants evaluate extra stages lazily, at most once per step.
  virtual void dense(const System& f, double theta, Vec& out) = 0;

  // An interpolant of the last accepted step cheaper than dense(), for looking for sign changes
  // of the guards (numerics::integrate confirms and locates any it sees on dense()): fills out
  // and returns true, or returns false when the method has none.
  virtual bool cheap_interpolant(const System& /*f*/, double /*theta*/, Vec& /*out*/) { return false; }

  // Bounds e_i >= |y_i(t0 + theta h) - y_i(t0)| for all theta in [0, 1] on the interpolant of
  // the last accepted step (what dense() returns). False when the method gives none.
  virtual bool dense_excursion(const System& /*f*/, Vec& /*e*/) { return false; }

  // The state was changed outside the stepper (projection, impact, mode switch): drop any
  // stage reused from the previous step.
  virtual void reset() = 0;

  long rhs_evals() const { return rhs_evals_; }
  // Adds evaluations made on this stepper's behalf (the driver's initial-step heuristic).
  void count_rhs_evals(long n) { rhs_evals_ += n; }

 protected:
  long rhs_evals_ = 0;
};

// Factory by name: "euler", "rk4", "dopri5", "dop853", "radau_iia".
// Throws std::invalid_argument naming the allowed values on an unknown name.
std::unique_ptr<Stepper> make_stepper(std::string_view name);

// The allowed names, for error messages and help text.
std::string_view stepper_names();

// Shared helper: the error norm of Tolerances.
double error_norm(const Vec& err, const Vec& y, const Vec& y_new, const Tolerances& tol);

}  // namespace ajx::numerics
