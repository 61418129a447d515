// Recurrence on a Poincaré section: whether a held level's orbit has returned to a periodic
// orbit of the frame turning with the top (lagging, flower), so that its settling may skip a
// whole number of periods (sim/settle_watch.hpp).
//
// The section is a plane of that frame (chosen by the caller, crossed at least twice a period
// by any orbit that is not a fixed point), each crossing tagged with its direction. A
// crossing's point p is the state in the turning frame as lengths: the balls' positions x,
// their velocities u (lab velocities turned by −ψ) over ω0 = √(g/l) (a swing of amplitude A
// about a point has speed A ω0), and, with a tie that may slip, R χ̇ / ω0. A periodic orbit
// crossing the section k times a period gives points with p_i = p_{i−k}; its period T and the
// turn of the frame Δψ over it are read off the crossings. The drift per period is the largest
// shift s = |p_i − p_{i−k}| over every crossing of the last `history` seconds (several periods
// of the slowest swing, 2π/ω0, so that a swing beside the orbit, or a second frequency, shows
// in it). If it does not grow (the newest shift no larger than the oldest of the history), the
// state after n more periods is within D = n s of where a skip of n periods leaves it: a drift
// that decays as e^{−γ t} moves it by s (1 − e^{−γ n T})/(γ T) ≤ n s. A growing drift, e^{+γ t}
// (a deviation from an unstable orbit, as a lag just past its Hopf point), would outrun n s and
// is never taken. The orbit is known once D ≤ ε l for the n periods that fit.
#pragma once
#include <Eigen/Core>
#include <array>
#include <deque>
#include <optional>

namespace ajx::sim {

// The integrals a skipped stretch carries on at their rates: the work integrals of y
// (settle_watch.cpp, kWorks) and the impact loss [J].
using Works = std::array<double, 6>;

struct SectionPoint {
  double t = 0.0;    // crossing time [s]
  double psi = 0.0;  // the top's azimuth ψ, unwrapped [rad]
  int direction = 0; // sign of dα/dt at the crossing
  Eigen::VectorXd p; // the state in the turning frame as lengths [m]
  Works works{};     // the integrals at t [J]
};

// One period of a recognised orbit.
struct Period {
  int crossings = 0;  // k
  double T = 0.0;     // [s]
  double turn = 0.0;  // Δψ over T [rad]
  Works works{};      // increase of each integral over T [J]
  double distance = 0.0;  // D [m]
};

class SectionRecurrence {
 public:
  static constexpr int kMaxCrossings = 12;  // a period of at most this many crossings
  static constexpr std::size_t kMaxPoints = 256;  // crossings kept

  // ε l [m]; the history that must recur [s].
  SectionRecurrence(double tolerance, double history) : tol_(tolerance), history_(history) {}
  void clear() { points_.clear(); }
  // The next crossing; a period when the orbit is known and at least one period fits in
  // time_left [s].
  std::optional<Period> add(SectionPoint point, double time_left);

 private:
  std::optional<Period> test(int k, double time_left) const;
  double tol_, history_;
  std::deque<SectionPoint> points_;  // the last kMaxPoints crossings
};

}  // namespace ajx::sim
