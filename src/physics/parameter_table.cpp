#include "physics/parameter_table.hpp"

#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <stdexcept>

namespace ajx::physics {

namespace {
std::string number_text(double v) { return std::isinf(v) ? "∞" : fmt::format("{}", v); }
}  // namespace

bool ParameterInfo::in_range(double v) const {
  return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
}

std::string ParameterInfo::range() const {
  return fmt::format("{}{}, {}{}", lo_open ? "(" : "[", number_text(lo), number_text(hi), hi_open ? ")" : "]");
}

const ParameterInfo* find_parameter(std::string_view key) {
  for (const ParameterInfo& p : kParameters)
    if (p.key == key) return &p;
  return nullptr;
}

const ParameterAlias* find_alias(std::string_view key) {
  for (const ParameterAlias& a : kParameterAliases)
    if (a.key == key) return &a;
  return nullptr;
}

void set_parameter(Parameters& p, std::string_view key, double v) {
  if (const ParameterInfo* info = find_parameter(key)) {
    p.*info->field = v;
  } else if (const ParameterAlias* alias = find_alias(key)) {
    for (auto field : alias->fields) p.*field = v;
  } else {
    throw std::invalid_argument(fmt::format("unknown model parameter '{}'", key));
  }
}

double parameter(const Parameters& p, std::string_view key) {
  if (const ParameterInfo* info = find_parameter(key)) return p.*info->field;
  if (const ParameterAlias* alias = find_alias(key)) return p.*alias->fields[0];
  throw std::invalid_argument(fmt::format("unknown model parameter '{}'", key));
}

namespace {
// The keys of the parameters a flag of the table marks, then the aliases (which name one).
std::vector<std::string> keys_marked(bool ParameterInfo::*flag) {
  std::vector<std::string> out;
  for (const ParameterInfo& p : kParameters)
    if (p.*flag) out.emplace_back(p.key);
  for (const ParameterAlias& a : kParameterAliases) out.emplace_back(a.key);
  return out;
}
}  // namespace

std::vector<std::string> grid_parameter_keys() { return keys_marked(&ParameterInfo::grid_axis); }
std::vector<std::string> continuation_parameter_keys() { return keys_marked(&ParameterInfo::continuation); }

std::vector<double> parameter_row(const Parameters& p) {
  std::vector<double> row;
  row.reserve(std::size(kParameters));
  for (const ParameterInfo& info : kParameters) row.push_back(p.*info.field);
  return row;
}

std::vector<std::string> parameter_column_names() {
  std::vector<std::string> out;
  for (const ParameterInfo& info : kParameters)
    out.push_back(fmt::format("{}{}", info.key, info.unit.empty() ? "" : fmt::format(" [{}]", info.unit)));
  return out;
}

std::string parameter_columns() { return fmt::format("{}", fmt::join(parameter_column_names(), ",")); }

// ---- layers -----------------------------------------------------------------------------

namespace {
constexpr std::string_view kFrictionWords[] = {"none", "kinetic", "stick_slip", "regularised", "stribeck"};
constexpr std::string_view kFrictionLawWords[] = {"capstan", "point_contact"};
constexpr std::string_view kTieWords[] = {"rigid", "clutch"};
constexpr std::string_view kPairCoupleWords[] = {"none", "motor_clutch"};
std::string yes_no(bool b) { return b ? "true" : "false"; }

const LayerInfo kLayers[] = {
    {"friction", LayerInfo::Kind::Word, kFrictionWords, nullptr, 0, 0, false, "",
     "bead–string friction: none (frictionless); kinetic (μ_k only, no stick: where the forces lie "
     "inside the μ_k cone at ṡ = 0 the bead is held and the run reports it); stick_slip (the full "
     "Coulomb law, the default); regularised (sgn ṡ → tanh(ṡ/ε), saturates at μ_k, no stuck mode, for "
     "comparison only); stribeck (μ_k sgn ṡ → [μ_k + (μ_s − μ_k) exp(−(ṡ/v_s)²)] tanh(ṡ/ε): a peak near μ_s "
     "at slip ~ ε, so a bead needing μ_k < μ* < μ_s is held by creeping at ṡ ~ ε; no stuck mode, for "
     "comparison only)",
     [](const Layers& L) { return std::string(kFrictionWords[int(L.friction)]); }},
    {"friction_law", LayerInfo::Kind::Word, kFrictionLawWords, nullptr, 0, 0, false, "",
     "how T1/T2 depends on the string's deflection ψ at the bead: capstan (belt friction over the "
     "wrap angle) or point_contact (a normal force at one point)",
     [](const Layers& L) { return std::string(kFrictionLawWords[int(L.friction_law)]); }},
    {"regularisation", LayerInfo::Kind::Number, {}, &Layers::regularisation, 0.0, 1e3, true, "m/s",
     "ε of tanh(ṡ/ε) for friction = \"regularised\" and \"stribeck\"",
     [](const Layers& L) { return fmt::format("{}", L.regularisation); }},
    {"stribeck_speed", LayerInfo::Kind::Number, {}, &Layers::stribeck_speed, 0.0, 1e3, true, "m/s",
     "v_s of friction = \"stribeck\": the slip speed over which μ falls from its peak μ_s to μ_k "
     "(exp(−(ṡ/v_s)²)); the peak is near μ_s only while ε ≪ v_s",
     [](const Layers& L) { return fmt::format("{}", L.stribeck_speed); }},
    {"bottom_stop", LayerInfo::Kind::Boolean, {}, nullptr, 0, 0, false, "",
     "one-sided contact L2 >= d of the bead on the bottom ball; off, a crossing is reported",
     [](const Layers& L) { return yes_no(L.bottom_stop); }},
    {"top_stop", LayerInfo::Kind::Boolean, {}, nullptr, 0, 0, false, "",
     "one-sided contact L1 >= s_min of the bead at the top; off, a crossing is reported",
     [](const Layers& L) { return yes_no(L.top_stop); }},
    {"slack", LayerInfo::Kind::Boolean, {}, nullptr, 0, 0, false, "",
     "the string may go slack (free flight until re-taut); off, negative tensions are reported",
     [](const Layers& L) { return yes_no(L.slack); }},
    {"restitution", LayerInfo::Kind::Number, {}, &Layers::restitution, 0.0, 1.0, false, "",
     "e of the re-taut impact of a slack string (0 plastic, 1 elastic)",
     [](const Layers& L) { return fmt::format("{}", L.restitution); }},
    {"tie", LayerInfo::Kind::Word, kTieWords, nullptr, 0, 0, false, "",
     "the string's tie to the motor's rod: rigid (the top is a(t)) or clutch (it slips on the rod "
     "past τ_s and passes τ_k on while slipping; needs model.tie_static_torque and tie_kinetic_torque)",
     [](const Layers& L) { return std::string(kTieWords[L.tie_clutch ? 1 : 0]); }},
    {"pair_couple", LayerInfo::Kind::Word, kPairCoupleWords, nullptr, 0, 0, false, "",
     "a diagnostic couple about ẑ between the motor and the lower segment: none, or motor_clutch "
     "(needs model.couple_torque); not a part of the Astrojax",
     [](const Layers& L) { return std::string(kPairCoupleWords[int(L.pair_couple)]); }},
};
}  // namespace

std::string LayerInfo::range() const {
  switch (kind) {
    case Kind::Word: return fmt::format("{}", fmt::join(words, ", "));
    case Kind::Boolean: return "true, false";
    case Kind::Number: return fmt::format("{}{}, {}]", lo_open ? "(" : "[", number_text(lo), number_text(hi));
  }
  return "";
}

std::span<const LayerInfo> layer_table() { return kLayers; }

const LayerInfo* find_layer(std::string_view key) {
  for (const LayerInfo& l : kLayers)
    if (l.key == key) return &l;
  return nullptr;
}

std::span<const std::string_view> friction_words() { return kFrictionWords; }
std::span<const std::string_view> friction_law_words() { return kFrictionLawWords; }
std::span<const std::string_view> tie_words() { return kTieWords; }
std::span<const std::string_view> pair_couple_words() { return kPairCoupleWords; }

}  // namespace ajx::physics
