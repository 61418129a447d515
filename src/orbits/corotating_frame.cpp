#include "orbits/corotating_frame.hpp"

#include <cmath>

#include "physics/astrojax_system.hpp"

namespace ajx::orbits {

namespace {
Vec3 rotate_z(const Vec3& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y(), v.z()};
}
}  // namespace

physics::TopKinematics corotating_top(double R, double omega) {
  return physics::point_on_circle(R, 0.0, omega, 0.0);
}

numerics::Vec lab_state(const Vec12& z, double omega, int dim) {
  namespace idx = physics::idx;
  const Vec3 W(0, 0, omega);
  numerics::Vec y = numerics::Vec::Zero(dim);
  for (int b = 0; b < 2; ++b) {
    const Vec3 q = z.segment<3>(3 * b), qd = z.segment<3>(6 + 3 * b);
    y.segment<3>(idx::r1 + 3 * b) = q;
    y.segment<3>(idx::v1 + 3 * b) = qd + W.cross(q);
  }
  return y;
}

Vec12 frame_state(const numerics::Vec& y, double phi, double omega) {
  namespace idx = physics::idx;
  const Vec3 W(0, 0, omega);
  Vec12 z;
  for (int b = 0; b < 2; ++b) {
    const Vec3 q = rotate_z(y.segment<3>(idx::r1 + 3 * b), -phi);
    z.segment<3>(3 * b) = q;
    z.segment<3>(6 + 3 * b) = rotate_z(y.segment<3>(idx::v1 + 3 * b), -phi) - W.cross(q);
  }
  return z;
}

Vec12 frame_derivative(const Vec12& z, const Vec3& acc1, const Vec3& acc2, double omega) {
  const Vec3 W(0, 0, omega);
  Vec12 dz;
  dz.head<6>() = z.tail<6>();
  const Vec3 acc[2] = {acc1, acc2};
  for (int b = 0; b < 2; ++b) {
    const Vec3 q = z.segment<3>(3 * b), qd = z.segment<3>(6 + 3 * b);
    dz.segment<3>(6 + 3 * b) = acc[b] - 2.0 * W.cross(qd) + omega * omega * Vec3(q.x(), q.y(), 0.0);
  }
  return dz;
}

Vec12 corotating_rhs(const physics::Model& m, double omega, const physics::Contact& c, const Vec12& z) {
  const physics::TopKinematics top = corotating_top(m.p.drive_radius, omega);
  const physics::Dynamics d = physics::evaluate(m, top, c, lab_state(z, omega));
  return frame_derivative(z, d.acc1, d.acc2, omega);
}

}  // namespace ajx::orbits
