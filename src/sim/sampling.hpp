// The run's observer of accepted steps: samples on the grid origin + k sample_dt handed out
// in the lab, the statistics over them (RunOptions::run_statistics), and the unwrapped
// azimuths of the two balls for ω_ball over the last window.
#pragma once
#include <Eigen/Core>

#include "numerics/integrate.hpp"
#include "sim/run_context.hpp"

namespace ajx::sim {

// Unwrapped azimuth of a point about the motor axis, advanced in small increments. The
// increment is measured in a frame that turned by dbeta against these axes since the last
// point (where it is smaller): Δθ = ∠(last, Rz(−dbeta) now) + dbeta.
struct Azimuth {
  double theta = 0.0;
  Eigen::Vector2d last = Eigen::Vector2d::Zero();
  void reset(const physics::Vec3& r) {
    theta = 0.0;
    last = r.head<2>();
  }
  void advance(const physics::Vec3& r, double dbeta = 0.0);
};

class Sampler {
 public:
  // From ctx.s (already in the integrator's axes) to t_end; sample_dt <= 0: no samples.
  Sampler(RunContext& ctx, double t_end, double sample_dt, const SampleObserver& on_sample, double sample_origin);
  Sampler(const Sampler&) = delete;
  Sampler& operator=(const Sampler&) = delete;

  // The first sample, when the grid holds the start time.
  void start();
  // An accepted step: the samples in (t0, t1], and the azimuths advanced to t1.
  bool observe(const numerics::StepView& step);
  // The run ended at ctx.s.t: omega_ball and the sample statistics into ctx.sum.
  void finish();

 private:
  // The larger |dθ/dt| of the two balls about the axis in the integrator's axes (own) and in
  // the other frame (other).
  struct Rates {
    double own = 0.0, other = 0.0;
  };
  Rates azimuth_rates(double t, const numerics::Vec& y) const;
  void emit(double t, const numerics::Vec& y);
  // Whether ts lies in a sample span (RunOptions::sample_spans); if not, next_sample_ jumps to
  // just before the next span (past t_end when there is none).
  bool wanted(double ts);
  void advance_azimuths(const numerics::StepView& step);

  RunContext& ctx_;
  const SampleObserver& on_sample_;
  double t_end_, sample_dt_, t_start_, origin_;
  long next_sample_;
  std::size_t span_ = 0;  // the first sample span not yet behind the grid
  numerics::Vec ybuf_, ylab_, yend_;
  Azimuth az1_, az2_;
  double window_, t_window_;
  bool window_started_;
  Rates rate_start_;
};

}  // namespace ajx::sim
