#include "bench/friction_study.hpp"

namespace ajx::bench {

Scene regularised(const Scene& base, double eps, physics::Friction law) {
  Scene s = base;
  s.model.layers.friction = law;
  s.model.layers.regularisation = eps;
  // A stuck start has no meaning without a stuck mode: the same state, sliding (the
  // regularised law then holds it by creeping at ṡ ~ ε).
  if (s.initial.contact.mode == physics::Mode::Stuck) s.initial.contact = {physics::Mode::Sliding, 0, 0.0};
  return s;
}

Scene kinetic(const Scene& base) {
  Scene s = base;
  s.model.layers.friction = physics::Friction::Kinetic;
  return s;
}

double bead_position(const Scene& scene, const physics::State& s) {
  const physics::TopKinematics top = scene.schedule.top(s.t);
  return (physics::Vec3(s.y.segment<3>(physics::idx::r1)) - top.a).norm();
}

}  // namespace ajx::bench
