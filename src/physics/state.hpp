// The mutable state (MuJoCo's mjData): owned by whoever integrates it.
#pragma once
#include <string_view>

#include "numerics/vector.hpp"
#include "physics/drive.hpp"
#include "physics/model.hpp"

namespace ajx::physics {

// Which constraints are active (docs/physics/model.md, "String, bead and forces").
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
  Contact() = default;
  Contact(Mode mode_, int sigma_ = 0, double s_star_ = 0.0) : mode(mode_), sigma(sigma_), s_star(s_star_) {}
  Mode mode = Mode::BottomStop;
  int sigma = 0;        // sliding direction sgn ṡ used by the friction law (+1 down, -1 up)
  double s_star = 0.0;  // L1 held while stuck [m]
  // The tie-clutch layer (physics/tie.hpp): the tie is held at χ = φ + offset, or slips.
  // Independent of the bead's mode: a change of the bead's mode keeps it.
  struct Tie {
    bool slip = false;
    int sigma = 0;          // while slipping: sgn(ω_m - χ̇), the sense of the clutch torque
    double offset = 0.0;    // χ - φ while held [rad]
    bool operator==(const Tie&) const = default;
  } tie;
  bool operator==(const Contact&) const = default;
};

// Layout of the flat vector the integrators see. The work integrals are quadratures
// of the powers (they do not feed back) so that the energy balance is integrated to the
// integrator's own accuracy.
namespace idx {
inline constexpr int r1 = 0;           // bead position [m] (3)
inline constexpr int r2 = 3;           // bottom ball position [m] (3)
inline constexpr int v1 = 6;           // bead velocity [m/s] (3)
inline constexpr int v2 = 9;           // bottom ball velocity [m/s] (3)
// ∫ −F1 u1·ȧ dt plus the top's impulsive work: the work the top passes into the string (with
// the pair couple, plus the couple's work on the balls). For a rigid tie it is the motor's.
inline constexpr int motor_work = 12;  // W_s [J]
inline constexpr int drag_loss = 13;   // ∫ c_D (|v1|² + |v2|²) dt [J]
inline constexpr int friction_loss = 14;  // ∫ (T1 - T2) ṡ dt [J]
inline constexpr int dim = 15;
// Where the motor drives through a clutch (the tie-clutch layer, physics/tie.hpp, or the pair
// couple, physics/pair_couple.hpp), the motor's own work and the clutches' loss:
inline constexpr int rod_work = 15;    // W_m = ∫ (τ_rod + τ_couple,z) ω_m dt, the motor's work [J]
inline constexpr int clutch_loss = 16; // W_c = ∫ τ_c (ω_m − χ̇) dt + the couple's slip loss [J]
inline constexpr int dim_ledger = 17;
// With the tie-clutch layer, the tie:
inline constexpr int chi = 17;         // χ, azimuth of the string's tie about the motor axis [rad]
inline constexpr int chi_dot = 18;     // χ̇ [rad/s] (= ω_m while the tie is held)
inline constexpr int dim_tie = 19;
}  // namespace idx

// The length of y for a model: the motor's ledger and the tie's χ, χ̇ only where a layer needs
// them, so that a model without a clutch integrates exactly the 15 components it always had.
inline int state_dim(const Model& m) {
  return m.layers.tie_clutch ? idx::dim_tie : m.layers.pair_couple != PairCouple::None ? idx::dim_ledger : idx::dim;
}
// Whether y carries the motor's ledger (W_m, W_c), and the tie's χ, χ̇.
inline bool has_ledger(const numerics::Vec& y) { return y.size() > idx::rod_work; }
inline bool has_tie(const numerics::Vec& y) { return y.size() > idx::chi_dot; }

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
