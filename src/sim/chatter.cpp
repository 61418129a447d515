#include "sim/chatter.hpp"

#include <algorithm>

namespace ajx::sim {

ChatterDetector::ChatterDetector(RunContext& ctx)
    : ctx_(ctx), weight_((ctx.model.p.bead_mass + ctx.model.p.ball_mass) * ctx.model.p.gravity) {}

void ChatterDetector::record_switch() {
  const double t = ctx_.s.t;
  recent_switches_.push_back(t);
  if (recent_switches_.size() < std::size_t(ctx_.opt.chatter_switches)) return;
  const double span = recent_switches_.back() - recent_switches_.front();
  recent_switches_.erase(recent_switches_.begin());
  if (span > ctx_.opt.chatter_window) return;
  if (ctx_.sum.chatter++ == 0) ctx_.sum.first_chatter = t;
  ctx_.band = ctx_.band == 0.0 ? 1e-9 * weight_ : std::min(10.0 * ctx_.band, 1e-3 * weight_);
  ctx_.restitution = 0.0;
  recent_switches_.clear();
}

}  // namespace ajx::sim
