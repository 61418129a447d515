#include "physics/model.hpp"

#include <cmath>
#include <fmt/format.h>

#include "physics/parameter_table.hpp"

namespace ajx::physics {

std::vector<ParameterIssue> validate(const Model& model) {
  const Parameters& p = model.p;
  std::vector<ParameterIssue> out;
  // Each parameter in its own range (parameter_table.hpp), then the bounds between them.
  for (const ParameterInfo& info : kParameters)
    if (!info.in_range(p.*info.field))
      out.push_back({fmt::format("model.{}", info.key), p.*info.field,
                     fmt::format("{} in {}{}", info.symbol, info.range(), info.unit.empty() ? "" : " " + std::string(info.unit))});
  auto need = [&](bool ok, const char* key, double v, std::string allowed) {
    if (!ok) out.push_back({key, v, std::move(allowed)});
  };
  const double l = p.string_length;
  need(p.mu_kinetic <= p.mu_static, "model.mu_kinetic", p.mu_kinetic, fmt::format("0 <= μ_k <= μ_s = {}", p.mu_static));
  need(p.drive_radius < l, "model.drive_radius", p.drive_radius, fmt::format("0 <= R < l = {} m", l));
  need(p.contact_distance < l, "model.contact_distance", p.contact_distance, fmt::format("0 < d < l = {} m", l));
  need(p.top_stop < l - p.contact_distance, "model.top_stop", p.top_stop,
       fmt::format("0 <= s_min < l - d = {} m", l - p.contact_distance));
  need(p.tie_kinetic_torque <= p.tie_static_torque, "model.tie_kinetic_torque", p.tie_kinetic_torque,
       fmt::format("0 <= τ_k <= τ_s = {} N m", p.tie_static_torque));
  const Layers& L = model.layers;
  // The Stribeck peak reaches near μ_s only where tanh(ṡ/ε) saturates before exp(−(ṡ/v_s)²) decays.
  if (L.friction == Friction::Stribeck)
    need(L.stribeck_speed > L.regularisation, "layers.stribeck_speed", L.stribeck_speed,
         fmt::format("v_s > ε = layers.regularisation = {} m/s", L.regularisation));
  for (const LayerInfo& info : layer_table())
    if (info.kind == LayerInfo::Kind::Number && !info.in_range(L.*info.number))
      out.push_back({fmt::format("layers.{}", info.key), L.*info.number, info.range()});
  return out;
}

std::string_view to_string(Friction f) { return friction_words()[std::size_t(f)]; }

std::string_view to_string(FrictionLaw f) { return friction_law_words()[std::size_t(f)]; }

std::string_view to_string(PairCouple c) { return pair_couple_words()[std::size_t(c)]; }

}  // namespace ajx::physics
