// The scenes of the native-versus-WebAssembly comparison (tests/web/compare_native_wasm.py):
// one script, compiled into both builds, driving the Engine in page-sized frames of 1/60 s.
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "web/engine.hpp"

namespace ajx::web {
namespace {

constexpr double kPi = 3.141592653589793;
constexpr double kFrame = 1.0 / 60.0;  // [s] of simulated time per frame at real speed

// One line: t, ω_m, a, r1, r2, the ledger, the mode; every double exact (%a).
void print_line(std::string& out, const Engine& e) {
  out += fmt::format("t {:a} w {:a} mode {}", e.time(), e.omega_m(), e.mode());
  for (double x : e.positions()) out += fmt::format(" {:a}", x);
  const Energies g = e.energies();
  out += fmt::format(" E {:a} {:a} {:a} {:a} {:a} {:a}\n", g.kinetic, g.potential, g.motor_work, g.drag_loss,
                     g.friction_loss, g.impact_loss);
}

// `frames` frames, a line every `every` frames; `at(k)` may command the motor before frame k.
void run(std::string& out, Engine& e, int frames, int every, const std::function<void(int)>& at = {}) {
  for (int k = 0; k < frames; ++k) {
    if (at) at(k);
    if (!e.advance(kFrame)) {
      out += "failed " + e.failure() + "\n";
      return;
    }
    if ((k + 1) % every == 0) print_line(out, e);
  }
}

void print_end(std::string& out, const Engine& e) {
  const sim::RunSummary& s = e.totals();
  out += fmt::format("events switches {} sticks {} first_stick {:a} slack {} impacts {} tie_slips {}\n",
                     s.mode_switches, s.sticks, s.first_stick, s.slack_phases, s.impacts, s.tie_slips);
  const Verdict v = e.classify();
  out += fmt::format("verdict {} omega_ball {:a} omega_m {:a}\n", v.cls, v.omega_ball, v.omega_m);
}

}  // namespace

std::string scene_report(const std::string& scene) {
  // "NAME:tight": the scene at 100 times tighter tolerances, for the native result's own error.
  const bool tight = scene.size() > 6 && scene.ends_with(":tight");
  const std::string name = tight ? scene.substr(0, scene.size() - 6) : scene;
  Engine e;
  std::vector<std::string> base;  // every configure() of the scene starts from these
  if (tight) base = {"integrator.rtol=1e-11", "integrator.atol=1e-13"};
  e.configure(base);
  std::string out = "scene " + name + "\n";
  if (name == "locked") {
    // The locked orbit at 4.5π rad/s held for 10 s, then the paper's Table 1 positions at
    // 4.5π for 40 s: stick-slip from the start, and the bead falls onto the bottom ball.
    e.start("locked_orbit", 4.5 * kPi);
    run(out, e, 60 * 10, 15);
    print_end(out, e);
    e.start("circular_high", 4.5 * kPi);
    run(out, e, 60 * 40, 15);
  } else if (name == "climb") {
    // From rest, ω_m ramped up at 1 rad/s² to 14π: near 12π the bead leaves the bottom ball,
    // sticks and slips on the string and falls back (an impact when it lands).
    e.start("hanging", 0.0);
    e.ramp(14 * kPi, 1.0);
    run(out, e, 60 * 50, 15);
  } else if (name == "slack") {
    // The locked orbit at 4.5π, and after 1 s the string made 8 cm longer (l = 0.906 m): slack,
    // the balls fly free and the string jerks taut again (impacts).
    e.start("locked_orbit", 4.5 * kPi);
    run(out, e, 60 * 4, 15, [&](int k) {
      if (k == 60) {
        base.push_back("model.string_length=0.906");
        e.configure(base);
      }
    });
  } else {
    throw std::invalid_argument("unknown scene '" + name + "'; allowed: locked, climb, slack (and NAME:tight)");
  }
  print_end(out, e);
  return out;
}

}  // namespace ajx::web
