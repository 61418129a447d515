// Mode transitions of a run: what each guard's crossing does to the contact mode (impacts
// included), the tie's slip and lock, and the settling of the modes at one instant. A new
// event (a guard of physics/mode_transitions.hpp that switches modes) gets its case in
// on_event().
#pragma once
#include "physics/mode_transitions.hpp"
#include "sim/run_context.hpp"

namespace ajx::sim {

class ModeSwitches {
 public:
  explicit ModeSwitches(RunContext& ctx);
  ModeSwitches(const ModeSwitches&) = delete;
  ModeSwitches& operator=(const ModeSwitches&) = delete;

  // The integrator stopped on guard g (not a watch) at ctx.s: make its switch. Sets
  // ctx.sum.failure where the equations have no continuation (a stop reached without its layer).
  void on_event(physics::Guard g);
  // After an impact, and at every segment start, the state may sit on a guard's surface while
  // moving into its forbidden side, where no crossing is ever seen: act on it here. A taut
  // mode must also satisfy its cone (settle) and, with the slack layer, positive tensions.
  // Sets ctx.sum.failure when the modes do not settle.
  void resolve_now();

 private:
  void enter(Contact next, double e);
  void book_impulse(const physics::ProjectionEnergy& pe);  // its work and loss into the ledger
  void impact_account(const physics::ProjectionEnergy& pe);
  void meet_stop(bool bottom);
  void pull_taut();
  void slip_tie(int sigma);
  void lock_tie();
  bool tie_slips_now();
  // One pass of resolve_now: true when it changed the mode (look again), false when settled.
  bool resolve_pass();

  RunContext& ctx_;
  physics::TopFor top_now_;  // the top for a mode c at the present state ctx.s
  double on_surface_;        // a state this close sits on a surface [m]
};

}  // namespace ajx::sim
