// The state as a row of doubles, declared once: the carry a farm task hands the next, the
// sweep file's /tasks/final_state rows and their column names all come from this table. A
// layer that adds state (as the tie clutch added χ, χ̇) adds its rows here and nowhere else.
// The discrete parts (mode, σ, the tie's slip) are stored as exact small integers; χ and χ̇
// are NaN for a model without the tie-clutch layer, W_m and W_c without a clutch; a row with a
// finite χ decodes to a state of idx::dim_tie components, one with a finite W_m only to
// idx::dim_ledger.
#pragma once
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "physics/state.hpp"

namespace ajx::physics {

struct StateColumn {
  const char* name;
  const char* units;
  double (*get)(const State&);
  void (*set)(State&, double);  // y's columns beyond the state's dimension are skipped
};

namespace state_row_detail {
template <int K>
double y_get(const State& s) {
  return K < s.y.size() ? s.y(K) : std::numeric_limits<double>::quiet_NaN();
}
template <int K>
void y_set(State& s, double v) {
  if (K < s.y.size()) s.y(K) = v;
}
}  // namespace state_row_detail

#define AJX_Y(name, units, k) \
  StateColumn { name, units, state_row_detail::y_get<k>, state_row_detail::y_set<k> }
inline constexpr StateColumn kStateColumns[] = {
    {"t", "s", [](const State& s) { return s.t; }, [](State& s, double v) { s.t = v; }},
    {"mode", "", [](const State& s) { return double(s.contact.mode); },
     [](State& s, double v) { s.contact.mode = static_cast<Mode>(int(v)); }},
    {"sigma", "", [](const State& s) { return double(s.contact.sigma); },
     [](State& s, double v) { s.contact.sigma = int(v); }},
    {"s_star", "m", [](const State& s) { return s.contact.s_star; }, [](State& s, double v) { s.contact.s_star = v; }},
    {"impact_loss", "J", [](const State& s) { return s.impact_loss; }, [](State& s, double v) { s.impact_loss = v; }},
    AJX_Y("r1_x", "m", idx::r1), AJX_Y("r1_y", "m", idx::r1 + 1), AJX_Y("r1_z", "m", idx::r1 + 2),
    AJX_Y("r2_x", "m", idx::r2), AJX_Y("r2_y", "m", idx::r2 + 1), AJX_Y("r2_z", "m", idx::r2 + 2),
    AJX_Y("v1_x", "m/s", idx::v1), AJX_Y("v1_y", "m/s", idx::v1 + 1), AJX_Y("v1_z", "m/s", idx::v1 + 2),
    AJX_Y("v2_x", "m/s", idx::v2), AJX_Y("v2_y", "m/s", idx::v2 + 1), AJX_Y("v2_z", "m/s", idx::v2 + 2),
    AJX_Y("motor_work", "J", idx::motor_work), AJX_Y("drag_loss", "J", idx::drag_loss),
    AJX_Y("friction_loss", "J", idx::friction_loss),
    {"tie_slip", "", [](const State& s) { return double(s.contact.tie.slip); },
     [](State& s, double v) { s.contact.tie.slip = v != 0.0; }},
    {"tie_sigma", "", [](const State& s) { return double(s.contact.tie.sigma); },
     [](State& s, double v) { s.contact.tie.sigma = int(v); }},
    {"tie_offset", "rad", [](const State& s) { return s.contact.tie.offset; },
     [](State& s, double v) { s.contact.tie.offset = v; }},
    AJX_Y("chi", "rad", idx::chi), AJX_Y("chi_dot", "rad/s", idx::chi_dot),
    // the motor's ledger where it drives through a clutch: W_m, W_c (NaN without one)
    AJX_Y("rod_work", "J", idx::rod_work), AJX_Y("clutch_loss", "J", idx::clutch_loss),
};
#undef AJX_Y
inline constexpr std::size_t kStateCols = std::size(kStateColumns);
inline constexpr std::size_t kStateChiColumn = kStateCols - 4;      // finite only with the tie clutch
inline constexpr std::size_t kStateRodWorkColumn = kStateCols - 2;  // finite with the tie clutch or the pair couple

inline std::vector<double> state_row(const State& s) {
  std::vector<double> row(kStateCols);
  for (std::size_t k = 0; k < kStateCols; ++k) row[k] = kStateColumns[k].get(s);
  return row;
}

// The inverse of state_row, bit for bit.
inline State state_from_row(std::span<const double> row) {
  State s;
  s.y.resize(std::isfinite(row[kStateChiColumn])       ? idx::dim_tie
             : std::isfinite(row[kStateRodWorkColumn]) ? idx::dim_ledger
                                                       : idx::dim);
  for (std::size_t k = 0; k < kStateCols; ++k) kStateColumns[k].set(s, row[k]);
  return s;
}

// "t [s]", "mode", ...: the names of the row's columns with their units.
inline std::vector<std::string> state_column_names() {
  std::vector<std::string> out;
  for (const StateColumn& c : kStateColumns)
    out.push_back(*c.units ? std::string(c.name) + " [" + c.units + "]" : std::string(c.name));
  return out;
}

}  // namespace ajx::physics
