// The mutable state (MuJoCo's mjData): owned by whoever integrates it.
#pragma once
#include <string_view>

#include "numerics/vector.hpp"
#include "physics/drive.hpp"

namespace ajx::physics {

// Which constraints are active (model.md, "Modes").
enum class Mode : int {
  Sliding = 0,     // taut, bead sliding: L1 + L2 = l, one unknown tension, T1 = κ T2
  BottomStop = 1,  // bead resting on the bottom ball: L1 = l - d, L2 = d (a double pendulum)
  Stuck = 2,       // bead held by friction: L1 = s*, L2 = l - s* (a double pendulum)
  TopStop = 3,     // bead against the top: L1 = s_min, L2 = l - s_min (a double pendulum)
  Slack = 4,       // L1 + L2 < l: both balls fly free under gravity and drag
};
std::string_view to_string(Mode m);

// The discrete part of the state: the mode and what it holds fixed.
struct Contact {
  Mode mode = Mode::BottomStop;
  int sigma = 0;        // sliding direction sgn ṡ used by the friction law (+1 down, -1 up)
  double s_star = 0.0;  // L1 held while stuck [m]
};

// Layout of the flat vector the integrators see. The three work integrals are quadratures
// of the powers (they do not feed back) so that the energy balance is integrated to the
// integrator's own accuracy.
namespace idx {
inline constexpr int r1 = 0;           // bead position [m] (3)
inline constexpr int r2 = 3;           // bottom ball position [m] (3)
inline constexpr int v1 = 6;           // bead velocity [m/s] (3)
inline constexpr int v2 = 9;           // bottom ball velocity [m/s] (3)
inline constexpr int motor_work = 12;  // ∫ P_motor dt [J]
inline constexpr int drag_loss = 13;   // ∫ c_D (|v1|² + |v2|²) dt [J]
inline constexpr int friction_loss = 14;  // ∫ (T1 - T2) ṡ dt [J]
inline constexpr int dim = 15;
}  // namespace idx

struct State {
  double t = 0.0;                 // [s]
  Contact contact;
  numerics::Vec y = numerics::Vec::Zero(idx::dim);  // see idx
  double impact_loss = 0.0;       // energy dissipated by plastic impacts [J]

  auto r1() const { return y.segment<3>(idx::r1); }
  auto r2() const { return y.segment<3>(idx::r2); }
  auto v1() const { return y.segment<3>(idx::v1); }
  auto v2() const { return y.segment<3>(idx::v2); }
  auto r1() { return y.segment<3>(idx::r1); }
  auto r2() { return y.segment<3>(idx::r2); }
  auto v1() { return y.segment<3>(idx::v1); }
  auto v2() { return y.segment<3>(idx::v2); }
};

}  // namespace ajx::physics
