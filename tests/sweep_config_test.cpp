// Sweep files: the protocol and grid parse, the grid expands to one chain per point with its
// parameters, and bad input is rejected before any work with file, key and allowed range.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include <cstdio>

#include "config/config.hpp"
#include "sweep/plan.hpp"

using namespace ajx::config;

namespace {
std::string quick() {
  std::ifstream in(std::string(ASTROJAX_SOURCE_DIR) + "/sweeps/quick.toml");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
std::string error_of(const std::vector<std::string>& overrides) {
  try {
    parse_sweep_config(quick(), "sweeps/quick.toml", overrides);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(SweepConfig, TheShippedQuickSweepParses) {
  const SweepConfig c = parse_sweep_config(quick(), "sweeps/quick.toml");
  ASSERT_EQ(c.protocol.size(), 2u);
  EXPECT_EQ(c.protocol[0].kind, ajx::sweep::Segment::Kind::Ramp);
  ASSERT_EQ(c.grid.size(), 1u);
  const auto points = ajx::sweep::expand_grid(c.model, c, c.source_name);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_DOUBLE_EQ(points[0].model.p.drive_radius, 0.01);
  EXPECT_DOUBLE_EQ(points[1].model.p.drive_radius, 0.02);
}

TEST(SweepConfig, GridsAreCartesianProductsLastAxisFastest) {
  const SweepConfig c = parse_sweep_config(
      quick(), "q.toml", {"grid.contact_distance={start=0.02,stop=0.04,num=3}", "grid.mass=[0.018,0.1]", "grid.ramp_rate=[0.25]"});
  const auto points = ajx::sweep::expand_grid(c.model, c, c.source_name);
  ASSERT_EQ(points.size(), 2u * 3u * 2u * 1u);
  // Axes in alphabetical order: contact_distance (slowest), drive_radius, mass, ramp_rate.
  EXPECT_DOUBLE_EQ(points[0].model.p.contact_distance, 0.02);
  EXPECT_DOUBLE_EQ(points[0].model.p.drive_radius, 0.01);
  EXPECT_DOUBLE_EQ(points[0].model.p.bead_mass, 0.018);
  EXPECT_DOUBLE_EQ(points[1].model.p.bead_mass, 0.1);
  EXPECT_DOUBLE_EQ(points[1].model.p.ball_mass, 0.1);
  EXPECT_DOUBLE_EQ(points[2].model.p.drive_radius, 0.02);
  EXPECT_DOUBLE_EQ(points[4].model.p.contact_distance, 0.03);
  EXPECT_DOUBLE_EQ(points[11].model.p.contact_distance, 0.04);
  EXPECT_EQ(points[11].values, (std::vector<double>{0.04, 0.02, 0.1, 0.25}));
  for (const auto& p : points)
    for (const auto& s : p.protocol) EXPECT_DOUBLE_EQ(s.ramp.rate, 0.25);
}

// The tie clutch's torques are grid axes too; each point is validated like [model], so a
// kinetic torque above the static one is refused at the grid point that has it.
TEST(SweepConfig, TieClutchParametersAreGridAxes) {
  const SweepConfig c = parse_sweep_config(
      quick(), "q.toml",
      {"layers.tie=\"clutch\"", "model.tie_static_torque=1.5e-3", "model.tie_kinetic_torque=1.35e-3",
       "grid.tie_damping=[1e-7,2e-6]", "grid.tie_kinetic_torque=[1.3e-3]"});
  const auto points = ajx::sweep::expand_grid(c.model, c, c.source_name);
  ASSERT_EQ(points.size(), 2u * 1u * 2u);  // drive_radius × tie_damping × tie_kinetic_torque
  EXPECT_DOUBLE_EQ(points[0].model.p.tie_damping, 1e-7);
  EXPECT_DOUBLE_EQ(points[1].model.p.tie_damping, 2e-6);
  EXPECT_DOUBLE_EQ(points[1].model.p.tie_kinetic_torque, 1.3e-3);
  EXPECT_DOUBLE_EQ(points[1].model.p.tie_static_torque, 1.5e-3);
  try {
    parse_sweep_config(quick(), "q.toml",
                       {"layers.tie=\"clutch\"", "model.tie_static_torque=1.5e-3", "model.tie_kinetic_torque=1.35e-3",
                        "grid.tie_kinetic_torque=[1.4e-3,1.6e-3]"});
    ADD_FAILURE() << "a kinetic torque above the static one was accepted";
  } catch (const ConfigError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("model.tie_kinetic_torque"), std::string::npos) << m;
    EXPECT_NE(m.find("grid.tie_kinetic_torque[1]"), std::string::npos) << m;
  }
}

// The pair couple's τ_c and Ω_ε are grid axes; an Ω_ε out of range (> 0) is refused at its point.
TEST(SweepConfig, PairCoupleParametersAreGridAxes) {
  const SweepConfig c =
      parse_sweep_config(quick(), "q.toml",
                         {"layers.pair_couple=\"motor_clutch\"", "model.couple_torque=2e-3",
                          "grid.couple_torque=[0.0,1e-3]", "grid.couple_slip_rate=[0.5]"});
  const auto points = ajx::sweep::expand_grid(c.model, c, c.source_name);
  ASSERT_EQ(points.size(), 2u * 1u * 2u);  // couple_slip_rate × couple_torque × drive_radius
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_DOUBLE_EQ(points[i].model.p.couple_slip_rate, 0.5);
    EXPECT_DOUBLE_EQ(points[i].model.p.couple_torque, i < 2 ? 0.0 : 1e-3);
  }
  const std::string m = error_of({"grid.couple_slip_rate=[1.0,0.0]"});
  EXPECT_NE(m.find("model.couple_slip_rate"), std::string::npos) << m;
  EXPECT_NE(m.find("grid.couple_slip_rate[1]"), std::string::npos) << m;
}

TEST(SweepConfig, BadSweepFilesNameFileKeyAndRange) {
  const struct {
    std::vector<std::string> set;
    std::string key, range;
  } cases[] = {
      {{"protocol.colour=1"}, "protocol.colour", "unknown key"},
      {{"grid.length=[1.0]"}, "grid.length", "drive_radius, contact_distance"},
      {{"grid.drive_radius=[0.01, 0.9]"}, "model.drive_radius", "0 <= R < l"},
      {{"grid.drive_radius=[0.01, 0.9]"}, "grid.drive_radius[1]", ""},
      {{"grid.contact_distance={start=0.02,stop=0.04}"}, "grid.contact_distance.num", "missing"},
      {{"grid.mass=[]"}, "grid.mass", "empty"},
      {{"protocol.segment=[]"}, "protocol.segment", "at least one"},
      {{"protocol.segment=[{kind=\"ramp\",from=0.0,to=10.0,rate=-1.0}]"}, "protocol.segment[0].rate", "(0, 10000]"},
      {{"protocol.segment=[{kind=\"steps\",from=1.0,to=2.0,num=0,measure=1.0}]"}, "protocol.segment[0].num", "[1, 100000]"},
      {{"protocol.segment=[{kind=\"hop\",from=1.0,to=2.0}]"}, "protocol.segment[0].kind", "ramp, steps"},
      {{"protocol.sample_rate=0"}, "protocol.sample_rate", "(0, 100000]"},
      {{"grid.ramp_rate=[0.0]"}, "grid.ramp_rate[0]", "(0, 10000]"},
  };
  for (const auto& c : cases) {
    const std::string e = error_of(c.set);
    ASSERT_FALSE(e.empty()) << c.set[0] << " was accepted";
    EXPECT_NE(e.find("sweeps/quick.toml"), std::string::npos) << e;
    EXPECT_NE(e.find(c.key), std::string::npos) << e;
    EXPECT_NE(e.find(c.range), std::string::npos) << e;
  }
}

TEST(SweepConfig, HoldModeParsesAndRejectsBadSeeds) {
  std::ifstream in(std::string(ASTROJAX_SOURCE_DIR) + "/tests/data/tiny_hold.toml");
  std::stringstream ss;
  ss << in.rdbuf();
  const SweepConfig c = parse_sweep_config(ss.str(), "tests/data/tiny_hold.toml");
  ASSERT_TRUE(c.hold);
  EXPECT_EQ(c.hold->omega.size(), 2u);
  EXPECT_EQ(c.hold->seeds, (std::vector<std::string>{"hanging", "circular_high"}));
  EXPECT_EQ(c.hold->perturbations, 1);
  const auto err = [&](const std::vector<std::string>& set) {
    try {
      parse_sweep_config(ss.str(), "tests/data/tiny_hold.toml", set);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(err({"hold.seeds=[\"spinning\"]"}).find("hold.seeds[0]"), std::string::npos);
  EXPECT_NE(err({"hold.omega=[-1.0]"}).find("hold.omega[0]"), std::string::npos);
  EXPECT_NE(err({"hold.measure=0"}).find("hold.measure"), std::string::npos);
  EXPECT_NE(err({"protocol.start_omega=1.0"}).find("either [protocol]"), std::string::npos);
}

// [protocol] start_seed: a protocol may start from a seed orbit instead of rest. The plan's
// start state is that seed turning at start_omega (sweeps/table1.toml starts on Table 1's orbit).
TEST(SweepConfig, ProtocolStartsFromASeed) {
  const SweepConfig rest = parse_sweep_config(quick(), "sweeps/quick.toml");
  EXPECT_EQ(rest.start_seed, "hanging");
  const double w = 4.0 * 3.141592653589793;
  const SweepConfig c = parse_sweep_config(
      quick(), "sweeps/quick.toml",
      {"protocol.start_seed=circular_high", "protocol.start_omega=" + std::to_string(w),
       "protocol.segment=[{kind=\"ramp\", from=" + std::to_string(w) + ", to=20.0, rate=0.5, window=5.0}]"});
  EXPECT_EQ(c.start_seed, "circular_high");
  const ajx::sweep::SweepPlan plan = ajx::config::make_plan(c);
  const ajx::physics::State s = plan.start_state(0);
  // Table 1's orbit: the bead high on the string (|r1| ≈ 0.545 m, well short of l − d), both
  // balls turning about the axis at start_omega. The seed sets v = ω ẑ × r, then projects the
  // positions onto the string: Table 1's positions miss l by δ = L1 + L2 − l (computed here
  // from the paper's numbers), which moves a radius ρ by at most δ, so the rate ρ-weighted
  // about the axis moves by at most δ/ρ_min of ω.
  const Eigen::Vector3d t1(-0.14427, 0.0, -0.52483), t2(0.11924, 0.0, -0.62353), a(c.model.p.drive_radius, 0, 0);
  const double delta = (t1 - a).norm() + (t2 - t1).norm() - 0.826, rho_min = 0.11924;
  const Eigen::Vector3d r1 = s.r1(), v1 = s.v1(), r2 = s.r2(), v2 = s.v2();
  EXPECT_LT(r1.norm(), 0.7 * c.model.p.string_length);
  const double w1 = r1.cross(v1).z() / r1.head<2>().squaredNorm(), w2 = r2.cross(v2).z() / r2.head<2>().squaredNorm();
  std::printf("measured seed angular velocities: %.6f %.6f rad/s at start_omega %.6f (bound %.4f)\n", w1, w2, w,
              delta / rho_min * w);
  EXPECT_NEAR(w1, w, delta / rho_min * w);
  EXPECT_NEAR(w2, w, delta / rho_min * w);
  EXPECT_NE(error_of({"protocol.start_seed=spinning"}).find("protocol.start_seed"), std::string::npos);
}

// Chain groups and model variants: each group runs once per variant, its tables and the
// variant's merged over the file's; the plan places every part's grid on the file's axes.
namespace {
const char* kGrouped = R"(
[model]
drive_radius = 0.015
[protocol]
sample_rate = 40.0
[[protocol.segment]]
kind = "ramp"
from = 0.0
to = 10.0
rate = 1.0
window = 5.0
[variant.rigid]
label = "rigid tie"
[variant.clutch]
label = "tie clutch"
layers = { tie = "clutch" }
model = { tie_static_torque = 1.5e-3, tie_kinetic_torque = 1.35e-3 }
[[group]]
name = "rest"
purpose = "from rest"
[[group]]
name = "orbit"
purpose = "from Table 1's orbit"
variants = ["clutch"]
model = { contact_distance = 0.04 }
[group.protocol]
start_seed = "circular_high"
start_omega = 12.0
[[group.protocol.segment]]
kind = "steps"
from = 13.0
to = 14.0
num = 2
settle = 1.0
measure = 2.0
[group.grid]
tie_damping = [1e-6, 2e-6]
[output]
path = "out/grouped.h5"
)";
std::string grouped_error(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    parse_sweep_config(text, "g.toml", overrides);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}
}  // namespace

TEST(SweepConfig, GroupsRunOncePerVariantWithTheirTablesMerged) {
  const SweepConfig c = parse_sweep_config(kGrouped, "g.toml");
  ASSERT_EQ(c.parts.size(), 3u);  // rest × (rigid, clutch), orbit × clutch
  // Variants in the file's order, not the table's sorted one.
  EXPECT_EQ(c.parts[0].group, "rest");
  EXPECT_EQ(c.parts[0].variant, "rigid");
  EXPECT_EQ(c.parts[1].variant, "clutch");
  EXPECT_EQ(c.parts[1].variant_label, "tie clutch");
  EXPECT_FALSE(c.parts[0].model.layers.tie_clutch);
  EXPECT_TRUE(c.parts[1].model.layers.tie_clutch);
  EXPECT_DOUBLE_EQ(c.parts[1].model.p.tie_static_torque, 1.5e-3);
  EXPECT_EQ(c.parts[1].start_seed, "hanging");
  const SweepConfig& orbit = c.parts[2];
  EXPECT_EQ(orbit.group, "orbit");
  EXPECT_EQ(orbit.group_purpose, "from Table 1's orbit");
  EXPECT_EQ(orbit.start_seed, "circular_high");
  EXPECT_DOUBLE_EQ(orbit.model.p.contact_distance, 0.04);  // the group's own value
  EXPECT_DOUBLE_EQ(orbit.model.p.drive_radius, 0.015);     // the file's
  ASSERT_EQ(orbit.protocol.size(), 1u);                    // the group's segments replace the file's
  EXPECT_EQ(orbit.protocol[0].kind, ajx::sweep::Segment::Kind::Steps);
  EXPECT_DOUBLE_EQ(c.sample_rate, 40.0);
  EXPECT_EQ(c.output_path, "out/grouped.h5");

  const ajx::sweep::SweepPlan plan = ajx::config::make_plan(c);
  ASSERT_EQ(plan.chains(), 4u);  // 1 + 1 + 2 grid points
  EXPECT_EQ(plan.part, (std::vector<std::size_t>{0, 1, 2, 2}));
  ASSERT_EQ(plan.axes, (std::vector<std::string>{"tie_damping"}));
  EXPECT_TRUE(std::isnan(plan.points[0].values[0]));  // a part without the axis
  EXPECT_DOUBLE_EQ(plan.points[3].values[0], 2e-6);
  EXPECT_DOUBLE_EQ(plan.setups[3].model.p.tie_damping, 2e-6);
  EXPECT_EQ(plan.starts[2].seed, "circular_high");
  EXPECT_DOUBLE_EQ(plan.starts[2].omega, 12.0);
  EXPECT_EQ(plan.setups[0].protocol.windows.size(), 2u);  // the file's ramp, 10 s in 5 s windows
}

TEST(SweepConfig, SetReachesEveryPartOrOneVariant) {
  const SweepConfig all = parse_sweep_config(kGrouped, "g.toml", {"model.contact_distance=0.03"});
  for (const SweepConfig& p : all.parts) EXPECT_DOUBLE_EQ(p.model.p.contact_distance, 0.03);  // over the group's too
  const SweepConfig one = parse_sweep_config(kGrouped, "g.toml", {"variant.clutch.model.tie_damping=3e-6"});
  EXPECT_DOUBLE_EQ(one.parts[0].model.p.tie_damping, ajx::physics::Parameters{}.tie_damping);
  EXPECT_DOUBLE_EQ(one.parts[1].model.p.tie_damping, 3e-6);
}

TEST(SweepConfig, BadGroupsAndVariantsNameFileAndKey) {
  EXPECT_NE(grouped_error(replaced(kGrouped, "purpose = \"from rest\"\n", "")).find("key 'group[0].purpose': missing"),
            std::string::npos);
  EXPECT_NE(grouped_error(replaced(kGrouped, "variants = [\"clutch\"]", "variants = [\"slip\"]"))
                .find("key 'group[1].variants[0]': expected a variant name used once; allowed: rigid, clutch"),
            std::string::npos);
  EXPECT_NE(grouped_error(replaced(kGrouped, "name = \"orbit\"", "name = \"rest\"")).find("'rest' names two groups"),
            std::string::npos);
  EXPECT_NE(grouped_error(replaced(kGrouped, "name = \"orbit\"", "name = \"or bit\"")).find("is not a name"),
            std::string::npos);
  EXPECT_NE(grouped_error(replaced(kGrouped, "label = \"rigid tie\"\n", "")).find("key 'variant.rigid.label': missing"),
            std::string::npos);
  EXPECT_NE(grouped_error(replaced(kGrouped, "[group.grid]", "[group.output]")).find("key 'group[1].output': unknown key"),
            std::string::npos);
  // Labels and purposes: any UTF-8 but control characters other than TAB.
  EXPECT_NE(grouped_error(replaced(kGrouped, "label = \"rigid tie\"", "label = \"rigid\\ntie\""))
                .find("key 'variant.rigid.label': control character U+000A not allowed"),
            std::string::npos);
  EXPECT_NE(grouped_error(replaced(kGrouped, "label = \"rigid tie\"", "label = \"\\u001b[31mred\""))
                .find("key 'variant.rigid.label': control character U+001B not allowed"),
            std::string::npos);
  EXPECT_NE(grouped_error(replaced(kGrouped, "purpose = \"from rest\"", "purpose = \"from\\u0085rest\""))
                .find("key 'group[0].purpose': control character U+0085 not allowed"),
            std::string::npos);
  EXPECT_EQ(grouped_error(replaced(kGrouped, "label = \"rigid tie\"", "label = \"rigid\\ttie — µ ✓\"")), "");
  // A group's own bad value names the file, the group, the variant and the key.
  const std::string e = grouped_error(replaced(kGrouped, "num = 2\n", "num = 0\n"));
  EXPECT_NE(e.find("g.toml (group[1] 'orbit', variant 'clutch'): key 'protocol.segment[0].num'"), std::string::npos) << e;
  EXPECT_NE(grouped_error(kGrouped, {"model.drive_radius=-1"}).find("key 'model.drive_radius'"), std::string::npos);
  // One sample rate for the file.
  const std::string rate = grouped_error(replaced(kGrouped, "start_omega = 12.0", "start_omega = 12.0\nsample_rate = 20.0"));
  EXPECT_NE(rate.find("key 'sample_rate'"), std::string::npos) << rate;
}

// --set means one thing in a plain and a grouped sweep: an unknown table is refused by both with
// the same words and the nearest table; keys are compared as typed (a Cyrillic о is another
// letter); a variant the file lacks is refused unless the same overrides give its label.
TEST(SweepConfig, SetIsRefusedAlikeInPlainAndGroupedSweeps) {
  const std::string grouped_text = kGrouped;
  const std::string plain_text = grouped_text.substr(0, grouped_text.find("[variant.rigid]"));
  for (const std::string set : {"nosuch.x=1", "mоdel.drag=0.5", "modl.drag=0.5"}) {
    const std::string table = set.substr(0, set.find('.'));
    const std::string grouped = grouped_error(kGrouped, {set}), plain = grouped_error(plain_text, {set});
    const std::string expected = "g.toml: key '" + table + "': unknown key";
    EXPECT_NE(grouped.find(expected), std::string::npos) << grouped;
    EXPECT_NE(plain.find(expected), std::string::npos) << plain;
    if (table != "nosuch") {
      EXPECT_NE(grouped.find("did you mean 'model'"), std::string::npos) << grouped;
      EXPECT_NE(plain.find("did you mean 'model'"), std::string::npos) << plain;
    }
  }
  // A key of a known table, mistyped with a lookalike letter (Cyrillic а), in every part.
  const std::string key = grouped_error(kGrouped, {"model.drаg=0.5"});
  EXPECT_NE(key.find("key 'model.drаg': unknown key (did you mean 'drag'?)"), std::string::npos) << key;

  const std::string missing = grouped_error(kGrouped, {"variant.slip.model.tie_damping=3e-6"});
  EXPECT_NE(missing.find("g.toml: key 'variant.slip': no such variant; allowed: rigid, clutch"), std::string::npos) << missing;
  EXPECT_NE(grouped_error(kGrouped, {"variant.clutc.model.tie_damping=3e-6"}).find("did you mean 'clutch'"),
            std::string::npos);
  // Defined completely by the same command: a third variant, run by the group that runs all.
  const SweepConfig c =
      parse_sweep_config(kGrouped, "g.toml", {"variant.slip.label=slipping", "variant.slip.model.tie_damping=3e-6"});
  ASSERT_EQ(c.parts.size(), 4u);
  EXPECT_EQ(c.parts[2].variant, "slip");
  EXPECT_EQ(c.parts[2].variant_label, "slipping");
  EXPECT_DOUBLE_EQ(c.parts[2].model.p.tie_damping, 3e-6);
}

TEST(SweepConfig, TheShippedPaperSweepHasBothVariantsOfEveryGroup) {
  std::ifstream in(std::string(ASTROJAX_SOURCE_DIR) + "/sweeps/paper.toml");
  std::stringstream ss;
  ss << in.rdbuf();
  const SweepConfig c = parse_sweep_config(ss.str(), "sweeps/paper.toml");
  ASSERT_EQ(c.parts.size(), 6u);
  for (std::size_t i = 0; i < c.parts.size(); ++i) {
    EXPECT_EQ(c.parts[i].variant, i % 2 == 0 ? "paper" : "clutch");
    EXPECT_EQ(c.parts[i].model.layers.tie_clutch, i % 2 == 1);
    EXPECT_FALSE(c.parts[i].group_purpose.empty());
  }
  EXPECT_EQ(c.parts[0].start_seed, "hanging");
  EXPECT_EQ(c.parts[2].start_seed, "circular_high");
}
