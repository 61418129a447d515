// A settling stretch that ends once its orbit is known (RunOptions::settle_spans).
//
// While ω_m is held, the equations are invariant under a rotation about the motor axis that
// turns the top's azimuth ψ with it (ψ = φ for a tie held on the rod, ψ = χ for a slipping
// one). An orbit that is a fixed point of the frame turning with the top, at Ω = ψ̇ (locked;
// the fallen pair turning with the motor; the lagging orbit of a slipping tie, which turns with
// χ), has no velocity in that frame: w_i = v_i − Ω ẑ × r_i = 0 for both balls. The watch
// follows V = max |w_i| over blocks of B seconds; once V has fallen in two blocks running, the
// slower of the two decay rates λ = −ln(V_j/V_{j−1})/B bounds the distance left to the fixed
// point, D ≤ V/λ, and when D ≤ ε l the stretch ends: its end state is taken to be the present
// one turned by Ω Δ (Δ the time left), with the work integrals advanced at their present rates.
// The end state then lies within ε l of the one a full integration reaches (both lie within
// D of the fixed point). Orbits that are not such fixed points (flowers, slow slides, escapes
// from a saddle: V not falling twice) run the full stretch.
#pragma once
#include <cstddef>
#include <limits>

#include "numerics/integrate.hpp"
#include "sim/run_context.hpp"

namespace ajx::sim {

class SettleWatch {
 public:
  // Block length B [s]: several periods of the slowest swing, 2π/√(g/l) ≈ 1.8 s for l = 0.826 m.
  static constexpr double kBlock = 5.0;

  explicit SettleWatch(RunContext& ctx);

  // An accepted step: false when the orbit is recognised inside a settle span (the run then
  // stops the integration and calls jump()).
  bool observe(const numerics::StepView& step);
  // Whether a recognised orbit waits for its jump.
  bool pending() const { return pending_; }
  // ctx.s from its time to the span's end, as the fixed point carries it; sum.skipped grows.
  void jump();
  // A recognition withdrawn (an event cut its step): the blocks start again.
  void cancel() {
    if (pending_) restart(-std::numeric_limits<double>::infinity());
  }

 private:
  struct Record {
    double t = 0.0;
    double work[3] = {0, 0, 0};  // the work integrals (motor, drag, friction) [J]
    double impact = 0.0;         // cumulative impact loss [J]
  };
  double relative_speed(double t, const numerics::Vec& y) const;  // V at (t, y) [m/s]
  double top_rate(double t, const numerics::Vec& y) const;        // Ω [rad/s]
  void restart(double t);
  Record record(double t, const numerics::Vec& y) const;

  RunContext& ctx_;
  std::size_t span_ = 0;  // the first settle span not yet behind the run
  bool pending_ = false;
  double block_end_ = 0.0;
  double v_now_ = 0.0, v_prev_ = -1.0, q_prev_ = 2.0;  // V of this block, of the last, their ratio
  Record block_start_;
  double rate_[4] = {0, 0, 0, 0};  // d/dt of the work integrals and the impact loss over the last block
  physics::Mode mode_ = physics::Mode::Sliding;
  bool tie_slip_ = false;
  numerics::Vec yend_;
};

}  // namespace ajx::sim
