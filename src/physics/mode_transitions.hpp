// When a mode ends and what follows (docs/physics/model.md, "String, bead and forces"): the
// guard functions each mode watches, as zero crossings located on the dense output, and the
// mode entered at a crossing.
// Guards of omitted layers are watches: they count a violated assumption and switch nothing.
#pragma once
#include <functional>
#include <string_view>
#include <vector>

#include "numerics/vector.hpp"
#include "physics/astrojax_system.hpp"
#include "physics/drive.hpp"
#include "physics/model.hpp"
#include "physics/state.hpp"

namespace ajx::physics {

enum class Guard {
  LandBottom,  // L2 - d falls through 0: the bead meets the bottom ball
  LandTop,     // L1 - s_min falls through 0: the bead meets the top
  Rest,        // σ ṡ falls through 0: the sliding bead comes to rest on the string
  SlipUp,      // T1 - κ_lo T2 falls through 0: the held bead slips up
  SlipDown,    // κ_hi T2 - T1 falls through 0: the held bead slips down
  Slacken,     // min(T1, T2) falls through 0: the string goes slack
  Taut,        // L1 + L2 - l - δ_s rises through 0 (δ_s = taut_margin): the slack string pulls taut (an impact)
  ReachBall,   // L2 falls to 1e-4 l without the bottom stop: singular, the run ends
  ReachTop,    // L1 falls to 1e-4 l without the top stop: singular, the run ends
  TieSlipAhead,   // τ_s - τ falls through 0: the rod cannot drag the held tie along, it slips back
  TieSlipBehind,  // τ_s + τ falls through 0: the tie overruns the rod and slips ahead
  TieLock,        // σ (ω_m - χ̇) falls through 0: the slipping tie has caught the rod's speed
  // Watches of omitted layers (both directions: entering and leaving the violation).
  WatchTension,  // min(T1, T2) < 0 without the slack layer
  WatchStick,    // ṡ = 0 without a stuck mode (regularised friction creeps through it)
  WatchBottom,   // L2 < d without the bottom stop
  WatchTop,      // L1 < s_min without the top stop
};
std::string_view to_string(Guard g);
bool is_watch(Guard g);

// δ_s [m]: the Taut guard fires δ_s beyond L1 + L2 = l. A slack flight starts on the surface
// (projected onto it, to the rounding of L1 + L2 - l, a few 1e-16 l), so with δ_s above that
// rounding it starts strictly on the slack side: a step that ends stretched is a sign change
// even if the flight dipped below the surface and came back within it, and the sign just after
// the start is never rounding noise. The plastic re-taut then removes the stretch δ_s, a
// potential energy of at most (m1 + m2) g δ_s, far below any energy balance the runs check.
inline double taut_margin(const Parameters& p) { return 1e-14 * p.string_length; }

struct GuardSpec {
  Guard kind;
  int direction;  // -1 falling, +1 rising, 0 both
};

// The guards of a mode under the model's layers.
std::vector<GuardSpec> guards(const Model& m, const Contact& c);

// The guard's value at (t, y) in mode c; zero at the switch.
double guard_value(Guard g, const Model& m, const TopKinematics& top, const Contact& c,
                   const numerics::Vec& y);
// The force guards (cone margins, tensions) need physics::evaluate at (t, y); the others not.
bool needs_dynamics(Guard g);
// The same value with d = evaluate(m, top, c, y) computed once for all guards of a mode.
double guard_value(Guard g, const Model& m, const TopKinematics& top, const Contact& c,
                   const numerics::Vec& y, const Dynamics& d);

// The top of the string at the (t, y) being judged, for a candidate contact state c (the
// bead's mode with the tie's state): tie.hpp's top_kinematics, or the rotating axes' top.
// With a slipping tie ä depends on the bead's mode (through χ̈, solved with F1 of that mode),
// so a mode's forces are judged at the top that mode gives.
using TopFor = std::function<TopKinematics(const Contact& c)>;

// The stuck mode at the bead's present s* = L1 = |r1 − a| with c's tie: the mode at_rest judges.
Contact held_here(const TopKinematics& top, const Contact& c, const numerics::Vec& y);

// The mode the bead takes when it is at rest on the string (ṡ = 0): stuck while the forces
// of the held bead lie inside the sticking cone, else sliding in the direction of the violated
// bound (σ = -1 up, +1 down). Without a stuck mode: sliding in the direction s̈ points.
// `top` is the top the held bead would give (top_for(held_here(...))).
// `band` widens the cone by a few newtons (>= 0; the chatter resolution, see simulation.hpp).
Contact at_rest(const Model& m, const TopKinematics& top, const numerics::Vec& y, double band = 0.0);

// The margin of the μ_s cone of the bead held at its present s, min(up, down) [N] (> 0 inside),
// at the top the held bead gives: what the watch of the `kinetic` and `regularised` layers
// reports at ṡ = 0 (those layers have no static coefficient of their own).
double static_cone_margin(const Model& m, const TopFor& top_for, const Contact& c, const numerics::Vec& y);

// A taut mode entered with velocities already on its constraints: the held modes keep it
// while their one-sided cones hold, else the bead slides in the direction of the violated
// bound; a sliding bead gets σ = sgn ṡ, or the rest rule when ṡ = 0 (judged at the held
// bead's top, top_for(held_here(...))). The tie's state (c.tie) is kept: only the bead's mode
// settles.
Contact settle(const Model& m, const TopFor& top_for, const Contact& c, const numerics::Vec& y,
               double band = 0.0);

}  // namespace ajx::physics
