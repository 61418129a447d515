// The Engine for JavaScript (embind): the page's only door into the engine. Arrays cross as
// Float64Array copies; strings as strings.
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include "web/engine.hpp"

namespace {

using ajx::web::Engine;
using emscripten::val;

val to_array(const std::vector<double>& v) {
  return val::global("Float64Array").new_(val(emscripten::typed_memory_view(v.size(), v.data())));
}

std::string configure(Engine& e, val overrides) {
  return e.configure(emscripten::vecFromJSArray<std::string>(overrides));
}
val positions(const Engine& e) { return to_array(e.positions()); }
val recent_samples(const Engine& e) { return to_array(e.recent_samples()); }
// kinetic, potential, motor work, drag, friction, impact, ΔE, residual [J]
val energies(const Engine& e) {
  const ajx::web::Energies g = e.energies();
  return to_array({g.kinetic, g.potential, g.motor_work, g.drag_loss, g.friction_loss, g.impact_loss,
                   g.delta_energy, g.residual});
}
val classify(const Engine& e) {
  const ajx::web::Verdict v = e.classify();
  val o = val::object();
  o.set("cls", v.cls);
  o.set("omegaBall", v.omega_ball);
  o.set("omegaM", v.omega_m);
  o.set("confidence", v.confidence);
  o.set("tEnd", v.t_end);
  o.set("reason", v.reason);
  return o;
}
val totals(const Engine& e) {
  const auto& s = e.totals();
  val o = val::object();
  o.set("steps", double(s.steps));
  o.set("rhsEvals", double(s.rhs_evals));
  o.set("modeSwitches", double(s.mode_switches));
  o.set("sticks", double(s.sticks));
  o.set("impacts", double(s.impacts));
  o.set("slackPhases", double(s.slack_phases));
  o.set("tieSlips", double(s.tie_slips));
  return o;
}
val parameters(const Engine& e) {
  const auto& p = e.model().p;
  const auto& L = e.model().layers;
  val o = val::object();
  o.set("l", p.string_length);
  o.set("m1", p.bead_mass);
  o.set("m2", p.ball_mass);
  o.set("cD", p.drag);
  o.set("muS", p.mu_static);
  o.set("muK", p.mu_kinetic);
  o.set("g", p.gravity);
  o.set("R", p.drive_radius);
  o.set("d", p.contact_distance);
  o.set("friction", std::string(ajx::physics::to_string(L.friction)));
  o.set("frictionLaw", std::string(ajx::physics::to_string(L.friction_law)));
  o.set("clutch", L.tie_clutch);
  return o;
}

}  // namespace

EMSCRIPTEN_BINDINGS(astrojax) {
  emscripten::class_<Engine>("Engine")
      .constructor<>()
      .function("configure", &configure)
      .function("start", &Engine::start)
      .function("hold", &Engine::hold)
      .function("ramp", &Engine::ramp)
      .function("advance", &Engine::advance)
      .function("time", &Engine::time)
      .function("omegaM", &Engine::omega_m)
      .function("omegaTarget", &Engine::omega_target)
      .function("mode", &Engine::mode)
      .function("tieSlipping", &Engine::tie_slipping)
      .function("positions", &positions)
      .function("recentSamples", &recent_samples)
      .function("energies", &energies)
      .function("classify", &classify)
      .function("totals", &totals)
      .function("parameters", &parameters)
      .function("failure", emscripten::optional_override([](const Engine& e) { return e.failure(); }))
      .function("sceneName", emscripten::optional_override([](const Engine& e) { return e.scene_name(); }));
  emscripten::function("sceneReport", &ajx::web::scene_report);
}
