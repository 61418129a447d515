#include "physics/string_friction.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace ajx::physics {

double deflection(const Vec3& u1, const Vec3& u2) {
  return std::atan2(u1.cross(u2).norm(), u1.dot(u2));
}

double tension_ratio(FrictionLaw law, double mu, double psi, double sigma) {
  if (sigma == 0 || mu == 0.0) return 1.0;
  switch (law) {
    case FrictionLaw::Capstan:
      return std::exp(mu * psi * sigma);
    case FrictionLaw::PointContact: {
      const double mt = mu * std::tan(0.5 * psi);
      if (mt >= 1.0)
        throw std::domain_error("point-contact friction jams: μ tan(ψ/2) >= 1");
      return (1.0 + sigma * mt) / (1.0 - sigma * mt);
    }
  }
  return 1.0;
}

FrictionCone friction_cone(FrictionLaw law, double mu, double psi) {
  if (law == FrictionLaw::PointContact && mu * std::tan(0.5 * psi) >= 1.0)
    return {0.0, std::numeric_limits<double>::infinity()};
  return {tension_ratio(law, mu, psi, -1), tension_ratio(law, mu, psi, +1)};
}

bool regularised(const Model& m) {
  return m.layers.friction == Friction::Regularised || m.layers.friction == Friction::Stribeck;
}

double regularised_mu(const Model& m, double sdot) {
  const Parameters& p = m.p;
  if (m.layers.friction != Friction::Stribeck) return p.mu_kinetic;
  const double x = sdot / m.layers.stribeck_speed;
  return p.mu_kinetic + (p.mu_static - p.mu_kinetic) * std::exp(-x * x);
}

double regularised_sigma(const Model& m, double sdot) { return std::tanh(sdot / m.layers.regularisation); }

double regularised_coefficient(const Model& m, double sdot) {
  return regularised_mu(m, sdot) * regularised_sigma(m, sdot);
}

double sliding_mu(const Model& m) {
  return m.layers.friction == Friction::None ? 0.0 : m.p.mu_kinetic;
}

double sticking_mu(const Model& m) {
  switch (m.layers.friction) {
    case Friction::StickSlip: return m.p.mu_static;
    case Friction::Kinetic: return m.p.mu_kinetic;
    case Friction::None:
    case Friction::Regularised:
    case Friction::Stribeck: return 0.0;
  }
  return 0.0;
}

bool can_stick(const Model& m) {
  return m.layers.friction == Friction::StickSlip || m.layers.friction == Friction::Kinetic;
}

}  // namespace ajx::physics
