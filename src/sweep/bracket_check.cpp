#include "sweep/bracket_check.hpp"

#include <algorithm>
#include <cstdint>
#include <exception>
#include <fmt/format.h>
#include <stdexcept>
#include <type_traits>

#include "sweep/codec.hpp"

namespace ajx::sweep {

namespace {

// The checks' kinds, first byte of a check and of a result: the variant's index.
constexpr std::uint8_t kHold = 0, kRefine = 1;
static_assert(std::is_same_v<std::variant_alternative_t<kHold, BracketCheck>, HoldCheck> &&
              std::is_same_v<std::variant_alternative_t<kRefine, CheckResult>, Refinement>);

std::uint8_t get_kind(ByteReader& r) {
  const auto kind = r.get<std::uint8_t>();
  if (kind != kHold && kind != kRefine) throw std::runtime_error(fmt::format("bracket check codec: kind {}", kind));
  return kind;
}

void put_class(ByteWriter& w, OrbitClass c) { w.put<std::int32_t>(std::int32_t(c)); }
OrbitClass get_class(ByteReader& r) {
  const auto c = r.get<std::int32_t>();
  if (c < 0 || c >= std::int32_t(kNumOrbitClasses)) throw std::runtime_error(fmt::format("bracket check codec: class {}", c));
  return OrbitClass(c);
}

void put_bracket(ByteWriter& w, const Bracket& b) {
  w.put(b.before);
  w.put(b.after);
  w.put<std::int32_t>(b.window_before);
  w.put<std::int32_t>(b.window_after);
}
Bracket get_bracket(ByteReader& r) {
  Bracket b{r.get<double>(), r.get<double>()};
  b.window_before = r.get<std::int32_t>();
  b.window_after = r.get<std::int32_t>();
  return b;
}

void put_powers(ByteWriter& w, const WindowPowers& p) {
  for (double v : {p.motor, p.drag, p.other, p.energy_rate, p.string, p.clutch}) w.put(v);
}
WindowPowers get_powers(ByteReader& r) {
  WindowPowers p{};
  for (double* v : {&p.motor, &p.drag, &p.other, &p.energy_rate, &p.string, &p.clutch}) *v = r.get<double>();
  return p;
}

void put_side(ByteWriter& w, const HoldSide& s) {
  for (double v : {s.omega, s.t_cut, s.hold}) w.put(v);
  w.put<std::uint64_t>(s.classes.size());
  for (OrbitClass c : s.classes) put_class(w, c);
  w.put<std::uint64_t>(s.powers.size());
  for (const WindowPowers& p : s.powers) put_powers(w, p);
  put_class(w, s.reference);
  put_class(w, s.final_class);
  w.put(s.first_change);
  w.put<std::int32_t>(s.measured);
  put_powers(w, s.mean);
  for (double v : {s.ratio, s.ratio_error, s.tolerance}) w.put(v);
  for (bool b : {s.sustained, s.determined, s.ok}) w.put<std::uint8_t>(b);
  w.put_string(s.failure);
  w.put(s.simulated);
}
HoldSide get_side(ByteReader& r) {
  HoldSide s;
  for (double* v : {&s.omega, &s.t_cut, &s.hold}) *v = r.get<double>();
  s.classes.resize(r.get<std::uint64_t>());
  for (OrbitClass& c : s.classes) c = get_class(r);
  s.powers.resize(r.get<std::uint64_t>());
  for (WindowPowers& p : s.powers) p = get_powers(r);
  s.reference = get_class(r);
  s.final_class = get_class(r);
  s.first_change = r.get<double>();
  s.measured = r.get<std::int32_t>();
  s.mean = get_powers(r);
  for (double* v : {&s.ratio, &s.ratio_error, &s.tolerance}) *v = r.get<double>();
  for (bool* b : {&s.sustained, &s.determined, &s.ok}) *b = r.get<std::uint8_t>() != 0;
  s.failure = r.get_string();
  s.simulated = r.get<double>();
  return s;
}

void put_refinement(ByteWriter& w, const Refinement& f) {
  w.put<std::uint8_t>(f.bracket.has_value());
  if (f.bracket) put_bracket(w, *f.bracket);
  w.put<std::int32_t>(f.factor);
  w.put<std::uint64_t>(f.windows.size());
  for (const ClassedWindow& cw : f.windows) {
    w.put(cw.omega_begin);
    w.put(cw.omega_end);
    w.put<std::int32_t>(cw.direction);
    put_class(w, cw.cls);
    w.put<std::int32_t>(cw.index);
  }
  w.put<std::uint8_t>(f.ok);
  w.put_string(f.failure);
  w.put(f.simulated);
}
Refinement get_refinement(ByteReader& r) {
  Refinement f;
  if (r.get<std::uint8_t>() != 0) f.bracket = get_bracket(r);
  f.factor = r.get<std::int32_t>();
  f.windows.resize(r.get<std::uint64_t>());
  for (ClassedWindow& cw : f.windows) {
    cw.omega_begin = r.get<double>();
    cw.omega_end = r.get<double>();
    cw.direction = r.get<std::int32_t>();
    cw.cls = get_class(r);
    cw.index = r.get<std::int32_t>();
  }
  f.ok = r.get<std::uint8_t>() != 0;
  f.failure = r.get_string();
  f.simulated = r.get<double>();
  return f;
}

void expect_end(const ByteReader& r) {
  if (!r.done()) throw std::runtime_error("bracket check codec: trailing bytes");
}

}  // namespace

CheckResult failed_check(const BracketCheck& check, const std::string& why) {
  if (const auto* f = std::get_if<RefineCheck>(&check)) {
    Refinement r;
    r.factor = f->factor;
    r.ok = false, r.failure = why;
    return r;
  }
  HoldSide s;
  s.reference = std::get<HoldCheck>(check).reference;
  s.ok = false, s.failure = why;
  return s;
}

CheckResult run_check(const BracketCheck& check, const SweepPlan& plan, const physics::State& start,
                      const ClassifierSettings& settings) {
  try {
    const std::size_t c = std::visit([](const auto& k) { return k.chain; }, check);
    if (c >= plan.chains())
      return failed_check(check, fmt::format("chain {} is not one of the sweep's {} chains", c, plan.chains()));
    if (const auto* h = std::get_if<HoldCheck>(&check))
      return hold_side(plan.setups[c], h->t_cut, h->hold, h->window, start, h->reference, settings);
    const RefineCheck& f = std::get<RefineCheck>(check);
    return refine_threshold(f.threshold, plan.setups[c], plan.points[c].protocol, f.bracket, f.factor, start, settings);
  } catch (const std::exception& e) {
    return failed_check(check, e.what());
  }
}

double check_seconds(const BracketCheck& check, const SweepPlan& plan, const physics::State& start) {
  const std::size_t c = std::visit([](const auto& k) { return k.chain; }, check);
  if (c >= plan.chains()) return 0.0;
  if (const auto* h = std::get_if<HoldCheck>(&check)) return std::max(h->t_cut + h->hold - start.t, 0.0);
  const RefineCheck& f = std::get<RefineCheck>(check);
  try {
    const ChainSetup refined = refined_chain(plan.setups[c], plan.points[c].protocol, f.bracket, f.factor);
    return refined.protocol.windows.empty() ? 0.0 : std::max(refined.protocol.windows.back().t_end - start.t, 0.0);
  } catch (const std::invalid_argument&) {
    return 0.0;  // run_check reports it
  }
}

std::vector<std::byte> encode(const BracketCheck& check) {
  ByteWriter w;
  if (const auto* h = std::get_if<HoldCheck>(&check)) {
    w.put<std::uint8_t>(kHold);
    w.put<std::uint64_t>(h->chain);
    for (double v : {h->t_cut, h->hold, h->window}) w.put(v);
    put_class(w, h->reference);
  } else {
    const RefineCheck& f = std::get<RefineCheck>(check);
    w.put<std::uint8_t>(kRefine);
    w.put<std::uint64_t>(f.chain);
    w.put<std::int32_t>(std::int32_t(f.threshold));
    put_bracket(w, f.bracket);
    w.put<std::int32_t>(f.factor);
  }
  return w.take();
}

BracketCheck decode_check(const std::vector<std::byte>& bytes) {
  ByteReader r(bytes.data(), bytes.size());
  BracketCheck out;
  if (get_kind(r) == kHold) {
    HoldCheck h;
    h.chain = std::size_t(r.get<std::uint64_t>());
    for (double* v : {&h.t_cut, &h.hold, &h.window}) *v = r.get<double>();
    h.reference = get_class(r);
    out = h;
  } else {
    RefineCheck f;
    f.chain = std::size_t(r.get<std::uint64_t>());
    const auto t = r.get<std::int32_t>();
    if (t < 0 || t >= std::int32_t(kThresholds.size()))
      throw std::runtime_error(fmt::format("bracket check codec: threshold {}", t));
    f.threshold = Threshold(t);
    f.bracket = get_bracket(r);
    f.factor = r.get<std::int32_t>();
    out = f;
  }
  expect_end(r);
  return out;
}

std::vector<std::byte> encode(const CheckResult& result) {
  ByteWriter w;
  if (const auto* s = std::get_if<HoldSide>(&result)) {
    w.put<std::uint8_t>(kHold);
    put_side(w, *s);
  } else {
    w.put<std::uint8_t>(kRefine);
    put_refinement(w, std::get<Refinement>(result));
  }
  return w.take();
}

CheckResult decode_check_result(const std::vector<std::byte>& bytes) {
  ByteReader r(bytes.data(), bytes.size());
  CheckResult out;
  if (get_kind(r) == kHold)
    out = get_side(r);
  else
    out = get_refinement(r);
  expect_end(r);
  return out;
}

}  // namespace ajx::sweep
