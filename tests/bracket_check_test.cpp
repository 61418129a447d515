// A bracket's checks as farm tasks (sweep/bracket_check.hpp): run_check gives exactly what the
// hold and the refinement give when called directly, a check and its result come back from
// their bytes bit for bit (NaNs included), an exception becomes the check's failure with its
// message, a damaged message is refused, and a check's seconds (the farm's order) are those it
// integrates. On tests/data/tiny_rise.toml, whose last ramp
// crosses ω_rise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "config/config.hpp"
#include "sweep/bracket_check.hpp"

using namespace ajx;
using namespace ajx::sweep;

namespace {

const SweepPlan& plan() {
  static const SweepPlan p =
      config::make_plan(config::load_sweep_config(std::string(ASTROJAX_SOURCE_DIR) + "/tests/data/tiny_rise.toml"));
  return p;
}

// The bytes of a result: equal bytes, equal results (doubles compared bit for bit).
std::vector<std::byte> bytes(const CheckResult& r) { return encode(r); }

// Two windows of the last ramp (12π → 14π), as a bracket.
Bracket last_ramp_bracket() {
  const auto& w = plan().setups[0].protocol.windows;
  const int a = int(w.size()) - 3;
  return Bracket{0.5 * (w[a].omega_begin + w[a].omega_end), 0.5 * (w[a + 1].omega_begin + w[a + 1].omega_end), a, a + 1};
}

HoldCheck hold_check() {
  const auto& w = plan().setups[0].protocol.windows;
  const Window& k = w[w.size() - 3];
  return HoldCheck{0, 0.5 * (k.t_begin + k.t_end), 20.0, k.t_end - k.t_begin, OrbitClass::Fallen};
}

}  // namespace

TEST(BracketCheck, HoldIsTheDirectHoldAndSurvivesItsBytes) {
  const HoldCheck h = hold_check();
  const physics::State start = plan().start_state(0);
  const CheckResult got = run_check(h, plan(), start, {});
  const HoldSide want = hold_side(plan().setups[0], h.t_cut, h.hold, h.window, start, h.reference, {});
  ASSERT_TRUE(std::holds_alternative<HoldSide>(got));
  const HoldSide& s = std::get<HoldSide>(got);
  EXPECT_TRUE(s.ok) << s.failure;
  EXPECT_EQ(s.classes.size(), want.classes.size());
  EXPECT_GE(s.classes.size(), 4u);  // at least four windows held
  EXPECT_EQ(bytes(got), bytes(want));
  EXPECT_EQ(bytes(decode_check_result(bytes(got))), bytes(got));
  const HoldSide back = std::get<HoldSide>(decode_check_result(bytes(got)));
  EXPECT_EQ(back.omega, s.omega);
  EXPECT_EQ(back.ratio, s.ratio);
  EXPECT_EQ(back.powers.size(), s.powers.size());
  EXPECT_EQ(back.powers.back().clutch, s.powers.back().clutch);
  EXPECT_EQ(back.final_class, s.final_class);
  EXPECT_EQ(back.sustained, s.sustained);
}

TEST(BracketCheck, RefinementIsTheDirectRefinementAndSurvivesItsBytes) {
  const RefineCheck f{0, Threshold::Rise, last_ramp_bracket(), 2};
  const physics::State start = plan().start_state(0);
  const CheckResult got = run_check(f, plan(), start, {});
  const Refinement want = refine_threshold(f.threshold, plan().setups[0], plan().points[0].protocol, f.bracket, 2, start, {});
  ASSERT_TRUE(std::holds_alternative<Refinement>(got));
  const Refinement& r = std::get<Refinement>(got);
  EXPECT_TRUE(r.ok) << r.failure;
  EXPECT_EQ(r.factor, 2);
  EXPECT_EQ(r.windows.size(), want.windows.size());
  EXPECT_GE(r.windows.size(), 4u);  // two old windows' span at half the rate
  EXPECT_EQ(bytes(got), bytes(want));
  const Refinement back = std::get<Refinement>(decode_check_result(bytes(got)));
  EXPECT_EQ(back.bracket.has_value(), r.bracket.has_value());
  EXPECT_EQ(back.windows.back().omega_end, r.windows.back().omega_end);
  EXPECT_EQ(back.windows.back().cls, r.windows.back().cls);
  EXPECT_EQ(back.simulated, r.simulated);
}

// The farm hands the checks out longest first by the seconds each integrates: for a refinement,
// the seconds it did integrate; for a hold, the replay up to t_cut and the hold.
TEST(BracketCheck, ItsSecondsAreThoseItIntegrates) {
  const physics::State start = plan().start_state(0);
  const RefineCheck f{0, Threshold::Rise, last_ramp_bracket(), 2};
  const Refinement r = std::get<Refinement>(run_check(f, plan(), start, {}));
  EXPECT_NEAR(check_seconds(f, plan(), start), r.simulated, 1e-9 * r.simulated);
  const HoldCheck h = hold_check();
  EXPECT_DOUBLE_EQ(check_seconds(h, plan(), start), h.t_cut + h.hold - start.t);
  HoldCheck elsewhere = h;
  elsewhere.chain = 99;  // no such chain: run_check fails it, and it costs nothing
  EXPECT_EQ(check_seconds(elsewhere, plan(), start), 0.0);
}

TEST(BracketCheck, ChecksSurviveTheirBytes) {
  const HoldCheck h = hold_check();
  const auto hb = std::get<HoldCheck>(decode_check(encode(BracketCheck{h})));
  EXPECT_EQ(hb.chain, h.chain);
  EXPECT_EQ(hb.t_cut, h.t_cut);
  EXPECT_EQ(hb.hold, h.hold);
  EXPECT_EQ(hb.window, h.window);
  EXPECT_EQ(hb.reference, h.reference);
  const RefineCheck f{0, Threshold::Omega2, last_ramp_bracket(), 7};
  const auto fb = std::get<RefineCheck>(decode_check(encode(BracketCheck{f})));
  EXPECT_EQ(fb.threshold, Threshold::Omega2);
  EXPECT_EQ(fb.bracket.before, f.bracket.before);
  EXPECT_EQ(fb.bracket.after, f.bracket.after);
  EXPECT_EQ(fb.bracket.window_before, f.bracket.window_before);
  EXPECT_EQ(fb.bracket.window_after, f.bracket.window_after);
  EXPECT_EQ(fb.factor, 7);
  // A side that never ran keeps its NaNs and its failure.
  HoldSide empty;
  empty.ok = false;
  empty.failure = "why";
  const HoldSide eb = std::get<HoldSide>(decode_check_result(encode(CheckResult{empty})));
  EXPECT_TRUE(std::isnan(eb.omega) && std::isnan(eb.mean.motor) && std::isnan(eb.first_change));
  EXPECT_FALSE(eb.ok);
  EXPECT_EQ(eb.failure, "why");
}

TEST(BracketCheck, AnExceptionBecomesTheFailure) {
  // A start state later than the hold or the refinement: hold_side and refine_threshold throw.
  physics::State late = plan().start_state(0);
  late.t = plan().setups[0].protocol.duration;
  const CheckResult h = run_check(hold_check(), plan(), late, {});
  EXPECT_FALSE(std::get<HoldSide>(h).ok);
  EXPECT_EQ(std::get<HoldSide>(h).failure, "hold: the start state is later than the hold");
  EXPECT_EQ(std::get<HoldSide>(h).reference, OrbitClass::Fallen);
  const CheckResult f = run_check(RefineCheck{0, Threshold::Rise, last_ramp_bracket(), 3}, plan(), late, {});
  EXPECT_FALSE(std::get<Refinement>(f).ok);
  EXPECT_EQ(std::get<Refinement>(f).failure, "refinement: the start state is later than the bracket");
  EXPECT_EQ(std::get<Refinement>(f).factor, 3);
  // A chain the plan does not have.
  HoldCheck far = hold_check();
  far.chain = 5;
  const CheckResult c = run_check(far, plan(), plan().start_state(0), {});
  EXPECT_EQ(std::get<HoldSide>(c).failure, "chain 5 is not one of the sweep's 1 chains");
}

TEST(BracketCheck, DamagedBytesAreRefused) {
  const std::vector<std::byte> check = encode(BracketCheck{hold_check()});
  EXPECT_THROW(decode_check(std::vector<std::byte>(check.begin(), check.end() - 1)), std::runtime_error);
  std::vector<std::byte> longer = check;
  longer.push_back(std::byte{0});
  EXPECT_THROW(decode_check(longer), std::runtime_error);
  std::vector<std::byte> kind = check;
  kind[0] = std::byte{7};
  EXPECT_THROW(decode_check(kind), std::runtime_error);
  std::vector<std::byte> cls = check;
  const std::int32_t bad = 99;  // the reference class, the last four bytes
  std::memcpy(cls.data() + cls.size() - 4, &bad, 4);
  EXPECT_THROW(decode_check(cls), std::runtime_error);
  EXPECT_THROW(decode_check_result({}), std::runtime_error);
}
