#include "config/key_catalogue.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <limits>

#include "numerics/stepper.hpp"
#include "orbits/continuation.hpp"
#include "physics/parameter_table.hpp"
#include "sim/table1_starts.hpp"
#include "sweep/orbit_classifier.hpp"

namespace ajx::config {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kOmegaMax = 2000.0;  // as the reader's bound on every ω_m [rad/s]

std::string number_text(double v) { return std::isinf(v) ? "∞" : fmt::format("{}", v); }
std::string range_text(double lo, double hi, bool lo_open, bool hi_open) {
  return fmt::format("{}{}, {}{}", lo_open ? "(" : "[", number_text(lo), number_text(hi), hi_open ? ")" : "]");
}

// A number with a fixed range.
KeyInfo num(std::string section, std::string key, std::string unit, double lo, double hi, bool lo_open, bool hi_open,
            std::string fallback, std::string doc, std::string type = "number") {
  KeyInfo k{std::move(section), std::move(key), std::move(type), std::move(unit), range_text(lo, hi, lo_open, hi_open),
            std::move(fallback), std::move(doc)};
  k.lo = lo, k.hi = hi, k.lo_open = lo_open, k.hi_open = hi_open;
  return k;
}
// A whole number (the reader's count(): closed range).
KeyInfo whole(std::string section, std::string key, double lo, double hi, std::string fallback, std::string doc) {
  return num(std::move(section), std::move(key), "", lo, hi, false, false, std::move(fallback), std::move(doc),
             "whole number");
}
// Anything else: its allowed values in words.
KeyInfo other(std::string section, std::string key, std::string type, std::string unit, std::string allowed,
              std::string fallback, std::string doc) {
  return {std::move(section), std::move(key), std::move(type), std::move(unit), std::move(allowed),
          std::move(fallback), std::move(doc)};
}

std::string joined(const std::vector<std::string>& words) { return fmt::format("{}", fmt::join(words, ", ")); }

std::vector<std::string> integrator_methods() {
  std::vector<std::string> out;
  std::string names(numerics::stepper_names());
  for (std::size_t a = 0; a < names.size();) {
    std::size_t b = names.find(',', a);
    if (b == std::string::npos) b = names.size();
    std::string w = names.substr(a, b - a);
    w.erase(0, w.find_first_not_of(' '));
    out.push_back(w);
    a = b + 1;
  }
  out.insert(out.end(), {"paper", "paper_corrected"});
  return out;
}

std::vector<KeyInfo> physics_keys() {
  std::vector<KeyInfo> out;
  for (const physics::ParameterInfo& p : physics::kParameters) {
    KeyInfo k = num("model", std::string(p.key), std::string(p.unit), p.lo, p.hi, p.lo_open, p.hi_open,
                    fmt::format("{}", p.default_value()), fmt::format("{}: {}", p.symbol, p.doc));
    if (!p.depends.empty()) k.allowed += fmt::format(", {}", p.depends);
    out.push_back(std::move(k));
  }
  for (const physics::LayerInfo& l : physics::layer_table()) {
    using K = physics::LayerInfo::Kind;
    if (l.kind == K::Number)
      out.push_back(num("layers", std::string(l.key), std::string(l.unit), l.lo, l.hi, l.lo_open, false,
                        l.default_value(), std::string(l.doc)));
    else
      out.push_back(other("layers", std::string(l.key), l.kind == K::Word ? "word" : "boolean", "", l.range(),
                          l.default_value(), std::string(l.doc)));
  }
  return out;
}

// [integrator]
void integrator_keys(std::vector<KeyInfo>& k) {
  k.push_back(other("integrator", "method", "word", "", joined(integrator_methods()), "dop853",
                    "the integrator; paper and paper_corrected are the source paper's two-step scheme as printed "
                    "and with its drag's sign corrected"));
  k.push_back(num("integrator", "rtol", "", 1e-15, 1.0, false, true, "1e-10", "relative tolerance of the adaptive methods"));
  k.push_back(num("integrator", "atol", "", 0.0, 1.0, true, false, "1e-12", "absolute tolerance of the adaptive methods"));
  k.push_back(num("integrator", "step", "s", 0.0, 0.1, true, false, "0.0005",
                  "step of the fixed-step methods (euler, rk4, radau_iia, paper); the paper used 1/2000 s"));
  {
    KeyInfo m = num("integrator", "max_step", "s", 0.0, 10.0, true, false, "\"auto\"",
                    "\"auto\": each step bounded by h <= (k + 1)/Ω from the guards' rates (k = event_samples), so "
                    "that no guard crosses zero unseen inside a step; a number: a fixed bound instead, the guard "
                    "bound off");
    m.type = "number or \"auto\"";
    m.allowed = "\"auto\" or " + m.allowed;
    k.push_back(std::move(m));
  }
  k.push_back(whole("integrator", "event_samples", 0, 16, "3 with max_step = \"auto\", else 0",
                    "guard samples inside each step, on the step's cubic Hermite interpolant (confirmed on the dense "
                    "output where they show a sign change)"));
  k.push_back(other("integrator", "axes", "word", "", "rotating, lab, auto", "rotating",
                    "the axes integrated in: turning with the motor, the lab's, or chosen per run; input, output "
                    "and samples are in the lab axes either way; a clutch tie always uses lab"));
  k.push_back(num("integrator", "projection_tol", "m", 0.0, 1e-3, true, false, "1e-12",
                  "constraint drift |C| (or |J v − b| [m/s]) that triggers a projection onto the string"));
  k.push_back(whole("integrator", "max_events", 1, 1e12, "1000000", "bound on mode switches and impacts per run"));
  k.push_back(num("integrator", "omega_window", "s", 0.0, 1e7, true, false, "10",
                  "ω_ball of a run's summary is averaged over its last window of this length"));
  k.push_back(num("integrator", "rest_speed", "m/s", 0.0, 1.0, false, false, "0.001",
                  "re-taut impacts slower than this are plastic (ends Zeno bouncing)"));
  k.push_back(whole("integrator", "chatter_switches", 2, 1e6, "50", "this many mode switches ..."));
  k.push_back(num("integrator", "chatter_window", "s", 0.0, 1e3, true, false, "0.001",
                  "... within this time count as chattering (reported as a violation)"));
}

// [initial]
void initial_keys(std::vector<KeyInfo>& k) {
  k.push_back(other("initial", "preset", "word", "", "hanging, explicit, table1, pair", "hanging",
                    "the start: hanging (at rest on the bottom ball), explicit (r1, r2, v1, v2, mode), table1 "
                    "(a two-step start of the paper's Table 1) or pair (two positions, at t = 0 and t = step)"));
  k.push_back(other("initial", "orbit", "word", "", joined(sim::table1_orbits()), "circular1",
                    "preset = \"table1\": which of the paper's starts"));
  k.push_back(num("initial", "omega", "rad/s", 0.0, kOmegaMax, false, false, "ω_m(0)",
                  "preset = \"table1\": the circular starts' rate θ = ω h"));
  for (const char* v : {"r1", "r2"})
    k.push_back(other("initial", v, "3-vector", "m", "each component in [−10 l, 10 l]", "",
                      fmt::format("preset = \"explicit\" or \"pair\": position of the {} at t = 0",
                                  v[1] == '1' ? "bead" : "bottom ball")));
  for (const char* v : {"r1_next", "r2_next"})
    k.push_back(other("initial", v, "3-vector", "m", "each component in [−10 l, 10 l]", "",
                      fmt::format("preset = \"pair\": position of the {} at t = step",
                                  v[1] == '1' ? "bead" : "bottom ball")));
  for (const char* v : {"v1", "v2"})
    k.push_back(other("initial", v, "3-vector", "m/s", "each component in [−1000, 1000]", "[0, 0, 0]",
                      fmt::format("preset = \"explicit\": velocity of the {}", v[1] == '1' ? "bead" : "bottom ball")));
  k.push_back(other("initial", "mode", "word", "", "sliding, bottom_stop, stuck, slack", "sliding",
                    "preset = \"explicit\": the contact mode at t = 0"));
  k.push_back(other("initial", "length_tolerance", "number", "m", "(0, 0.1 l]", "1e-06",
                    "accepted |L1 + L2 − l| of an explicit start before it is projected onto the string"));
  k.push_back(num("initial", "tie_slip_rate", "rad/s", -1e4, 1e4, false, false, "held",
                  "with tie = \"clutch\" and preset = \"explicit\": the tie starts slipping at χ = φ(0) with this χ̇"));
}

// [[schedule]] (astrojax run)
void schedule_keys(std::vector<KeyInfo>& k) {
  k.push_back(other("schedule", "kind", "word", "", "hold, ramp", "", "a held ω_m, or a linear ramp of ω_m"));
  k.push_back(num("schedule", "omega", "rad/s", 0.0, kOmegaMax, false, false, "", "kind = \"hold\": ω_m held"));
  k.push_back(num("schedule", "duration", "s", 0.0, 1e7, true, false, "",
                  "length of the hold; for a ramp, instead of rate"));
  k.push_back(num("schedule", "from", "rad/s", 0.0, kOmegaMax, false, false, "", "kind = \"ramp\": ω_m at its start"));
  k.push_back(num("schedule", "to", "rad/s", 0.0, kOmegaMax, false, false, "", "kind = \"ramp\": ω_m at its end"));
  k.push_back(num("schedule", "rate", "rad/s^2", 0.0, 1e4, true, false, "", "kind = \"ramp\": |dω_m/dt|, instead of duration"));
}

// [output]
void output_keys(std::vector<KeyInfo>& k) {
  k.push_back(other("output", "path", "text", "", "a writable file path", "out/run.h5 (run), out/sweep.h5 (sweep)",
                    "the HDF5 file written; -o overrides it"));
  k.push_back(num("output", "sample_interval", "s", 0.0, 1e6, true, false, "0.01", "astrojax run: the sampling step"));
}

// [protocol] (astrojax sweep)
// The early stop's two keys, the same in [protocol] and [hold].
void early_stop_keys(std::vector<KeyInfo>& k, const char* section) {
  k.push_back(other(section, "early_stop", "boolean", "", "true, false", "true",
                    "each held level's settling ends once its orbit is known: converging to a fixed point or a periodic orbit of the frame turning with the top at a measured rate that has not slowed; false runs every settle in full"));
  k.push_back(num(section, "early_stop_tolerance", "1", 0.0, 0.01, true, false, "1e-4",
                  "ε: the settling ends when the distance left to the fixed point, or the drift over the periods skipped of a periodic orbit, is at most ε l"));
}

void protocol_keys(std::vector<KeyInfo>& k) {
  k.push_back(num("protocol", "start_omega", "rad/s", 0.0, kOmegaMax, false, false, "0", "ω_m at t = 0"));
  k.push_back(other("protocol", "start_seed", "word", "", "hanging, circular_high, locked_orbit", "hanging",
                    "the state at t = 0, a seed state at start_omega"));
  k.push_back(whole("protocol", "windows_per_task", 1, 1e6, "10", "windows per farm task (the unit of work and of resume)"));
  k.push_back(num("protocol", "sample_rate", "1/s", 0.0, 1e5, true, false, "100", "samples stored per second of every window"));
  early_stop_keys(k, "protocol");
  k.push_back(other("protocol", "segment", "array of tables", "", "at least one", "",
                    "the protocol's segments, [[protocol.segment]], run in order"));
  k.push_back(other("protocol.segment", "kind", "word", "", "ramp, steps", "",
                    "a ramp of ω_m measured in windows, or a staircase of held levels"));
  k.push_back(num("protocol.segment", "from", "rad/s", 0.0, kOmegaMax, false, false, "0", "ω_m at the segment's start"));
  k.push_back(num("protocol.segment", "to", "rad/s", 0.0, kOmegaMax, false, false, "0", "ω_m at the segment's end"));
  k.push_back(num("protocol.segment", "rate", "rad/s^2", 0.0, 1e4, true, false, "", "kind = \"ramp\": |dω_m/dt|"));
  k.push_back(num("protocol.segment", "window", "s", 0.0, 1e6, true, false, "5", "kind = \"ramp\": length of a classified window"));
  k.push_back(whole("protocol.segment", "num", 1, 1e5, "1", "kind = \"steps\": number of levels, both ends included"));
  k.push_back(num("protocol.segment", "settle", "s", 0.0, 1e6, false, false, "0", "kind = \"steps\": transient at each level"));
  k.push_back(num("protocol.segment", "measure", "s", 0.0, 1e6, true, false, "0", "kind = \"steps\": the classified window at each level"));
  k.push_back(num("protocol.segment", "step_rate", "rad/s^2", 0.0, 1e4, true, false, "1",
                  "kind = \"steps\": |dω_m/dt| between levels"));
}

// [hold] (astrojax sweep, instead of [protocol])
void hold_keys(std::vector<KeyInfo>& k) {
  k.push_back(other("hold", "omega", "list", "rad/s", fmt::format("each in [0, {}]", kOmegaMax), "",
                    "the held ω_m values: a list or {start, stop, num}"));
  k.push_back(num("hold", "settle", "s", 0.0, 1e6, false, false, "60", "transient before the measured window"));
  k.push_back(num("hold", "measure", "s", 0.0, 1e6, true, false, "10", "the measured window"));
  k.push_back(other("hold", "seeds", "list of words", "", "hanging, circular_high, locked_orbit", "[\"hanging\"]",
                    "the seed states each ω_m starts from"));
  k.push_back(whole("hold", "perturbations", 0, 1000, "0", "extra copies of each seed with random velocity kicks"));
  k.push_back(num("hold", "perturbation", "m/s", 0.0, 10.0, true, false, "0.01", "size of a kick"));
  k.push_back(num("hold", "sample_rate", "1/s", 0.0, 1e5, true, false, "100", "samples stored per second of every window"));
  early_stop_keys(k, "hold");
}

// [basin] (astrojax sweep, instead of [protocol]; sweep/basin.hpp)
void basin_keys(std::vector<KeyInfo>& k) {
  k.push_back(other("basin", "omega", "list", "rad/s", fmt::format("each in [0, {}]", kOmegaMax), "",
                    "the ω_m levels: a list or {start, stop, num}"));
  k.push_back(whole("basin", "samples", 1, 100000, "", "N, the starts drawn at each level"));
  k.push_back(other("basin", "family", "word", "", "hanging, hand, cloud", "",
                    "the distribution of the starts (guide: basin sweeps)"));
  k.push_back(whole("basin", "seed", 0, 9007199254740992.0, "1", "the draws' stream: another seed draws other starts"));
  k.push_back(num("basin", "settle", "s", 0.0, 1e6, false, false, "60", "held at the level before the measured window"));
  k.push_back(num("basin", "measure", "s", 0.0, 1e6, true, false, "10", "the measured window"));
  k.push_back(other("basin", "match_tolerance", "number", "", "any (ignored)", "",
                    "retired on 2026-11-28 and ignored: attractors are matched with bands from the features' measured "
                    "scatter (guide: basin sweeps); still accepted so that sweep files made before read"));
  k.push_back(other("basin", "s", "[lo, hi]", "m", "within the stops [s_min, l − d]", "l − d (on the bottom ball)",
                    "family hanging: the bead's position along the string, uniform in [lo, hi]"));
  k.push_back(num("basin", "swing", "rad", 0.0, 1.5707963267948966, false, false, "0.3",
                  "family hanging: each segment's angle from the vertical, uniform in [0, swing]"));
  k.push_back(num("basin", "hand_amplitude", "m", 0.0, 10.0, true, false, "0.1",
                  "family hand: A, the hand moves the top at most this far from the motor's top; at most l (guide: basin sweeps)"));
  k.push_back(num("basin", "hand_duration", "s", 0.0, 600.0, true, false, "3",
                  "family hand: T, the hand holds the top this long; shorter than settle"));
  k.push_back(whole("basin", "hand_modes", 1, 20, "3", "family hand: K, the random Fourier modes of the hand's path"));
  k.push_back(num("basin", "step_rate", "rad/s^2", 0.0, 1e4, true, false, "5",
                  "family hand: the motor's ramp from rest to the level, from t = 0"));
  k.push_back(other("basin", "orbit", "word", "", "locked_orbit, circular_high", "locked_orbit",
                    "family cloud: the orbit the starts surround, at each level"));
  k.push_back(other("basin", "state", "table", "", "{file, chain, window}; not with orbit", "",
                    "family cloud: the starts surround the state at the end of a window of a sweep file (guide: basin sweeps)"));
  k.push_back(other("basin.state", "file", "text", "", "a sweep file (relative to the working directory)", "",
                    "the sweep file the state is read from"));
  k.push_back(whole("basin.state", "chain", 0, 1e9, "", "the chain's index in that file"));
  k.push_back(whole("basin.state", "window", 0, 1e9, "",
                    "the window's index in its chain: the state at its end, which must end its task"));
  k.push_back(num("basin", "epsilon", "m", 0.0, 1.0, true, false, "0.01",
                  "family cloud: ε, each ball moved across the string by up to ε, each velocity component by up to ε ω_m "
                  "(at most a tenth of l)"));
  k.push_back(num("basin", "sample_rate", "1/s", 0.0, 1e5, true, false, "100", "samples stored per second of every window"));
}

// [bisect] (astrojax sweep, instead of [protocol] or [hold]): sweep/bisection.hpp.
void bisect_keys(std::vector<KeyInfo>& k) {
  k.push_back(other("bisect", "threshold", "word", "", "omega_rise, omega_fall, omega_1, omega_2", "",
                    "the threshold bracketed at every grid point"));
  k.push_back(other("bisect", "start_seed", "word", "", "hanging, circular_high, locked_orbit",
                    "hanging (omega_rise), circular_high (the others)", "the state at t = 0, a seed state at start_omega"));
  k.push_back(num("bisect", "start_omega", "rad/s", 0.0, kOmegaMax, false, false, "0", "ω_m of the seed at t = 0"));
  k.push_back(num("bisect", "from", "rad/s", 0.0, kOmegaMax, false, false, "",
                  "the first level, on the threshold's known side (reached from the seed at step_rate)"));
  k.push_back(num("bisect", "to", "rad/s", 0.0, kOmegaMax, false, false, "",
                  "the far end of the range: above from for omega_rise, omega_1, omega_2, below it for omega_fall"));
  k.push_back(num("bisect", "width", "rad/s", 0.0, kOmegaMax, true, false, "",
                  "the bracket's final width; at least 2π/(4·measure), below |to − from|"));
  k.push_back(num("bisect", "settle", "s", 0.0, 1e6, false, false, "100", "transient at each probed level"));
  k.push_back(num("bisect", "measure", "s", 0.0, 1e6, true, false, "20", "the classified window at each probed level"));
  k.push_back(num("bisect", "step_rate", "rad/s^2", 0.0, 1e4, true, false, "0.1", "|dω_m/dt| on the way to a level"));
  k.push_back(num("bisect", "sample_rate", "1/s", 0.0, 1e5, true, false, "100", "samples per second of every probe's window"));
  k.push_back(other("bisect", "decide_early", "boolean", "", "true, false", "true",
                    "stop an omega_fall or omega_1 probe once its class is decided: the bead down on the ball, or "
                    "stuck and converged to the locked orbit (false: every probe runs through its window)"));
  k.push_back(other("bisect", "guide", "word", "", "middle, held_orbit", "middle",
                    "where the probes go: the middle of every bracket, or (omega_fall, omega_1) next to the end of "
                    "the locked orbit the start level holds, continued in ω_m at its bead's s*; a wrong prediction "
                    "costs probes, never the bracket"));
}

// [grid]: each axis a list of values or {start, stop, num}.
void grid_keys(std::vector<KeyInfo>& k) {
  for (const std::string& axis : physics::grid_parameter_keys()) {
    const physics::ParameterInfo* p = physics::find_parameter(axis);
    const physics::ParameterAlias* a = p ? nullptr : physics::find_alias(axis);
    k.push_back(other("grid", axis, "list", std::string(p ? p->unit : a->unit),
                      p ? p->range() + (p->depends.empty() ? "" : fmt::format(", {}", p->depends)) : "as model.bead_mass",
                      "", fmt::format("sets model.{} of each chain{}", axis, a ? fmt::format(" ({})", a->doc) : "")));
  }
  k.push_back(other("grid", "ramp_rate", "list", "rad/s^2", "each in (0, 10000]", "",
                    "sets the rate of every ramp segment of each chain"));
  k.push_back(num("grid.*", "start", "", -1e12, 1e12, false, false, "0", "{start, stop, num}: the first value"));
  k.push_back(num("grid.*", "stop", "", -1e12, 1e12, false, false, "0", "{start, stop, num}: the last value"));
  k.push_back(whole("grid.*", "num", 1, 1e5, "1", "{start, stop, num}: how many values, both ends included"));
}

// [variant.NAME] and [[group]] (astrojax sweep)
void group_keys(std::vector<KeyInfo>& k) {
  k.push_back(other("variant", "label", "text", "", "non-empty", "", "what the model variant is, for tables and figures (any "
                    "UTF-8 but control characters other than TAB); a variant may also hold [model], [layers], [integrator] and [initial] tables"));
  k.push_back(other("group", "name", "text", "", "1 to 40 letters, digits, '_' or '-'", "", "the chain group's name"));
  k.push_back(other("group", "purpose", "text", "", "non-empty", "", "why its chains are there (any UTF-8 but control "
                    "characters other than TAB); a group may also hold "
                    "[model], [layers], [integrator], [initial], [protocol], [hold] or [bisect], and [grid] tables"));
  k.push_back(other("group", "variants", "list of words", "", "names of [variant.NAME] tables", "every variant",
                    "the variants the group runs with"));
}

// [orbits] (astrojax orbits)
void orbits_keys(std::vector<KeyInfo>& k) {
  k.push_back(other("orbits", "omega", "number or list", "rad/s", "each in (0, 2000]", "", "the ω_m of the table"));
  k.push_back(whole("orbits", "s_points", 2, 10000, "81", "points along the string of the table at each ω"));
  k.push_back(other("orbits", "continue", "word", "", joined(orbits::continuation_parameters()), "",
                    "the parameter a branch is continued in"));
  k.push_back(other("orbits", "range", "[lo, hi]", "", "lo < hi", "", "the continued parameter's interval"));
  k.push_back(other("orbits", "s", "number or list", "m", "each between the stops", "", "the bead's arc lengths s* of the table"));
}

// The classifier's settings: not in files, but given to classify as --set classifier.NAME=value.
void classifier_keys(std::vector<KeyInfo>& k) {
  const sweep::ClassifierSettings defaults;
  for (const sweep::ClassifierSettingInfo& c : sweep::classifier_setting_table())
    k.push_back(num("classifier", std::string(c.name), std::string(c.unit), 0.0, kInf, true, true,
                    fmt::format("{}", defaults.*c.field), std::string(c.doc)));
}

// Every section's keys, in the order of a file's tables.
std::vector<KeyInfo> build() {
  std::vector<KeyInfo> k = physics_keys();
  for (auto add : {integrator_keys, initial_keys, schedule_keys, output_keys, protocol_keys, hold_keys, basin_keys, bisect_keys, grid_keys,
                   group_keys, orbits_keys, classifier_keys})
    add(k);
  return k;
}

}  // namespace

const std::vector<KeyInfo>& key_catalogue() {
  static const std::vector<KeyInfo> keys = build();
  return keys;
}

std::string generic_section(std::string_view prefix) {
  // "group[3].start" -> "group.start": every "[digits]" dropped (a loop, not std::regex: this
  // runs for every key read, and a regex made the parse of a sweep with many variants cost
  // seconds under the fuzzer's sanitizers).
  std::string s;
  s.reserve(prefix.size());
  for (std::size_t i = 0; i < prefix.size(); ++i) {
    if (prefix[i] == '[') {
      std::size_t j = i + 1;
      while (j < prefix.size() && prefix[j] >= '0' && prefix[j] <= '9') ++j;
      if (j > i + 1 && j < prefix.size() && prefix[j] == ']') {
        i = j;
        continue;
      }
    }
    s += prefix[i];
  }
  if (s.rfind("variant.", 0) == 0) {  // variant.NAME or variant.NAME.model
    const std::size_t dot = s.find('.', 8);
    return dot == std::string::npos ? "variant" : s.substr(dot + 1);
  }
  if (s.rfind("grid.", 0) == 0 || s.rfind("hold.omega", 0) == 0 || s.rfind("basin.omega", 0) == 0 || s.rfind("orbits.", 0) == 0) return "grid.*";
  return s;
}

const KeyInfo* find_key(std::string_view section, std::string_view key) {
  const std::string g = generic_section(section);
  for (const KeyInfo& k : key_catalogue())
    if (k.section == g && k.key == key) return &k;
  return nullptr;
}

namespace {
std::set<std::string>& read_set() {
  static std::set<std::string> keys;
  return keys;
}
}  // namespace

void note_read(const KeyInfo& k) { read_set().insert(k.section + "." + k.key); }
std::vector<std::string> keys_read() { return {read_set().begin(), read_set().end()}; }

std::string key_reference_markdown() {
  std::string out;
  std::string section;
  for (const KeyInfo& k : key_catalogue()) {
    if (k.section != section) {
      section = k.section;
      const std::string title = section == "schedule" || section == "protocol.segment" || section == "group"
                                    ? fmt::format("`[[{}]]`", section)
                                : section == "variant" ? std::string("`[variant.NAME]`")
                                : section == "classifier"
                                    ? std::string("Classifier settings (`astrojax classify --set classifier.NAME=value`)")
                                : section == "grid.*"
                                    ? std::string("A value list `{start, stop, num}` (a [grid] axis, hold.omega, orbits.omega, orbits.s)")
                                    : fmt::format("`[{}]`", section);
      out += fmt::format("\n## {}\n\n| key | type | unit | allowed | default | meaning |\n|---|---|---|---|---|---|\n",
                         title);
    }
    auto cell = [](std::string s) {  // a table cell: no bare | inside, and * (as in s*) no emphasis
      for (const char c : {'|', '*'})
        for (std::size_t i = 0; (i = s.find(c, i)) != std::string::npos; i += 2) s.insert(i, 1, '\\');
      return s;
    };
    out += fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", k.key, k.type, k.unit.empty() ? "" : k.unit,
                       cell(k.allowed), k.fallback.empty() ? "" : cell(k.fallback), cell(k.doc));
  }
  return out;
}

}  // namespace ajx::config
