// The orbit classes, declared once: the enum's order is the class code stored in
// /windows/class, and this table gives each its name, whether it is circular, what it means and
// its colour in every figure (the Okabe–Ito palette, told apart with any colour vision; grey
// for the fallen bead). The writer stores the table as /classes, from which the analysis takes
// names and colours. The exact criteria: docs/physics/orbit-classes.md.
#pragma once
#include <cstddef>
#include <optional>
#include <string_view>

namespace ajx::sweep {

enum class OrbitClass { Fallen, LockedCircular, LaggingCircular, Flower, NotSettled, Failed };

struct OrbitClassInfo {
  OrbitClass cls;
  const char* name;
  bool circular;  // the balls circle the axis at a steady radius
  const char* description;
  const char* colour;  // "#rrggbb"
};

inline constexpr OrbitClassInfo kOrbitClasses[] = {
    {OrbitClass::Fallen, "fallen", false, "the bead on the bottom ball in both halves of the window", "#999999"},
    {OrbitClass::LockedCircular, "locked-circular", true,
     "a circular orbit (radius oscillation ≤ 10 %) with |ω_ball/ω_m − 1| ≤ 0.02", "#0072B2"},
    {OrbitClass::LaggingCircular, "lagging-circular", true,
     "a circular orbit with 0 < ω_ball/ω_m < 0.98", "#009E73"},
    {OrbitClass::Flower, "flower", false, "a quasi-periodic, stationary radius oscillation (at least 4 cycles in the window)", "#CC79A7"},
    {OrbitClass::NotSettled, "not-settled", false, "a statistic changes between the window's halves beyond its tolerance, or a circular orbit decays or grows",
     "#E69F00"},
    {OrbitClass::Failed, "failed", false, "the integration failed in or before the window", "#000000"},
};
inline constexpr std::size_t kNumOrbitClasses = std::size(kOrbitClasses);

// The table's row of a class (the rows are in code order).
constexpr const OrbitClassInfo& info(OrbitClass c) { return kOrbitClasses[std::size_t(c)]; }
constexpr bool circular(OrbitClass c) { return info(c).circular; }
// "fallen", "locked-circular", ...
constexpr std::string_view to_string(OrbitClass c) {
  return std::size_t(c) < kNumOrbitClasses ? kOrbitClasses[std::size_t(c)].name : "unknown";
}
constexpr std::optional<OrbitClass> parse_orbit_class(std::string_view name) {
  for (const OrbitClassInfo& i : kOrbitClasses)
    if (name == i.name) return i.cls;
  return std::nullopt;
}

static_assert([] {
  for (std::size_t k = 0; k < kNumOrbitClasses; ++k)
    if (std::size_t(kOrbitClasses[k].cls) != k) return false;
  return true;
}(), "kOrbitClasses: one row per class, in the enum's order");

}  // namespace ajx::sweep
