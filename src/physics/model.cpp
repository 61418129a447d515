#include "physics/model.hpp"

#include <cmath>
#include <fmt/format.h>

namespace ajx::physics {

std::vector<ParameterIssue> validate(const Model& model) {
  const Parameters& p = model.p;
  std::vector<ParameterIssue> out;
  auto need = [&](bool ok, const char* key, double v, std::string allowed) {
    if (!ok || !std::isfinite(v)) out.push_back({key, v, std::move(allowed)});
  };
  need(p.string_length > 0, "model.string_length", p.string_length, "l > 0 m");
  need(p.bead_mass > 0, "model.bead_mass", p.bead_mass, "m1 > 0 kg");
  need(p.ball_mass > 0, "model.ball_mass", p.ball_mass, "m2 > 0 kg");
  need(p.drag >= 0, "model.drag", p.drag, "c_D >= 0 kg/s");
  need(p.mu_static >= 0, "model.mu_static", p.mu_static, "μ_s >= 0");
  need(p.mu_kinetic >= 0 && p.mu_kinetic <= p.mu_static, "model.mu_kinetic", p.mu_kinetic,
       fmt::format("0 <= μ_k <= μ_s = {}", p.mu_static));
  need(p.gravity >= 0, "model.gravity", p.gravity, "g >= 0 m/s²");
  const double l = p.string_length;
  need(p.drive_radius >= 0 && p.drive_radius < l, "model.drive_radius", p.drive_radius,
       fmt::format("0 <= R < l = {} m", l));
  need(p.contact_distance > 0 && p.contact_distance < l, "model.contact_distance",
       p.contact_distance, fmt::format("0 < d < l = {} m", l));
  need(p.top_stop >= 0 && p.top_stop < l - p.contact_distance, "model.top_stop", p.top_stop,
       fmt::format("0 <= s_min < l - d = {} m", l - p.contact_distance));
  need(p.tie_static_torque >= 0, "model.tie_static_torque", p.tie_static_torque, "τ_s >= 0 N m");
  need(p.tie_kinetic_torque >= 0 && p.tie_kinetic_torque <= p.tie_static_torque, "model.tie_kinetic_torque",
       p.tie_kinetic_torque, fmt::format("0 <= τ_k <= τ_s = {} N m", p.tie_static_torque));
  need(p.tie_inertia > 0, "model.tie_inertia", p.tie_inertia, "I_a > 0 kg m²");
  need(p.tie_damping >= 0, "model.tie_damping", p.tie_damping, "c_a >= 0 N m s");
  need(p.couple_torque >= 0, "model.couple_torque", p.couple_torque, "τ_c >= 0 N m");
  need(p.couple_slip_rate > 0, "model.couple_slip_rate", p.couple_slip_rate, "Ω_ε > 0 rad/s");
  const Layers& L = model.layers;
  need(L.regularisation > 0, "layers.regularisation", L.regularisation, "ε > 0 m/s");
  need(L.restitution >= 0 && L.restitution <= 1, "layers.restitution", L.restitution, "0 <= e <= 1");
  return out;
}

std::string_view to_string(Friction f) {
  switch (f) {
    case Friction::None: return "none";
    case Friction::Kinetic: return "kinetic";
    case Friction::StickSlip: return "stick_slip";
    case Friction::Regularised: return "regularised";
  }
  return "?";
}

std::string_view to_string(FrictionLaw f) {
  switch (f) {
    case FrictionLaw::Capstan: return "capstan";
    case FrictionLaw::PointContact: return "point_contact";
  }
  return "?";
}

std::string_view to_string(PairCouple c) {
  switch (c) {
    case PairCouple::None: return "none";
    case PairCouple::MotorClutch: return "motor_clutch";
  }
  return "?";
}

}  // namespace ajx::physics
