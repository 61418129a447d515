// A settling stretch that ends once its orbit is known (RunOptions::settle_spans).
//
// While ω_m is held, the equations are invariant under a rotation about the motor axis that
// turns the top's azimuth ψ with it (ψ = φ for a tie held on the rod, ψ = χ for a slipping
// one). An orbit that is a fixed point of the frame turning with the top, at Ω = ψ̇ (locked;
// the fallen pair turning with the motor; the lagging orbit of a slipping tie, which turns with
// χ), keeps both balls' positions in that frame, x = Rz(−ψ) (r1, r2), constant. The watch
// follows x over blocks of B seconds: each block's box of x (its centre m_j, its half-diagonal
// a_j, what an oscillation about the centre spans) and the shift of the centre from the last
// block, s_j = |m_j − m_{j−1}|; d_j = a_j + s_j measures the deviation from the fixed point.
//
// Being near the fixed point is not enough: past a Hopf point (the lag at ω_m > ω_H) the
// deviation is the sum of a mode that decays and one that grows from far below it, and the
// first hides the second until it has decayed. So the orbit is known only where it is seen to
// converge at a rate that holds: over the last kRateBlocks blocks every contraction
// Λ_j = ln(d_{j−1}/d_j) = σ B is positive, the newest is no smaller than the smallest before it
// (a slower mode surfacing, or σ → 0 at a Hopf point, shows as a falling Λ), a_j ≤ a_{j−1}, and
// with q = e^{−min Λ}, the slowest contraction seen, the distance left is at most
// D = a_j + s_j q/(1 − q) ≤ ε l. The full settle would end within D e^{−σ Δ} of the fixed
// point (Δ the time left); the stretch ends:
//  - where the deviation is one decaying mode (three block boundaries B apart in line, see
//    land_on_fixed_point), on the state the full settle reaches, extrapolated by that mode,
//    within E + D e^{−σ Δ} of it (E the part the single mode leaves out, used only when E < D);
//  - otherwise on the present state turned by Ω Δ, within D of it.
// The work integrals advance at their rates over the last block.
//
// An orbit that returns to a periodic orbit of that frame (lagging behind a held tie, a flower,
// a tie that catches the rod and slips again every cycle, for which ψ = χ throughout) is
// recognised by its recurrence on a Poincaré section (sim/section_recurrence.hpp): once the
// distance left to the periodic orbit is at most ε l, the stretch skips the n whole periods T
// that fit before its end, the state turned by n Δψ (the frame's turn over a period; a held tie's
// offset δ = χ − φ by n (Δψ − ω_m T)) and the
// integrals advanced by n times their increase over a period; the rest of the stretch is
// integrated; a drift that grows over the history (a flower still growing from the lag) is not
// taken. Orbits that neither converge nor recur (slow slides, escapes from a saddle, a
// quasi-periodic flower, a lag near its Hopf point) run the full stretch, bit for bit as
// without the watch.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <limits>

#include "numerics/integrate.hpp"
#include "sim/run_context.hpp"
#include "sim/section_recurrence.hpp"

namespace ajx::sim {

class SettleWatch {
 public:
  // Block length B [s]: several periods of the slowest swing, 2π/√(g/l) ≈ 1.8 s for l = 0.826 m.
  static constexpr double kBlock = 5.0;
  // Distances d_j compared for the decay rate: three contractions Λ, so that a rate that slows
  // (the second of two modes surfacing) is seen before the stop; 20 s of blocks after the first.
  static constexpr int kRateBlocks = 4;

  explicit SettleWatch(RunContext& ctx);

  // An accepted step: false when the orbit is recognised inside a settle span (the run then
  // stops the integration and calls jump()).
  bool observe(const numerics::StepView& step);
  // Whether a recognised orbit waits for its jump.
  bool pending() const { return pending_; }
  // ctx.s from its time to the span's end, as the fixed point carries it, or on by the whole
  // periods of the periodic orbit; sum.skipped grows.
  void jump();
  // A recognition withdrawn (an event cut its step): the blocks start again.
  void cancel() {
    if (pending_) restart(-std::numeric_limits<double>::infinity());
  }

 private:
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  struct Record {
    double t = 0.0;
    Works works{};  // the work integrals of y (settle_watch.cpp, kWorks) and the impact loss [J]
  };
  double top_rate(double t, const numerics::Vec& y) const;  // Ω [rad/s]
  double top_azimuth(double t, const numerics::Vec& y) const;  // ψ in the integrator's axes [rad]
  Vec6 in_top_frame(double t, const numerics::Vec& y) const;  // x = Rz(−ψ) (r1, r2) [m]
  void reset_rates();  // the fixed-point test's blocks and their contraction rates start anew
  void restart(double t);
  void open_block(double t, const numerics::Vec& y);
  Record record(double t, const numerics::Vec& y) const;
  // The block just closed at t: whether the orbit is known (sets the rates for the jump).
  bool recognised(double t);
  void choose_section(const Vec6& x);
  // The step crossed the section: whether the orbit now recurs (sets period_ for the jump).
  bool crossed(const numerics::StepView& step, double g_begin);
  SectionPoint section_point(double t, const numerics::Vec& y, int direction) const;
  void jump_periods();
  void sample_grid(const numerics::StepView& step);
  bool land_on_fixed_point(double end);  // the state at end from the decaying mode, or false

  RunContext& ctx_;
  std::size_t span_ = 0;  // the first settle span not yet behind the run
  bool pending_ = false;
  double block_end_ = 0.0;
  int blocks_ = 0;                  // blocks closed in this run of the span
  Vec6 lo_, hi_, centre_;           // this block's box of x, the last block's centre
  double spread_prev_ = 0.0;        // a_{j−1} [m]
  std::array<double, kRateBlocks> dist_{};  // d of the last kRateBlocks blocks, oldest first [m]
  double distance_ = 0.0;                   // D of the last recognition [m]
  std::array<Eigen::VectorXd, 3> grid_;     // w at the last three block boundaries, oldest first
  int grid_count_ = 0;                      // how many of them lie B apart
  double grid_t_ = 0.0;                     // the last boundary [s]
  Record block_start_;
  double rate_[6] = {0, 0, 0, 0, 0, 0};  // d/dt of the work integrals and the impact loss over the last block
  SectionRecurrence recurrence_;
  int section_axis_ = -1;        // the section x_i = c in the turning frame: i (−1: none yet)
  double section_level_ = 0.0;   // c [m]
  double section_g_ = 0.0;       // x_i − c at the last step's end [m]
  std::optional<Period> period_;  // the periodic orbit recognised, for the jump
  physics::Mode mode_ = physics::Mode::Sliding;
  bool tie_slip_ = false;
  bool tie_switched_ = false;  // the tie switched in the block now open
  numerics::Vec yend_;
};

}  // namespace ajx::sim
