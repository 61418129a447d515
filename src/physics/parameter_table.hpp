// The model described once. Every parameter of physics::Parameters and every layer of
// physics::Layers has one row here; the configuration reader, --set, the [grid] axes, the
// /chains/model columns, the resolved configuration stored in every output file, the
// continuation's parameter list and the configuration reference of the docs all read it.
// Adding a parameter: a field in Parameters (model.hpp), a row in kParameters, and the physics
// that uses it; nothing else.
#pragma once
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "physics/model.hpp"

namespace ajx::physics {

// One number of Parameters. The range is the one a value must lie in by itself; ranges that
// depend on other parameters (R < l, μ_k <= μ_s, ...) are validate()'s, and `depends` says
// them in words for the reference. The default is Parameters{}'s.
struct ParameterInfo {
  std::string_view key;          // in [model], /chains/model, [grid], the continuation
  double Parameters::*field;
  std::string_view symbol;       // as in the physics docs
  std::string_view unit;         // SI, "" for a pure number
  double lo, hi;
  bool lo_open, hi_open;
  bool grid_axis;                // may be a [grid] axis of a sweep
  bool continuation;             // may be the continued parameter of `astrojax orbits`
  std::string_view depends;      // the cross-parameter bound validate() checks, or ""
  std::string_view doc;          // one line for the reference

  double default_value() const { return Parameters{}.*field; }
  bool in_range(double v) const;
  std::string range() const;     // "(0, 100]", "[0, ∞)"
};

inline constexpr double kUnbounded = std::numeric_limits<double>::infinity();

// Rows in the order of the /chains/model columns (files of format 1 hold the first 10, 14 or
// 16 of these rows only: the tie clutch's four came after the first ten, the couple's two last).
inline constexpr ParameterInfo kParameters[] = {
    {"string_length", &Parameters::string_length, "l", "m", 0.0, 100.0, true, false, true, true, "",
     "length of the string from the top to the bottom ball"},
    {"bead_mass", &Parameters::bead_mass, "m1", "kg", 0.0, kUnbounded, true, true, false, true, "",
     "mass of the middle ball (the bead that slides on the string)"},
    {"ball_mass", &Parameters::ball_mass, "m2", "kg", 0.0, kUnbounded, true, true, false, true, "",
     "mass of the bottom ball, fixed to the string's end"},
    {"drag", &Parameters::drag, "c_D", "kg/s", 0.0, kUnbounded, false, true, true, true, "",
     "linear air drag, a force −c_D v on each ball"},
    {"mu_static", &Parameters::mu_static, "μ_s", "", 0.0, kUnbounded, false, true, true, true, "",
     "static friction coefficient between bead and string"},
    {"mu_kinetic", &Parameters::mu_kinetic, "μ_k", "", 0.0, kUnbounded, false, true, true, true, "μ_k <= μ_s",
     "kinetic friction coefficient between bead and string"},
    {"gravity", &Parameters::gravity, "g", "m/s^2", 0.0, kUnbounded, false, true, false, true, "",
     "gravitational acceleration"},
    {"drive_radius", &Parameters::drive_radius, "R", "m", 0.0, kUnbounded, false, true, true, true, "R < l",
     "radius of the circle the string's top follows on the motor's rod"},
    {"contact_distance", &Parameters::contact_distance, "d", "m", 0.0, kUnbounded, true, true, true, true, "d < l",
     "closest approach of the bead to the bottom ball along the string: L2 >= d"},
    {"top_stop", &Parameters::top_stop, "s_min", "m", 0.0, kUnbounded, false, true, false, false, "s_min < l − d",
     "closest approach of the bead to the top along the string: L1 >= s_min (top-stop layer)"},
    {"tie_static_torque", &Parameters::tie_static_torque, "τ_s", "N m", 0.0, kUnbounded, false, true, true, true, "",
     "largest torque the tie holds on the rod without slipping (tie = \"clutch\"; required with it)"},
    {"tie_kinetic_torque", &Parameters::tie_kinetic_torque, "τ_k", "N m", 0.0, kUnbounded, false, true, true, true,
     "τ_k <= τ_s", "torque the slipping tie passes on (tie = \"clutch\"; required with it)"},
    {"tie_inertia", &Parameters::tie_inertia, "I_a", "kg m^2", 0.0, kUnbounded, true, true, false, false, "",
     "moment of inertia of the tie about the motor axis (tie = \"clutch\")"},
    {"tie_damping", &Parameters::tie_damping, "c_a", "N m s", 0.0, kUnbounded, false, true, true, true, "",
     "viscous part of the slipping tie's torque, c_a (ω_m − χ̇) (tie = \"clutch\")"},
    {"couple_torque", &Parameters::couple_torque, "τ_c", "N m", 0.0, kUnbounded, false, true, true, false, "",
     "magnitude of the diagnostic couple between motor and lower segment (pair_couple = \"motor_clutch\")"},
    {"couple_slip_rate", &Parameters::couple_slip_rate, "Ω_ε", "rad/s", 0.0, kUnbounded, true, true, true, false, "",
     "slip rate of the couple's tanh((ω_m − β̇)/Ω_ε) (pair_couple = \"motor_clutch\")"},
};

// A name that sets several parameters at once: `mass` sets m1 = m2 (a [grid] axis and a
// continuation parameter; not a [model] key).
struct ParameterAlias {
  std::string_view key;
  double Parameters::*fields[2];
  std::string_view symbol, unit, doc;
};
inline constexpr ParameterAlias kParameterAliases[] = {
    {"mass", {&Parameters::bead_mass, &Parameters::ball_mass}, "m1 = m2", "kg", "both balls' mass, kept equal"},
};

const ParameterInfo* find_parameter(std::string_view key);
const ParameterAlias* find_alias(std::string_view key);

// A parameter or an alias, set or read by name (the [grid] axes, the continuation).
void set_parameter(Parameters& p, std::string_view key, double v);  // key known, else std::invalid_argument
double parameter(const Parameters& p, std::string_view key);

// The names of the [grid] axes that set a parameter, and of the continuation's parameters
// (parameters, then aliases, in table order).
std::vector<std::string> grid_parameter_keys();
std::vector<std::string> continuation_parameter_keys();

// One row of /chains/model: every parameter, in table order.
std::vector<double> parameter_row(const Parameters& p);
// "string_length [m],bead_mass [kg],...": the column names of that row, with units.
std::string parameter_columns();
// The same, one name per column: "drive_radius [m]", ...
std::vector<std::string> parameter_column_names();

// ---- layers -----------------------------------------------------------------------------

// One layer of physics::Layers: its key in [layers], the values it takes (words, or a range
// for a number), its default and doc line, and how to read it back as the TOML value.
struct LayerInfo {
  enum class Kind { Word, Boolean, Number };
  std::string_view key;
  Kind kind;
  std::span<const std::string_view> words;  // Kind::Word: the allowed values, enum order
  double Layers::*number;                   // Kind::Number: the field and its range
  double lo, hi;
  bool lo_open;
  std::string_view unit;
  std::string_view doc;
  std::string (*value)(const Layers&);      // as written in TOML: "stick_slip", "true", "0.001"

  bool in_range(double v) const { return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && v <= hi; }
  std::string range() const;
  std::string default_value() const { return value(Layers{}); }
};

std::span<const LayerInfo> layer_table();
const LayerInfo* find_layer(std::string_view key);

// The words of the enum layers, in enum order (to_string's names).
std::span<const std::string_view> friction_words();
std::span<const std::string_view> friction_law_words();
std::span<const std::string_view> tie_words();
std::span<const std::string_view> pair_couple_words();

}  // namespace ajx::physics
