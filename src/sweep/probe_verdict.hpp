// A bisection probe's class decided before its window (sweep/bisection.hpp). A probe needs only
// the side of the threshold its held level lies on, so it may stop as soon as its class can no
// longer change: the window it would measure is then known.
//
// The probe's path up to its window is integrated in blocks of B = 5 s (a few periods of the
// slowest swing, 2π/√(g/l) ≈ 1.8 s for l = 0.826 m) on the grid from the probe's start, sampled
// every 0.1 s; after each block two verdicts are tested on its samples:
//
//  fallen  the bead on the bottom ball (the classifier's on-ball test) at every sample for B,
//          from the first sample of its landing on: the block after a landing ends B after it
//          (not on the grid: a fall lands at any time, and waiting for the next whole block
//          cost 2.3 s more on the ball on average, where a step is dearest, the bottom ball
//          swinging about the bead on a link of length d: tests/bench/probe_anatomy.cpp).
//          A fallen pair rises again only at a rise of the held level, and held levels lift no
//          bead off the ball up to 16π at any point of the shipped maps; so a bead down before
//          the window stays down through it, in both halves: the window is fallen. Tested for
//          ω_fall and ω1 only, whose ranges lie far below (2.5π to 6.5π).
//  locked  ω_m held (the block begins at or after t_hold), the bead stuck and the tie held at
//          every sample of three whole blocks in a row, and the balls' positions
//          in the frame turning with the top, x = Rz(−ψ)(r1, r2), converging: the block's box
//          of x has a half-diagonal a_j ≤ a_{j−1}, the shift of its centre from the last
//          block's, s_j, contracts, q = s_j/s_{j−1} < 1, and the distance left to the fixed
//          point, D = a_j + s_j q/(1 − q), is at most δ = 10⁻³ l. The orbit then stays within δ
//          of a fixed point of the turning frame with the bead stuck (a contracting oscillation
//          only shrinks the friction-force excursions the block already survived): ω_ball = ω_m
//          and a radius oscillation of δ/ρ, a locked-circular window. Tested for ω_fall and ω1,
//          whose known sides hold the locked orbit (not ω2: a lag near its Hopf point converges
//          slowly and may grow again, sim/settle_watch.hpp).
//
// Any other orbit (sliding, slipping, flowers, a fall still on its way) runs on through its
// window, classified as every window is.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <limits>
#include <optional>

#include "physics/model.hpp"
#include "physics/state.hpp"
#include "sim/simulation.hpp"
#include "sweep/orbit_classifier.hpp"
#include "sweep/task.hpp"
#include "sweep/thresholds.hpp"

namespace ajx::sweep {

class ProbeVerdict {
 public:
  static constexpr double kBlock = 5.0;        // B [s]
  static constexpr double kSampleStep = 0.1;   // the blocks' sampling step [s]
  static constexpr double kLockTolerance = 1e-3;  // δ / l

  // t_hold: the time from which ω_m is held at the probe's level [s].
  ProbeVerdict(Threshold threshold, const physics::Model& model, const ClassifierSettings& settings, double t_hold);

  // Whether this threshold's probes may be decided early at all.
  bool active() const { return may_fall_ || may_lock_; }
  void add(const sim::Sample& s);
  // The block that began at t_begin ended at t_end: the class when decided.
  std::optional<OrbitClassification> close_block(double t_begin, double t_end);
  // When the bead on the ball since its landing will have been there for B (just past the
  // sample at landing + B, so that the block ending there holds it); +inf when it is not on the ball.
  double fall_due() const;

 private:
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  bool may_fall_ = false, may_lock_ = false;
  double l_ = 0.0, d_ = 0.0, on_ball_tol_ = 0.0, t_hold_ = 0.0;
  // this block
  long n_ = 0;
  bool stuck_ = true;
  double t_first_ = 0.0;
  // the bead on the ball at every sample from on_since_ to last_on_ (NaN: not on the ball at the last sample)
  double on_since_ = std::numeric_limits<double>::quiet_NaN(), last_on_ = 0.0;
  Vec6 lo_, hi_;
  // the blocks before, while stuck and held: the last box's half-diagonal and centre, the last shift
  int stuck_blocks_ = 0;
  double spread_prev_ = 0.0, shift_prev_ = 0.0;
  Vec6 centre_prev_;
};

// A probe's path: from start through the chain's one window, in blocks while the verdict may
// decide it. decided: the class and the time it was decided (the output then ends there, with
// an empty window record).
struct ProbePath {
  TaskOutput out;
  std::optional<OrbitClassification> decided;
  double decided_at = 0.0;  // [s]
};
// on_sample and on_block (optional) see every sample of the blocks and every block's span and
// steps (tests/bench/probe_anatomy.cpp: where a probe's steps go).
ProbePath run_probe_path(const ChainSetup& chain, physics::State start, Threshold threshold,
                         const ClassifierSettings& settings, const sim::SampleObserver& on_sample = {},
                         const std::function<void(double t_begin, double t_end, long steps)>& on_block = {});

}  // namespace ajx::sweep
