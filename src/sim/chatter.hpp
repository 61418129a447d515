// Chatter detection and resolution: a storm of switches in a short time (opt.chatter_switches
// within opt.chatter_window) widens the band past which the force guards (cone margins,
// tensions) switch, and makes impacts plastic. Deterministic: the band starts at
// 1e-9 (m1 + m2) g and grows tenfold per further storm, up to 1e-3 (m1 + m2) g.
#pragma once
#include <vector>

#include "sim/run_context.hpp"

namespace ajx::sim {

class ChatterDetector {
 public:
  explicit ChatterDetector(RunContext& ctx);
  // A mode switch was made at ctx.s.t; on a storm, widen ctx.band and zero ctx.restitution.
  void record_switch();

 private:
  RunContext& ctx_;
  double weight_;                       // (m1 + m2) g [N]
  std::vector<double> recent_switches_;  // times of the last switches [s]
};

}  // namespace ajx::sim
