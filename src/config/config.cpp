#include "config/config.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>
#include <limits>
#include <optional>
#include <fmt/format.h>
#include <filesystem>
#include <fstream>
#include <set>
#include <span>
#include <sstream>
#include <toml++/toml.h>

#include "config/did_you_mean.hpp"
#include "config/text.hpp"
#include "config/key_catalogue.hpp"
#include "physics/parameter_table.hpp"
#include "numerics/stepper.hpp"
#include "orbits/continuation.hpp"
#include "sim/paper_scheme.hpp"
#include "sim/table1_starts.hpp"

namespace ajx::config {

namespace {

// Reads typed values out of one TOML table, remembering which keys were used so that
// unknown ones can be reported.
class Reader {
 public:
  Reader(const toml::table& t, std::string prefix, std::string_view file)
      : t_(t), prefix_(std::move(prefix)), section_(generic_section(prefix_)), file_(file) {}

  [[noreturn]] void fail(std::string_view key, std::string_view what) const {
    throw ConfigError(fmt::format("{}: key '{}': {}", file_, full(key), what));
  }
  std::string full(std::string_view key) const { return prefix_.empty() ? std::string(key) : prefix_ + "." + std::string(key); }
  bool has(std::string_view key) const { return t_.contains(key); }
  const toml::table& table() const { return t_; }
  // A key read elsewhere, not to be reported as unknown.
  void known(std::string_view key) {
    if (const KeyInfo* k = find_key(section_, key)) note_read(*k);  // a catalogue key read by hand
    used_.insert(std::string(key));
  }

  // A number within [lo, hi] (open ends when the flags say so).
  double number(std::string_view key, double fallback, double lo, double hi, bool lo_open = false,
                bool hi_open = false) {
    const KeyInfo& doc = documented(key);
    if (!std::isnan(doc.lo) && (doc.lo != lo || doc.hi != hi || doc.lo_open != lo_open || doc.hi_open != hi_open))
      throw std::logic_error(fmt::format("key '{}' of [{}] is read with the range {}{}, {}{} but documented as {}", key,
                                         section_, lo_open ? "(" : "[", lo, hi, hi_open ? ")" : "]", doc.allowed));
    used_.insert(std::string(key));
    const toml::node* n = t_.get(key);
    if (!n) return fallback;
    if (!n->is_number()) fail(key, "expected a number");
    // toml++ gives no double for an integer that a double cannot hold exactly (|v| > 2^53).
    const std::optional<double> x = n->value<double>();
    if (!x) fail(key, "expected a number; this integer is too large to be held exactly");
    const double v = *x;
    const bool ok = std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
    if (!ok)
      fail(key, fmt::format("{} is out of range; allowed {}{}, {}{}", v, lo_open ? "(" : "[", lo, hi,
                            hi_open ? ")" : "]"));
    return v;
  }
  // A count: a whole number within [lo, hi] (2.5 windows is refused, not truncated).
  long count(std::string_view key, long fallback, double lo, double hi) {
    const double v = number(key, double(fallback), lo, hi);
    if (v != std::floor(v)) fail(key, fmt::format("{} is not a whole number; allowed {}, {}, ..., {}", v, lo, lo + 1, hi));
    return long(v);
  }
  std::string word(std::string_view key, std::string fallback, const std::vector<std::string>& allowed) {
    documented(key);
    used_.insert(std::string(key));
    const toml::node* n = t_.get(key);
    if (!n) return fallback;
    if (!n->is_string()) fail(key, "expected a string");
    std::string v = n->value<std::string>().value();
    if (std::find(allowed.begin(), allowed.end(), v) == allowed.end())
      fail(key, fmt::format("'{}' is not allowed; allowed: {}", v, fmt::join(allowed, ", ")));
    return v;
  }
  std::string text(std::string_view key, std::string fallback) {
    documented(key);
    used_.insert(std::string(key));
    const toml::node* n = t_.get(key);
    if (!n) return fallback;
    if (!n->is_string() || n->value<std::string>()->empty()) fail(key, "expected a non-empty string");
    return *n->value<std::string>();
  }
  bool boolean(std::string_view key, bool fallback) {
    documented(key);
    used_.insert(std::string(key));
    const toml::node* n = t_.get(key);
    if (!n) return fallback;
    if (!n->is_boolean()) fail(key, "expected true or false");
    return *n->value<bool>();
  }
  physics::Vec3 vec3(std::string_view key, double bound) {
    documented(key);
    used_.insert(std::string(key));
    const toml::array* a = t_.get_as<toml::array>(key);
    if (!a || a->size() != 3) fail(key, "expected an array of 3 numbers");
    physics::Vec3 v;
    for (int i = 0; i < 3; ++i) {
      const auto x = (*a)[std::size_t(i)].value<double>();
      if (!x || !std::isfinite(*x) || std::abs(*x) > bound)
        fail(key, fmt::format("component {} must be a number in [-{}, {}]", i, bound, bound));
      v(i) = *x;
    }
    return v;
  }
  // An unknown key names the nearest allowed one, if it looks like a typo, and lists them all.
  void reject_unknown() const {
    for (const auto& [k, v] : t_)
      if (!used_.count(std::string(k.str()))) {
        const std::string near = closest(k.str(), used_);
        fail(k.str(), fmt::format("unknown key{}; allowed: {}", near.empty() ? "" : " (did you mean '" + near + "'?)",
                                  fmt::join(used_, ", ")));
      }
  }

 private:
  // Every key read is in the catalogue (key_catalogue.hpp): the reference lists what is read.
  const KeyInfo& documented(std::string_view key) const {
    const KeyInfo* k = find_key(section_, key);
    if (!k)
      throw std::logic_error(fmt::format("key '{}' of [{}] is read but missing from the key catalogue", key, section_));
    note_read(*k);
    return *k;
  }

  const toml::table& t_;
  std::string prefix_;
  std::string section_;  // the catalogue's name of the prefix
  std::string_view file_;
  std::set<std::string> used_;
};

const toml::table& subtable(const toml::table& root, std::string_view name, std::string_view file) {
  static const toml::table empty;
  const toml::node* n = root.get(name);
  if (!n) return empty;
  if (!n->is_table()) throw ConfigError(fmt::format("{}: key '{}': expected a table [{}]", file, name, name));
  return *n->as_table();
}

// ω_m bound of every schedule, protocol and hold: far above any motor [rad/s].
constexpr double kOmegaMax = 2000.0;

// Each table of an array of segments, read with the key prefix `name[i]`; its unknown keys
// are rejected once `read` has taken what it knows.
template <class Read>
void each_table(const toml::array& arr, std::string_view name, std::string_view file, Read&& read) {
  for (std::size_t i = 0; i < arr.size(); ++i) {
    const std::string prefix = fmt::format("{}[{}]", name, i);
    const toml::table* t = arr[i].as_table();
    if (!t) throw ConfigError(fmt::format("{}: key '{}': expected a table", file, prefix));
    Reader r(*t, prefix, file);
    read(r);
    r.reject_unknown();
  }
}

// "a.b.c=value" into the table, creating tables on the way.
void apply_override(toml::table& root, const std::string& kv, std::string_view file) {
  const auto eq = kv.find('=');
  if (eq == std::string::npos || eq == 0)
    throw ConfigError(fmt::format("{}: override '{}': expected key=value", file, kv));
  // One value on one line: a newline would let the value add tables and keys of its own.
  if (kv.find_first_of("\r\n") != std::string::npos)
    throw ConfigError(fmt::format("{}: override '{}': a newline is not allowed; give key=value with one TOML value",
                                  file, kv));
  const std::string key = kv.substr(0, eq), value = kv.substr(eq + 1);
  toml::table* t = &root;
  std::size_t start = 0;
  for (std::size_t dot; (dot = key.find('.', start)) != std::string::npos; start = dot + 1) {
    const std::string part = key.substr(start, dot - start);
    if (!t->contains(part)) t->insert(part, toml::table{});
    t = t->get_as<toml::table>(part);
    if (!t) throw ConfigError(fmt::format("{}: override '{}': '{}' is not a table", file, kv, part));
  }
  const std::string leaf = key.substr(start);
  if (leaf.empty()) throw ConfigError(fmt::format("{}: override '{}': expected key=value", file, kv));
  try {
    toml::table v = toml::parse("v = " + value);
    t->insert_or_assign(leaf, std::move(*v.get("v")));
  } catch (const toml::parse_error&) {
    t->insert_or_assign(leaf, value);  // a bare word: a string
  }
}

std::vector<physics::DriveSegment> parse_schedule(const toml::table& root, std::string_view file) {
  const toml::node* n = root.get("schedule");
  const toml::array* arr = n ? n->as_array() : nullptr;
  if (!arr || arr->empty())
    throw ConfigError(fmt::format(
        "{}: key 'schedule': the motor schedule is empty; give at least one [[schedule]] segment "
        "(kind = \"hold\" with omega and duration, or kind = \"ramp\" with from, to and rate or duration)",
        file));
  std::vector<physics::DriveSegment> out;
  each_table(*arr, "schedule", file, [&](Reader& r) {
    const std::string kind = r.word("kind", "", {"hold", "ramp"});
    if (kind.empty()) r.fail("kind", "missing; allowed: hold, ramp");
    physics::DriveSegment s{};
    if (kind == "hold") {
      s.omega_begin = s.omega_end = r.number("omega", NAN, 0.0, kOmegaMax);
      if (!r.has("omega")) r.fail("omega", "missing (ω_m of the hold [rad/s])");
      if (!r.has("duration")) r.fail("duration", "missing (length of the hold [s])");
      s.duration = r.number("duration", NAN, 0.0, 1e7, true);
    } else {
      for (const char* k : {"from", "to"})
        if (!r.has(k)) r.fail(k, "missing (ω_m at the ramp's start and end [rad/s])");
      s.omega_begin = r.number("from", NAN, 0.0, kOmegaMax);
      s.omega_end = r.number("to", NAN, 0.0, kOmegaMax);
      if (r.has("rate") == r.has("duration"))
        r.fail("rate", "give exactly one of rate (|dω_m/dt| > 0 [rad/s²]) and duration (> 0 [s])");
      if (s.omega_end == s.omega_begin) r.fail("to", "a ramp needs to != from; use kind = \"hold\"");
      if (r.has("rate"))
        s.duration = std::abs(s.omega_end - s.omega_begin) / r.number("rate", NAN, 0.0, 1e4, true);
      else
        s.duration = r.number("duration", NAN, 0.0, 1e7, true);
    }
    out.push_back(s);
  });
  return out;
}

// [model], [layers], [integrator] and [initial]: shared by every command.
// A word of `words` (an enum's names in enum order) read as that enum.
template <class Enum>
Enum enum_word(Reader& r, std::string_view key, Enum fallback, std::span<const std::string_view> words) {
  const std::string w = r.word(key, std::string(words[std::size_t(fallback)]), {words.begin(), words.end()});
  return Enum(std::find(words.begin(), words.end(), w) - words.begin());
}

// The bounds between keys (physics::validate), once the model and the layers are read.
void require_valid(const physics::Model& model, std::string_view file) {
  for (const auto& issue : physics::validate(model))
    throw ConfigError(fmt::format("{}: key '{}': {} is out of range; allowed {}", file, issue.key,
                                  issue.value, issue.allowed));
}

// [model]: each number in its range (the parameter table); the bounds between them follow the layers.
void parse_model(const toml::table& root, std::string_view file, CommonConfig& c) {
  Reader r(subtable(root, "model", file), "model", file);
  physics::Parameters& p = c.model.p;
  for (const physics::ParameterInfo& m : physics::kParameters)
    p.*m.field = r.number(m.key, p.*m.field, m.lo, m.hi, m.lo_open, m.hi_open);
  r.reject_unknown();
}

// [layers]: the words and numbers of the layer table; a clutch tie and the pair couple need their torques in [model].
void parse_layers(const toml::table& root, std::string_view file, CommonConfig& c) {
  const toml::table& model = subtable(root, "model", file);
  const bool tie_torques_given = model.contains("tie_static_torque") && model.contains("tie_kinetic_torque");
  const bool couple_torque_given = model.contains("couple_torque");
  Reader r(subtable(root, "layers", file), "layers", file);
  physics::Layers& L = c.model.layers;
  L.friction = enum_word(r, "friction", L.friction, physics::friction_words());
  L.friction_law = enum_word(r, "friction_law", L.friction_law, physics::friction_law_words());
  L.pair_couple = enum_word(r, "pair_couple", L.pair_couple, physics::pair_couple_words());
  L.tie_clutch = enum_word(r, "tie", int(L.tie_clutch), physics::tie_words()) == 1;
  L.bottom_stop = r.boolean("bottom_stop", L.bottom_stop);
  L.top_stop = r.boolean("top_stop", L.top_stop);
  L.slack = r.boolean("slack", L.slack);
  for (const physics::LayerInfo& info : physics::layer_table())
    if (info.kind == physics::LayerInfo::Kind::Number)
      L.*info.number = r.number(info.key, L.*info.number, info.lo, info.hi, info.lo_open);
  if (c.model.layers.tie_clutch && !tie_torques_given)
    r.fail("tie", "\"clutch\" needs model.tie_static_torque and model.tie_kinetic_torque (τ_s >= τ_k >= 0 [N m])");
  if (c.model.layers.pair_couple == physics::PairCouple::MotorClutch && !couple_torque_given)
    r.fail("pair_couple", "\"motor_clutch\" needs model.couple_torque (τ_c >= 0 [N m])");
  r.reject_unknown();
}

// [integrator]: the method, its tolerances or step, and the step bound from the guards.
void parse_integrator(const toml::table& root, std::string_view file, CommonConfig& c) {
  Reader r(subtable(root, "integrator", file), "integrator", file);
  std::vector<std::string> methods;
  std::stringstream ss{std::string(numerics::stepper_names())};
  for (std::string w; std::getline(ss, w, ',');) {
    w.erase(0, w.find_first_not_of(' '));
    methods.push_back(w);
  }
  // The paper's own two-step scheme (sim/paper_scheme.hpp): its own simulation path.
  methods.insert(methods.end(), {"paper", "paper_corrected"});
  c.run.method = r.word("method", c.run.method, methods);
  if (sim::paper_variant(c.run.method))
    for (const auto& [key, need] : sim::paper_scheme_conflicts(c.model))
      throw ConfigError(fmt::format("{}: key '{}': integrator.method = \"{}\" needs {}", file, key, c.run.method, need));
  c.run.integ.tol.rtol = r.number("rtol", 1e-10, 1e-15, 1.0, false, true);
  c.run.integ.tol.atol = r.number("atol", 1e-12, 0.0, 1.0, true);
  c.run.integ.h_fixed = r.number("step", 5e-4, 0.0, 0.1, true);
  // max_step: "auto" (the default) bounds each step by the guards' time scale, h <= 1/Ω
  // (sim/step_bound.hpp, measured: docs/reports/accuracy-and-speed.md, "A step bound from the guards' time scales"); a
  // number is a fixed bound instead.
  const toml::node* max_step = r.has("max_step") ? subtable(root, "integrator", file).get("max_step") : nullptr;
  c.run.guard_step_bound = !max_step || max_step->is_string();
  if (c.run.guard_step_bound) {
    r.known("max_step");
    if (max_step && max_step->value<std::string>() != "auto")
      r.fail("max_step", fmt::format("'{}' is not allowed; allowed: \"auto\" or a number in (0, 10] s",
                                     *max_step->value<std::string>()));
    c.run.integ.h_max = 10.0;
  } else {
    c.run.integ.h_max = r.number("max_step", 0.05, 0.0, 10.0, true);
  }
  // event_samples: guard samples inside each step on the dense output; with "auto" the bound
  // becomes h <= (event_samples + 1)/Ω (sim/step_bound.hpp; measured: docs/reports/accuracy-and-speed.md, "Guard samples
  // inside the step"). With a fixed max_step none by default (each step would take them all).
  {
    const double k =
        r.number("event_samples", c.run.guard_step_bound ? c.run.integ.event_samples : 0, 0.0, 16.0);
    if (k != std::floor(k)) r.fail("event_samples", fmt::format("{} is not a whole number; allowed 0, 1, ..., 16", k));
    c.run.integ.event_samples = int(k);
  }
  // The integrator's axes (physics/rotating_axes.hpp): measured, docs/reports/accuracy-and-speed.md.
  const std::string axes = r.word("axes", "rotating", {"rotating", "lab", "auto"});
  c.run.axes = axes == "lab" ? sim::Axes::Lab : axes == "auto" ? sim::Axes::Auto : sim::Axes::Rotating;
  c.run.projection_tol = r.number("projection_tol", 1e-12, 0.0, 1e-3, true);
  c.run.max_events = r.count("max_events", 1000000, 1.0, 1e12);
  c.run.omega_window = r.number("omega_window", 10.0, 0.0, 1e7, true);
  c.run.rest_speed = r.number("rest_speed", c.run.rest_speed, 0.0, 1.0);
  c.run.chatter_switches = int(r.count("chatter_switches", c.run.chatter_switches, 2.0, 1e6));
  c.run.chatter_window = r.number("chatter_window", c.run.chatter_window, 0.0, 1e3, true);
  r.reject_unknown();
}

// [initial]: the start: hanging, explicit, or a two-step pair (table1, pair).
void parse_initial(const toml::table& root, std::string_view file, CommonConfig& c) {
  Reader r(subtable(root, "initial", file), "initial", file);
  c.initial.preset = r.word("preset", "hanging", {"hanging", "explicit", "table1", "pair"});
  // Two-step starts (sim/paper_scheme.hpp): positions at t = 0 and at t = integrator.step.
  if (c.initial.preset == "table1") {
    c.initial.orbit = r.word("orbit", "circular1", sim::table1_orbits());
    c.initial.orbit_omega = r.number("omega", NAN, 0.0, kOmegaMax);  // the circular orbits' θ = ω h
  }
  if (c.initial.preset == "pair") {
    const double bound = 10.0 * c.model.p.string_length;
    for (const char* k : {"r1", "r2", "r1_next", "r2_next"})
      if (!r.has(k)) r.fail(k, "missing: \"pair\" needs r1, r2 (at t = 0) and r1_next, r2_next (at t = integrator.step) [m]");
    c.initial.r1 = r.vec3("r1", bound);
    c.initial.r2 = r.vec3("r2", bound);
    c.initial.r1_next = r.vec3("r1_next", bound);
    c.initial.r2_next = r.vec3("r2_next", bound);
  }
  if (c.initial.preset == "hanging" && !c.model.layers.bottom_stop)
    r.fail("preset", "'hanging' rests the bead on the bottom ball and needs layers.bottom_stop = true");
  if (c.initial.preset == "explicit") {
    const double bound = 10.0 * c.model.p.string_length;
    c.initial.r1 = r.vec3("r1", bound);
    c.initial.r2 = r.vec3("r2", bound);
    c.initial.v1 = r.has("v1") ? r.vec3("v1", 1e3) : physics::Vec3::Zero();
    c.initial.v2 = r.has("v2") ? r.vec3("v2", 1e3) : physics::Vec3::Zero();
    const std::string mode = r.word("mode", "sliding", {"sliding", "bottom_stop", "stuck", "slack"});
    c.initial.mode = mode == "sliding"       ? physics::Mode::Sliding
                     : mode == "bottom_stop" ? physics::Mode::BottomStop
                     : mode == "stuck"       ? physics::Mode::Stuck
                                             : physics::Mode::Slack;
    c.initial.length_tolerance =
        r.number("length_tolerance", c.initial.length_tolerance, 0.0, 0.1 * c.model.p.string_length, true);
    if (r.has("tie_slip_rate")) {
      if (!c.model.layers.tie_clutch) r.fail("tie_slip_rate", "needs layers.tie = \"clutch\"");
      c.initial.tie_slip_rate = r.number("tie_slip_rate", 0.0, -1e4, 1e4);
    }
  }
  r.reject_unknown();
}

void parse_common(const toml::table& root, std::string_view file, CommonConfig& c) {
  parse_model(root, file, c);
  parse_layers(root, file, c);
  require_valid(c.model, file);
  parse_integrator(root, file, c);
  parse_initial(root, file, c);
}

// The file parsed, syntax errors with their line and column.
toml::table parse_text(std::string_view text, std::string_view file) {
  try {
    return toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    throw ConfigError(fmt::format("{}:{}:{}: {}", file, e.source().begin.line, e.source().begin.column,
                                  e.description()));
  }
}

// A top-level table not in `known` (a typo in the file or in a --set) is refused, naming the
// nearest allowed one. Keys are compared as typed: a lookalike letter (a Cyrillic о for an o)
// makes another key.
void reject_unknown_tables(const toml::table& root, const std::set<std::string>& known, std::string_view file) {
  for (const auto& [k, v] : root)
    if (!known.count(std::string(k.str()))) {
      const std::string near = closest(k.str(), known);
      throw ConfigError(fmt::format("{}: key '{}': unknown key{}; allowed tables: {}", file, k.str(),
                                    near.empty() ? "" : " (did you mean '" + near + "'?)", fmt::join(known, ", ")));
    }
}

// The file parsed, the overrides applied, and the top-level tables checked against `known`.
toml::table parse_root(std::string_view text, std::string_view file, const std::vector<std::string>& overrides,
                       const std::set<std::string>& known) {
  toml::table root = parse_text(text, file);
  for (const auto& o : overrides) apply_override(root, o, file);
  reject_unknown_tables(root, known, file);
  return root;
}

std::string read_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw ConfigError(fmt::format("{}: is a directory; give the configuration file (TOML) itself", path));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(fmt::format("{}: cannot open the configuration file", path));
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// What every command does first: keep the source, parse it with the overrides, check the
// top-level tables against `known` and read the shared sections.
toml::table begin(CommonConfig& c, std::string_view text, std::string_view source_name,
                  const std::vector<std::string>& overrides, const std::set<std::string>& known) {
  c.source_name = source_name;
  c.source_text = text;
  c.overrides = overrides;
  toml::table root = parse_root(text, c.source_name, overrides, known);
  parse_common(root, c.source_name, c);
  return root;
}

}  // namespace

RunConfig parse_run_config(std::string_view text, std::string_view source_name,
                           const std::vector<std::string>& overrides) {
  RunConfig c;
  const toml::table root =
      begin(c, text, source_name, overrides, {"model", "layers", "integrator", "initial", "schedule", "output"});
  const std::string_view file = c.source_name;
  c.schedule = parse_schedule(root, file);
  {
    Reader r(subtable(root, "output", file), "output", file);
    c.output.path = r.text("path", c.output.path);
    c.output.sample_interval = r.number("sample_interval", c.output.sample_interval, 0.0, 1e6, true);
    r.reject_unknown();
  }
  return c;
}

RunConfig load_run_config(const std::string& path, const std::vector<std::string>& overrides) {
  return parse_run_config(read_file(path), path, overrides);
}

namespace {

// A value list: an array of numbers, or {start, stop, num} (num >= 1, both ends included).
std::vector<double> value_list(const toml::node& n, const std::string& key, std::string_view file) {
  std::vector<double> out;
  if (const toml::array* a = n.as_array()) {
    for (std::size_t i = 0; i < a->size(); ++i) {
      const auto v = (*a)[i].value<double>();
      if (!v || !std::isfinite(*v))
        throw ConfigError(fmt::format("{}: key '{}[{}]': expected a number", file, key, i));
      out.push_back(*v);
    }
  } else if (const toml::table* t = n.as_table()) {
    Reader r(*t, key, file);
    for (const char* k : {"start", "stop", "num"})
      if (!r.has(k)) r.fail(k, "missing: give start, stop and num (num >= 1)");
    const double a = r.number("start", 0.0, -1e12, 1e12), b = r.number("stop", 0.0, -1e12, 1e12);
    const int num = int(r.count("num", 1, 1.0, 1e5));
    r.reject_unknown();
    for (int i = 0; i < num; ++i) out.push_back(num == 1 ? a : a + (b - a) * i / (num - 1));
  } else {
    throw ConfigError(fmt::format("{}: key '{}': expected an array of numbers or {{start, stop, num}}", file, key));
  }
  if (out.empty()) throw ConfigError(fmt::format("{}: key '{}': the list is empty", file, key));
  return out;
}

// [protocol] or [hold]: early_stop (on unless set false) and its tolerance ε
// (sim/settle_watch.hpp), at most the classifier's tightest drift tolerance (L1_drift_tol =
// 0.01): a larger ε could move a class. [basin] and [bisect] have no such key: their settles run
// in full (SweepSpec::early_stop).
void read_early_stop(Reader& r, SweepConfig& c) {
  c.early_stop = r.boolean("early_stop", true);
  c.early_stop_tolerance = r.number("early_stop_tolerance", c.early_stop_tolerance, 0.0, 0.01, true);
}

std::vector<sweep::Segment> parse_protocol(const toml::table& root, std::string_view file, SweepConfig& c) {
  const toml::table& pt = subtable(root, "protocol", file);
  Reader r(pt, "protocol", file);
  c.start_omega = r.number("start_omega", 0.0, 0.0, kOmegaMax);
  c.start_seed = r.word("start_seed", "hanging", {"hanging", "circular_high", "locked_orbit"});
  c.windows_per_task = int(r.count("windows_per_task", 10, 1.0, 1e6));
  c.sample_rate = r.number("sample_rate", 100.0, 0.0, 1e5, true);
  read_early_stop(r, c);
  const toml::array* arr = pt.get_as<toml::array>("segment");
  r.known("segment");  // its content is checked below
  if (!arr || arr->empty())
    throw ConfigError(fmt::format(
        "{}: key 'protocol.segment': the protocol is empty; give at least one [[protocol.segment]] "
        "(kind = \"ramp\" with from, to, rate, window; or kind = \"steps\" with from, to, num, settle, measure)",
        file));
  r.reject_unknown();
  std::vector<sweep::Segment> out;
  each_table(*arr, "protocol.segment", file, [&](Reader& s) {
    const std::string kind = s.word("kind", "", {"ramp", "steps"});
    if (kind.empty()) s.fail("kind", "missing; allowed: ramp, steps");
    for (const char* k : {"from", "to"})
      if (!s.has(k)) s.fail(k, "missing (ω_m at the start and end [rad/s])");
    sweep::Segment seg{};
    if (kind == "ramp") {
      seg.kind = sweep::Segment::Kind::Ramp;
      seg.ramp.from = s.number("from", 0.0, 0.0, kOmegaMax);
      seg.ramp.to = s.number("to", 0.0, 0.0, kOmegaMax);
      if (seg.ramp.from == seg.ramp.to) s.fail("to", "a ramp needs to != from");
      if (!s.has("rate")) s.fail("rate", "missing (|dω_m/dt| [rad/s²])");
      seg.ramp.rate = s.number("rate", 0.0, 0.0, 1e4, true);
      seg.ramp.window = s.number("window", 5.0, 0.0, 1e6, true);
    } else {
      seg.kind = sweep::Segment::Kind::Steps;
      seg.steps.from = s.number("from", 0.0, 0.0, kOmegaMax);
      seg.steps.to = s.number("to", 0.0, 0.0, kOmegaMax);
      if (!s.has("num")) s.fail("num", "missing (number of levels, >= 1)");
      seg.steps.num = int(s.count("num", 1, 1.0, 1e5));
      if (!s.has("measure")) s.fail("measure", "missing (measured hold at each level [s])");
      seg.steps.settle = s.number("settle", 0.0, 0.0, 1e6);
      seg.steps.measure = s.number("measure", 0.0, 0.0, 1e6, true);
      seg.steps.step_rate = s.number("step_rate", 1.0, 0.0, 1e4, true);
    }
    out.push_back(seg);
  });
  return out;
}

// [bisect] (instead of [protocol] or [hold]): one threshold per grid point by bisection on held
// levels (sweep/bisection.hpp). Every bound is checked here, before any work.
sweep::BisectSpec parse_bisect(const toml::table& root, std::string_view file, SweepConfig& c) {
  for (const char* other : {"protocol", "hold"})
    if (root.contains(other))
      throw ConfigError(fmt::format("{}: key 'bisect': a sweep has one of [protocol], [hold] or [bisect]; this one "
                                    "also has [{}]", file, other));
  const toml::table& bt = subtable(root, "bisect", file);
  Reader r(bt, "bisect", file);
  sweep::BisectSpec b;
  const std::string t = r.word("threshold", "", {"omega_rise", "omega_fall", "omega_1", "omega_2"});
  if (t.empty()) r.fail("threshold", "missing; allowed: omega_rise, omega_fall, omega_1, omega_2");
  for (sweep::Threshold th : sweep::kThresholds)
    if (sweep::to_string(th) == t) b.threshold = th;
  b.start_seed = r.word("start_seed", b.threshold == sweep::Threshold::Rise ? "hanging" : "circular_high",
                        {"hanging", "circular_high", "locked_orbit"});
  b.start_omega = r.number("start_omega", 0.0, 0.0, kOmegaMax);
  for (const char* k : {"from", "to", "width"})
    if (!r.has(k)) r.fail(k, "missing (from: a level on the threshold's known side, to: the far end, width: the "
                             "bracket's final width, all in rad/s)");
  b.from = r.number("from", 0.0, 0.0, kOmegaMax);
  b.to = r.number("to", 0.0, 0.0, kOmegaMax);
  const int dir = sweep::bisect_direction(b.threshold);
  if ((b.to - b.from) * dir <= 0.0)
    r.fail("to", fmt::format("{} is not {} than from = {}: {} is found with {} ω_m; allowed: to {} from", b.to,
                             dir > 0 ? "larger" : "smaller", b.from, t, dir > 0 ? "rising" : "falling", dir > 0 ? ">" : "<"));
  b.width = r.number("width", 0.0, 0.0, kOmegaMax, true);
  b.settle = r.number("settle", b.settle, 0.0, 1e6);
  b.measure = r.number("measure", b.measure, 0.0, 1e6, true);
  b.step_rate = r.number("step_rate", b.step_rate, 0.0, 1e4, true);
  c.sample_rate = r.number("sample_rate", 100.0, 0.0, 1e5, true);
  b.decide_early = r.boolean("decide_early", b.decide_early);
  if (r.word("guide", "middle", {"middle", "held_orbit"}) == "held_orbit") {
    if (b.threshold != sweep::Threshold::Fall && b.threshold != sweep::Threshold::Omega1)
      r.fail("guide", fmt::format("held_orbit predicts the end of a locked orbit, not {}; allowed: middle, or "
                                  "held_orbit with threshold omega_fall or omega_1", t));
    b.guide = sweep::BisectSpec::Guide::HeldOrbit;
  }
  r.reject_unknown();
  const double range = std::abs(b.to - b.from), w_min = sweep::min_width(b);
  if (b.width >= range)
    r.fail("width", fmt::format("{} rad/s is not below |to - from| = {} rad/s: nothing to bisect; allowed ({}, {})",
                                b.width, range, w_min, range));
  if (b.width < w_min)
    r.fail("width", fmt::format("{} rad/s ({:.4f}π) is below what a window of measure = {} s resolves; allowed at "
                                "least 2π/(4·measure) = {:.6g} rad/s ({:.4f}π): widen the bracket or lengthen "
                                "bisect.measure", b.width, b.width / std::numbers::pi, b.measure, w_min,
                                w_min / std::numbers::pi));
  c.windows_per_task = 1;
  c.start_seed = b.start_seed;
  c.start_omega = b.start_omega;
  return b;
}

// A map's grid (a [bisect] part): every axis a model parameter with at least two values.
void check_map_grid(const SweepConfig& c) {
  for (const sweep::GridAxis& a : c.grid) {
    if (a.key == sweep::kRampRateAxis)
      throw ConfigError(fmt::format("{}: key 'grid.{}': a bisection holds levels and has no ramps; allowed: a model "
                                    "parameter", c.source_name, a.key));
    if (a.values.size() < 2)
      throw ConfigError(fmt::format("{}: key 'grid.{}': a map's axis needs at least 2 values, it has {}; allowed: 2 "
                                    "or more values (or leave the axis out and set the parameter in [model])",
                                    c.source_name, a.key, a.values.size()));
  }
}

}  // namespace

namespace {

// The chains of a sweep (or of one part of a grouped one): the grid's points, times (hold) the
// held ω_m, seeds and perturbations; `factors` (if given) says where they come from.
double chain_count(const SweepConfig& c, std::vector<std::string>* factors = nullptr) {
  double chains = 1.0;
  for (const auto& axis : c.grid) {
    chains *= double(axis.values.size());
    if (factors) factors->push_back(fmt::format("grid.{}: {}", axis.key, axis.values.size()));
  }
  if (c.hold) {
    chains *= double(c.hold->omega.size()) * double(c.hold->seeds.size()) * double(c.hold->perturbations + 1);
    if (factors)
      factors->push_back(fmt::format("hold.omega: {}, hold.seeds: {}, hold.perturbations + 1: {}", c.hold->omega.size(),
                                     c.hold->seeds.size(), c.hold->perturbations + 1));
  }
  if (c.basin) {
    chains *= double(c.basin->omega.size()) * double(c.basin->samples);
    if (factors) factors->push_back(fmt::format("basin.omega: {}, basin.samples: {}", c.basin->omega.size(), c.basin->samples));
  }
  return chains;
}

// At most kMaxChains in one part and in all parts together (`before`: the chains of the parts
// read before this one).
void check_chain_count(const SweepConfig& c, double before) {
  std::vector<std::string> factors;
  const double chains = chain_count(c, &factors);
  const std::string_view key = !c.grid.empty() ? "grid" : c.basin ? "basin" : "hold";
  if (chains > double(kMaxChains))
    throw ConfigError(fmt::format("{}: key '{}': the sweep has {:.0f} chains ({}); allowed at most {}", c.source_name,
                                  key, chains, fmt::join(factors, ", "), kMaxChains));
  if (before + chains > double(kMaxChains))
    throw ConfigError(fmt::format("{}: key '{}': the sweep's parts have {:.0f} chains in total ({:.0f} in the parts "
                                  "before this one, {:.0f} in this one: {}); allowed at most {} in total",
                                  c.source_name, key, before + chains, before, chains, fmt::join(factors, ", "),
                                  kMaxChains));
}


StoredOrbitReader stored_orbit_reader = nullptr;  // set once by the application, before any configuration is read

// basin.state = {file, chain, window}: the end of that window of a sweep file, read through the
// registered reader (results/ reads sweep files, config does not), of the same string and drive
// radius as this model.
sweep::StoredOrbit read_stored_orbit(const toml::table& bt, const physics::Model& m, std::string_view file) {
  const toml::table* st = bt.get("state")->as_table();
  if (!st)
    throw ConfigError(fmt::format("{}: key 'basin.state': expected {{file = \"out/paper.h5\", chain = C, window = K}}: "
                                  "a window of a sweep file", file));
  Reader r(*st, "basin.state", file);
  if (!r.has("file")) r.fail("file", "missing: the sweep file the state is read from");
  const std::string path = r.text("file", "");
  if (!r.has("chain")) r.fail("chain", "missing: the chain's index in that file (0, 1, ...)");
  if (!r.has("window")) r.fail("window", "missing: the window's index in its chain (0, 1, ...)");
  const long chain = long(r.count("chain", 0, 0.0, 1e9)), window = long(r.count("window", 0, 0.0, 1e9));
  r.reject_unknown();
  if (!stored_orbit_reader) r.fail("file", "this command cannot read sweep files");
  sweep::StoredOrbit o;
  try {
    o = stored_orbit_reader(path, chain, window);
  } catch (const std::exception& e) {
    throw ConfigError(fmt::format("{}: key 'basin.state': {}", file, e.what()));
  }
  const double l = m.p.string_length, R = m.p.drive_radius;
  if (std::abs(o.string_length - l) > 1e-12 * l || std::abs(o.drive_radius - R) > 1e-12 * R)
    throw ConfigError(fmt::format("{}: key 'basin.state': chain {} of {} has l = {} m, R = {} m; this model has l = {} m, "
                                  "R = {} m; allowed: a state of the same string and drive radius",
                                  file, chain, path, o.string_length, o.drive_radius, l, R));
  return o;
}

// [basin] (sweep/basin.hpp): the levels, N starts per level and their family, checked against
// the model's bounds before any work.
sweep::BasinSpec read_basin(const toml::table& root, SweepConfig& c) {
  const std::string_view file = c.source_name;
  const toml::table& bt = subtable(root, "basin", file);
  Reader r(bt, "basin", file);
  sweep::BasinSpec b;
  if (!r.has("omega")) r.fail("omega", "missing: the ω_m levels [rad/s], a list or {start, stop, num}");
  r.known("omega");
  b.omega = value_list(*bt.get("omega"), "basin.omega", file);
  for (std::size_t i = 0; i < b.omega.size(); ++i)
    if (!(b.omega[i] >= 0.0 && b.omega[i] <= kOmegaMax))
      throw ConfigError(fmt::format("{}: key 'basin.omega[{}]': {} is out of range; allowed [0, {}]", file, i,
                                    b.omega[i], kOmegaMax));
  if (!r.has("samples")) r.fail("samples", "missing: the starts drawn at each level (N >= 1)");
  b.samples = int(r.count("samples", b.samples, 1.0, 100000.0));
  const std::string family = r.word("family", "", {"hanging", "hand", "cloud"});
  if (family.empty()) r.fail("family", "missing; allowed: hanging, hand, cloud");
  b.family = *sweep::parse_basin_family(family);
  b.seed = std::uint64_t(r.count("seed", 1, 0.0, 9007199254740992.0));
  b.settle = r.number("settle", b.settle, 0.0, 1e6);
  b.measure = r.number("measure", b.measure, 0.0, 1e6, true);
  r.known("match_tolerance");  // retired: files made before 2026-11-28 carry it; ignored
  // Retired with a change of physics, so refused rather than ignored: the hand of before (the top
  // on the motor's circle at a random piecewise linear ω_m, hand_omega, hand_knots) is not the
  // free top of today.
  for (const char* k : {"hand_omega", "hand_knots"})
    if (r.has(k))
      r.fail(k, "retired on 2026-11-28: the hand now moves the top freely in the horizontal plane; give "
                "hand_amplitude, hand_duration and hand_modes instead (guide: basin sweeps)");
  const auto only = [&](const char* key, sweep::BasinFamily f) {
    if (r.has(key) && b.family != f) r.fail(key, fmt::format("belongs to family = \"{}\", not \"{}\"", sweep::to_string(f), family));
  };
  only("s", sweep::BasinFamily::Hanging);
  only("swing", sweep::BasinFamily::Hanging);
  for (const char* k : {"hand_amplitude", "hand_duration", "hand_modes", "step_rate"}) only(k, sweep::BasinFamily::Hand);
  for (const char* k : {"orbit", "epsilon", "state"}) only(k, sweep::BasinFamily::Cloud);
  if (const toml::node* n = bt.get("s")) {
    r.known("s");
    const toml::array* a = n->as_array();
    const auto lo = a && a->size() == 2 ? (*a)[0].value<double>() : std::nullopt;
    const auto hi = a && a->size() == 2 ? (*a)[1].value<double>() : std::nullopt;
    if (!lo || !hi || !std::isfinite(*lo) || !std::isfinite(*hi) || *lo > *hi)
      r.fail("s", "expected [lo, hi] with lo <= hi, the bead's positions along the string [m]");
    b.s_lo = *lo;
    b.s_hi = *hi;
  }
  b.swing = r.number("swing", b.swing, 0.0, 1.5707963267948966);
  b.hand_amplitude = r.number("hand_amplitude", b.hand_amplitude, 0.0, 10.0, true);
  b.hand_duration = r.number("hand_duration", b.hand_duration, 0.0, 600.0, true);
  b.hand_modes = int(r.count("hand_modes", b.hand_modes, 1.0, 20.0));
  b.step_rate = r.number("step_rate", b.step_rate, 0.0, 1e4, true);
  b.orbit = r.word("orbit", b.orbit, {"locked_orbit", "circular_high"});
  b.epsilon = r.number("epsilon", b.epsilon, 0.0, 1.0, true);
  if (bt.contains("state")) {
    if (r.has("orbit")) r.fail("state", "a cloud surrounds either `orbit` or a stored `state`, not both");
    r.known("state");
    b.stored = read_stored_orbit(bt, c.model, file);
  }
  c.sample_rate = r.number("sample_rate", 100.0, 0.0, 1e5, true);
  r.reject_unknown();
  try {
    sweep::check_basin(c.model, b, file);
  } catch (const sweep::BasinError& e) {
    throw ConfigError(e.what());
  }
  if (b.family == sweep::BasinFamily::Cloud)  // the orbit at every level, before any work
    for (std::size_t i = 0; i < b.omega.size(); ++i) try {
        const sweep::CompiledProtocol p = sweep::basin_protocol(b, b.omega[i], int(i), 0);
        (void)sweep::basin_orbit(c.model, physics::MotorSchedule(c.model.p.drive_radius, p.schedule), b, b.omega[i]);
      } catch (const sweep::BasinError& e) {
        throw ConfigError(fmt::format("{}: key 'basin.{}': at basin.omega[{}] = {} rad/s: {}; allowed: a level "
                                      "where the orbit exists, or orbit = \"circular_high\"", file,
                                      b.stored ? "state" : "orbit", i, b.omega[i], e.what()));
      }
  c.windows_per_task = 1;
  return b;
}

// The tables of one sweep (a plain file, or one part of a grouped one) after [model],
// [layers], [integrator] and [initial]: [protocol] or [hold], [grid], [output].
// `chains_before`: the chains of the parts of a grouped sweep read before this one.
void read_sweep_tables(const toml::table& root, SweepConfig& c, double chains_before = 0.0) {
  const std::string_view file = c.source_name;
  if (root.contains("basin")) {
    for (const char* other : {"protocol", "hold", "bisect"})
      if (root.contains(other))
        throw ConfigError(fmt::format("{}: key 'basin': a sweep has one of [protocol], [hold], [bisect] and [basin], not {} beside it",
                                      file, other));
    c.basin = read_basin(root, c);
  } else if (root.contains("hold")) {
    if (root.contains("protocol"))
      throw ConfigError(fmt::format("{}: key 'hold': a sweep has either [protocol] (ramps) or [hold], not both", file));
    const toml::table& ht = subtable(root, "hold", file);
    Reader r(ht, "hold", file);
    sweep::HoldSpec h;
    if (!r.has("omega")) r.fail("omega", "missing: the held ω_m values [rad/s], a list or {start, stop, num}");
    r.known("omega");
    h.omega = value_list(*ht.get("omega"), "hold.omega", file);
    for (std::size_t i = 0; i < h.omega.size(); ++i)
      if (!(h.omega[i] >= 0.0 && h.omega[i] <= kOmegaMax))
        throw ConfigError(fmt::format("{}: key 'hold.omega[{}]': {} is out of range; allowed [0, {}]", file, i,
                                      h.omega[i], kOmegaMax));
    h.settle = r.number("settle", h.settle, 0.0, 1e6);
    h.measure = r.number("measure", h.measure, 0.0, 1e6, true);
    if (const toml::array* seeds = ht.get_as<toml::array>("seeds")) {
      r.known("seeds");
      h.seeds.clear();
      for (std::size_t i = 0; i < seeds->size(); ++i) {
        const auto v = (*seeds)[i].value<std::string>();
        if (!v || (*v != "hanging" && *v != "circular_high" && *v != "locked_orbit"))
          throw ConfigError(fmt::format("{}: key 'hold.seeds[{}]': allowed: hanging, circular_high, locked_orbit", file, i));
        h.seeds.push_back(*v);
      }
      if (h.seeds.empty()) r.fail("seeds", "the list is empty; allowed: hanging, circular_high, locked_orbit");
    } else if (ht.contains("seeds")) {
      r.fail("seeds", "expected an array of names (hanging, circular_high, locked_orbit)");
    }
    h.perturbations = int(r.count("perturbations", 0, 0.0, 1000.0));
    h.perturbation = r.number("perturbation", h.perturbation, 0.0, 10.0, true);
    c.sample_rate = r.number("sample_rate", 100.0, 0.0, 1e5, true);
    read_early_stop(r, c);
    r.reject_unknown();
    c.windows_per_task = 1;
    c.hold = h;
  } else if (root.contains("bisect")) {
    c.bisect = parse_bisect(root, file, c);
  } else {
    c.protocol = parse_protocol(root, file, c);
  }
  for (const auto& [k, v] : subtable(root, "grid", file)) {
    const std::string key(k.str());
    if (!sweep::is_grid_axis(key)) {
      throw ConfigError(fmt::format("{}: key 'grid.{}': unknown key; allowed: {}", file, key,
                                    fmt::join(sweep::grid_axis_keys(), ", ")));
    }
    if (const KeyInfo* doc = find_key("grid", key)) note_read(*doc);
    c.grid.push_back({key, value_list(v, "grid." + key, file)});
  }
  {
    Reader r(subtable(root, "output", file), "output", file);
    c.output_path = r.text("path", c.output_path);
    r.reject_unknown();
  }
  if (c.bisect) check_map_grid(c);
  check_chain_count(c, chains_before);  // before the grid is expanded: a sweep too large to hold is refused, not run out of memory
  try {
    sweep::expand_grid(c.model, c, file);  // every grid point is checked before any work
  } catch (const sweep::GridError& e) {
    throw ConfigError(e.what());
  }
  if (c.hold || c.basin || c.bisect) return;
  try {
    sweep::compile(c.protocol, c.start_omega);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(fmt::format("{}: key 'protocol': {}", file, e.what()));
  }
}


const std::set<std::string> kSweepTables{"model", "layers", "integrator", "initial", "protocol", "grid", "hold", "basin", "bisect", "output"};
// The tables a variant or a group may set over the file's.
const std::set<std::string> kVariantTables{"model", "layers", "integrator", "initial"};
const std::set<std::string> kGroupTables{"model", "layers", "integrator", "initial", "protocol", "hold", "basin", "bisect", "grid"};

// src's keys over dst's, table by table; anything else (numbers, arrays such as the segments
// of a protocol or a grid axis) replaces what dst had.
void merge_into(toml::table& dst, const toml::table& src) {
  for (const auto& [k, v] : src) {
    toml::table* d = dst.get_as<toml::table>(k.str());
    if (d && v.is_table())
      merge_into(*d, *v.as_table());
    else
      dst.insert_or_assign(k.str(), v);
  }
}

// A name of a group or a variant: it labels chains in files, tables and figures.
void check_name(const std::string& name, const std::string& key, std::string_view file) {
  const bool ok = !name.empty() && name.size() <= 40 &&
                  std::all_of(name.begin(), name.end(), [](char ch) { return std::isalnum((unsigned char)ch) || ch == '_' || ch == '-'; });
  if (!ok)
    throw ConfigError(fmt::format("{}: key '{}': '{}' is not a name; allowed: 1 to 40 letters, digits, '_' or '-'",
                                  file, key, printable(name)));
}

struct VariantSpec {
  std::string name, label;
  toml::table tables;  // its model, layers, integrator, initial
};
struct GroupSpec {
  std::string name, purpose;
  std::vector<std::string> variants;
  toml::table tables;  // its model, layers, integrator, initial, protocol or hold, grid
};

// A key of a variant or a group that is neither one of its own (`own`) nor a table it may set:
// refused naming the nearest of both, as a mistyped key of [model] is.
void reject_unknown_part_keys(Reader& r, const std::set<std::string>& own, const std::set<std::string>& tables) {
  std::set<std::string> allowed = own;
  allowed.insert(tables.begin(), tables.end());
  for (const auto& [k, v] : r.table())
    if (!allowed.count(std::string(k.str()))) {
      const std::string near = closest(k.str(), allowed);
      r.fail(k.str(), fmt::format("unknown key{}; allowed: {}", near.empty() ? "" : " (did you mean '" + near + "'?)",
                                  fmt::join(allowed, ", ")));
    }
}

// [variant.NAME] tables: label and the tables they set. None: one unnamed variant.
std::vector<VariantSpec> read_variants(const toml::table& root, std::string_view file) {
  std::vector<VariantSpec> out;
  const toml::node* n = root.get("variant");
  if (!n) return {VariantSpec{}};
  if (!n->is_table()) throw ConfigError(fmt::format("{}: key 'variant': expected tables [variant.NAME]", file));
  for (const auto& [k, v] : *n->as_table()) {
    const std::string key = fmt::format("variant.{}", k.str());
    VariantSpec spec{std::string(k.str()), "", {}};
    check_name(spec.name, key, file);
    const toml::table* t = v.as_table();
    if (!t) throw ConfigError(fmt::format("{}: key '{}': expected a table", file, key));
    Reader r(*t, key, file);
    spec.label = r.text("label", "");
    if (spec.label.empty()) r.fail("label", "missing: say what the variant is, e.g. \"the paper's physics (rigid tie)\"");
    if (const auto cp = control_character(spec.label))
      r.fail("label", fmt::format("control character {} not allowed (a label is one line of text; TAB is allowed)",
                                  code_point_name(*cp)));
    for (const auto& [tk, tv] : *t) {
      if (!kVariantTables.count(std::string(tk.str()))) continue;
      if (!tv.is_table()) r.fail(tk.str(), "expected a table");
      r.known(tk.str());
      spec.tables.insert(tk.str(), tv);
    }
    reject_unknown_part_keys(r, {"label"}, kVariantTables);
    r.reject_unknown();
    out.push_back(std::move(spec));
  }
  if (out.empty()) throw ConfigError(fmt::format("{}: key 'variant': no [variant.NAME] table", file));
  // In the order the file gives them (a TOML table's keys come sorted).
  const toml::table& vt = *n->as_table();
  // A variant defined by --set has no line: after the file's.
  const auto line = [&](const VariantSpec& v) {
    const auto l = vt.get(v.name)->source().begin.line;
    return l == 0 ? std::numeric_limits<decltype(l)>::max() : l;
  };
  std::stable_sort(out.begin(), out.end(), [&](const VariantSpec& a, const VariantSpec& b) { return line(a) < line(b); });
  return out;
}

// [[group]] tables. None: one unnamed group of the file's own tables, run for every variant.
std::vector<GroupSpec> read_groups(const toml::table& root, const std::vector<VariantSpec>& variants,
                                   std::string_view file) {
  std::vector<std::string> all;
  for (const VariantSpec& v : variants) all.push_back(v.name);
  const toml::node* n = root.get("group");
  if (!n) return {GroupSpec{"", "", all, {}}};
  const toml::array* arr = n->as_array();
  if (!arr || arr->empty())
    throw ConfigError(fmt::format("{}: key 'group': expected one or more [[group]] tables", file));
  std::vector<GroupSpec> out;
  each_table(*arr, "group", file, [&](Reader& r) {
    GroupSpec g;
    const std::string prefix = fmt::format("group[{}]", out.size());
    g.name = r.text("name", "");
    if (g.name.empty()) r.fail("name", "missing: a short name for the group's chains");
    check_name(g.name, prefix + ".name", file);
    for (const GroupSpec& o : out)
      if (o.name == g.name) r.fail("name", fmt::format("'{}' names two groups; allowed: a name used once", g.name));
    g.purpose = r.text("purpose", "");
    if (g.purpose.empty()) r.fail("purpose", "missing: say why these chains are there");
    if (const auto cp = control_character(g.purpose))
      r.fail("purpose", fmt::format("control character {} not allowed (a purpose is one line of text; TAB is allowed)",
                                    code_point_name(*cp)));
    g.variants = all;
    if (r.has("variants")) {
      r.known("variants");
      const toml::array* va = r.table().get_as<toml::array>("variants");
      if (!va || va->empty()) r.fail("variants", fmt::format("expected a list of variant names from: {}", fmt::join(all, ", ")));
      g.variants.clear();
      for (std::size_t i = 0; i < va->size(); ++i) {
        const auto name = (*va)[i].value<std::string>();
        if (!name || std::find(all.begin(), all.end(), *name) == all.end() ||
            std::find(g.variants.begin(), g.variants.end(), *name) != g.variants.end())
          throw ConfigError(fmt::format("{}: key '{}.variants[{}]': expected a variant name used once; allowed: {}",
                                        file, prefix, i, fmt::join(all, ", ")));
        g.variants.push_back(*name);
      }
    }
    for (const auto& [tk, tv] : r.table()) {
      if (!kGroupTables.count(std::string(tk.str()))) continue;
      if (!tv.is_table()) r.fail(tk.str(), "expected a table");
      r.known(tk.str());
      g.tables.insert(tk.str(), tv);
    }
    reject_unknown_part_keys(r, {"name", "purpose", "variants"}, kGroupTables);
    if (g.tables.contains("protocol") && g.tables.contains("hold"))
      r.fail("hold", "a group has either [group.protocol] (ramps, steps) or [group.hold], not both");
    if (g.tables.contains("basin") && (g.tables.contains("protocol") || g.tables.contains("hold")))
      r.fail("basin", "a group has one of [group.protocol], [group.hold] and [group.basin]");
    if (g.tables.contains("bisect") && (g.tables.contains("protocol") || g.tables.contains("hold")))
      r.fail("bisect", "a group has one of [group.protocol], [group.hold] or [group.bisect]");
    out.push_back(std::move(g));
  });
  return out;
}

// The root of one part: the file's tables, the variant's and the group's merged over them.
toml::table part_root(const toml::table& base, const VariantSpec& v, const GroupSpec& g) {
  toml::table root = base;
  merge_into(root, v.tables);
  // A group's [hold] replaces the file's [protocol] and the other way round.
  if (g.tables.contains("hold")) root.erase("protocol");
  if (g.tables.contains("protocol")) root.erase("hold");
  if (g.tables.contains("basin")) root.erase("protocol"), root.erase("hold");
  if (g.tables.contains("protocol") || g.tables.contains("hold")) root.erase("basin");
  // And a group's [bisect] replaces both, as either replaces the file's [bisect].
  if (g.tables.contains("bisect")) root.erase("protocol"), root.erase("hold");
  if (g.tables.contains("protocol") || g.tables.contains("hold")) root.erase("bisect");
  if (g.tables.contains("basin")) root.erase("bisect");
  if (g.tables.contains("bisect")) root.erase("basin");
  merge_into(root, g.tables);
  return root;
}

// --set variant.NAME.KEY=VALUE: NAME must be a variant of the file, or one the same command
// defines completely (gives its label, --set variant.NAME.label=...); a mistyped name would
// otherwise make a new variant of the file's tables and run it beside the others.
void check_variant_overrides(const toml::table& root, const std::vector<std::string>& overrides, std::string_view file) {
  const toml::table* variants = root.get_as<toml::table>("variant");
  std::vector<std::string> names;
  if (variants) {
    for (const auto& [k, v] : *variants) names.emplace_back(k.str());
    std::stable_sort(names.begin(), names.end(), [&](const std::string& a, const std::string& b) {
      return variants->get(a)->source().begin.line < variants->get(b)->source().begin.line;  // the file's order
    });
  }
  for (const std::string& o : overrides) {
    if (o.rfind("variant.", 0) != 0) continue;
    const std::string key = o.substr(0, o.find('='));
    const std::string name = key.substr(8, key.find('.', 8) == std::string::npos ? std::string::npos : key.find('.', 8) - 8);
    if (std::find(names.begin(), names.end(), name) != names.end()) continue;
    const std::string label = "variant." + name + ".label=";
    if (std::any_of(overrides.begin(), overrides.end(), [&](const std::string& x) { return x.rfind(label, 0) == 0; }))
      continue;
    const std::string near = closest(name, names);
    throw ConfigError(fmt::format(
        "{}: key 'variant.{}': no such variant{}; allowed: {}, or a new variant defined completely by the same "
        "command (--set variant.{}.label=\"what it is\" and the tables it changes)",
        file, name, near.empty() ? "" : " (did you mean '" + near + "'?)",
        names.empty() ? std::string("(the file has no [variant.NAME] tables)") : fmt::format("{}", fmt::join(names, ", ")),
        name));
  }
}

SweepConfig parse_grouped_sweep(toml::table root, std::string_view text, std::string_view source_name,
                                const std::vector<std::string>& overrides) {
  SweepConfig top;
  top.source_name = source_name;
  top.source_text = text;
  top.overrides = overrides;
  const std::string_view file = top.source_name;
  // --set variant.NAME.KEY=VALUE sets a key of one variant; any other key is set in every part,
  // over what its variant and group say.
  check_variant_overrides(root, overrides, file);
  std::vector<std::string> part_overrides;
  for (const std::string& o : overrides)
    if (o.rfind("variant.", 0) == 0)
      apply_override(root, o, file);
    else
      part_overrides.push_back(o);
  std::set<std::string> known = kSweepTables;
  known.insert({"variant", "group"});
  reject_unknown_tables(root, known, file);
  {  // the other overrides' tables, refused as in a plain sweep before any part is read
    toml::table set;
    for (const std::string& o : part_overrides) apply_override(set, o, file);
    reject_unknown_tables(set, kSweepTables, file);
  }
  const std::vector<VariantSpec> variants = read_variants(root, file);
  const std::vector<GroupSpec> groups = read_groups(root, variants, file);
  toml::table base = root;
  base.erase("variant");
  base.erase("group");
  double chains = 0.0;  // in the parts read so far
  for (std::size_t gi = 0; gi < groups.size(); ++gi)
    for (const std::string& vname : groups[gi].variants) {
      const VariantSpec& v = *std::find_if(variants.begin(), variants.end(), [&](const VariantSpec& x) { return x.name == vname; });
      const GroupSpec& g = groups[gi];
      toml::table proot = part_root(base, v, g);
      for (const std::string& o : part_overrides) apply_override(proot, o, file);
      SweepConfig part;
      part.source_name = fmt::format("{} (group{} '{}', variant '{}')", file, g.name.empty() ? "" : fmt::format("[{}]", gi),
                                     g.name, v.name);
      part.source_text = text;
      part.overrides = overrides;
      parse_common(proot, part.source_name, part);
      read_sweep_tables(proot, part, chains);
      chains += chain_count(part);
      part.group = g.name;
      part.group_purpose = g.purpose;
      part.variant = v.name;
      part.variant_label = v.label;
      top.parts.push_back(std::move(part));
    }
  // What the file shares: its output, the stored sample rate, the initial state.
  const SweepConfig& first = top.parts.front();
  for (const SweepConfig& p : top.parts)
    if (p.sample_rate != first.sample_rate)
      throw ConfigError(fmt::format("{}: key 'sample_rate': {} in {} but {} in {}; allowed: one sample rate for the "
                                    "whole file (set it in the file's [protocol])",
                                    file, p.sample_rate, p.source_name, first.sample_rate, first.source_name));
  top.model = first.model;
  top.run = first.run;
  top.initial = first.initial;
  top.sample_rate = first.sample_rate;
  top.output_path = first.output_path;
  return top;
}

}  // namespace

SweepConfig parse_sweep_config(std::string_view text, std::string_view source_name,
                               const std::vector<std::string>& overrides) {
  {
    toml::table raw = parse_text(text, source_name);
    if (raw.contains("group") || raw.contains("variant"))
      return parse_grouped_sweep(std::move(raw), text, source_name, overrides);
  }
  SweepConfig c;
  const toml::table root = begin(c, text, source_name, overrides, kSweepTables);
  read_sweep_tables(root, c);
  return c;
}

SweepConfig load_sweep_config(const std::string& path, const std::vector<std::string>& overrides) {
  return parse_sweep_config(read_file(path), path, overrides);
}

std::vector<sweep::PlanPart> plan_parts(const SweepConfig& c) {
  std::vector<sweep::PlanPart> out;
  if (c.parts.empty()) return {sweep::PlanPart{c.model, c.run, c, c.source_name}};
  for (const SweepConfig& part : c.parts) out.push_back({part.model, part.run, part, part.source_name});
  return out;
}


OrbitsConfig parse_orbits_config(std::string_view text, std::string_view source_name,
                                 const std::vector<std::string>& overrides) {
  OrbitsConfig c;
  const toml::table root = begin(c, text, source_name, overrides,
                                 {"model", "layers", "integrator", "initial", "schedule", "output", "protocol",
                                  "grid", "hold", "bisect", "orbits"});
  const std::string file = c.source_name;
  const physics::Parameters& p = c.model.p;
  if (const toml::table* t = root.get_as<toml::table>("orbits")) {
    Reader r(*t, "orbits", file);
    if (const toml::node* n = t->get("omega")) {
      r.known("omega");
      c.orbits.omega = n->is_number() ? std::vector<double>{n->value<double>().value()} : value_list(*n, "orbits.omega", file);
      for (std::size_t i = 0; i < c.orbits.omega.size(); ++i)
        if (!(c.orbits.omega[i] > 0.0 && c.orbits.omega[i] <= 2000.0))
          throw ConfigError(fmt::format("{}: key 'orbits.omega[{}]': {} is out of range; allowed (0, 2000] rad/s", file,
                                        i, c.orbits.omega[i]));
    }
    c.orbits.s_points = int(r.count("s_points", c.orbits.s_points, 2, 10000));
    c.orbits.parameter = r.word("continue", "", orbits::continuation_parameters());
    if (const toml::array* a = t->get_as<toml::array>("range")) {
      r.known("range");
      const auto lo = a->size() == 2 ? (*a)[0].value<double>() : std::nullopt;
      const auto hi = a->size() == 2 ? (*a)[1].value<double>() : std::nullopt;
      if (!lo || !hi || !std::isfinite(*lo) || !std::isfinite(*hi) || !(*lo < *hi))
        r.fail("range", "expected [lo, hi] with lo < hi");
      c.orbits.range_lo = *lo;
      c.orbits.range_hi = *hi;
    } else if (t->contains("range")) {
      r.fail("range", "expected [lo, hi] with lo < hi");
    }
    if (const toml::node* n = t->get("s")) {
      r.known("s");
      c.orbits.s = n->is_number() ? std::vector<double>{n->value<double>().value()} : value_list(*n, "orbits.s", file);
      const double lo = c.model.layers.top_stop ? p.top_stop : 0.0;
      const double hi = c.model.layers.bottom_stop ? p.string_length - p.contact_distance : p.string_length;
      for (std::size_t i = 0; i < c.orbits.s.size(); ++i)
        if (!(c.orbits.s[i] > lo && c.orbits.s[i] <= hi))
          throw ConfigError(fmt::format("{}: key 'orbits.s[{}]': {} is out of range; allowed ({}, {}] m (the stops)",
                                        file, i, c.orbits.s[i], lo, hi));
    }
    r.reject_unknown();
  }
  return c;
}

OrbitsConfig load_orbits_config(const std::string& path, const std::vector<std::string>& overrides) {
  return parse_orbits_config(read_file(path), path, overrides);
}

void set_stored_orbit_reader(StoredOrbitReader reader) { stored_orbit_reader = reader; }

}  // namespace ajx::config
