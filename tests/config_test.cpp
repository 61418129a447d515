// Configuration: every bad input is rejected before any work with a message that names the
// file, the key and the allowed range.
#include <gtest/gtest.h>

#include <ostream>
#include <string>

#include "config/config.hpp"

using namespace ajx::config;

namespace {

const std::string kGood = R"(
[model]
string_length = 0.826
drive_radius = 0.01
contact_distance = 0.03
[layers]
friction = "kinetic"
[[schedule]]
kind = "ramp"
from = 0.0
to = 20.0
rate = 0.5
[output]
path = "out/x.h5"
)";

// Parse with one line replaced (or appended) and return the error message ("" if none).
std::string error_of(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    parse_run_config(text, "sweeps/test.toml", overrides);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return text.replace(pos, from.size(), to);
}

}  // namespace

TEST(Config, GoodFileParses) {
  const RunConfig c = parse_run_config(kGood, "sweeps/test.toml");
  EXPECT_DOUBLE_EQ(c.model.p.drive_radius, 0.01);
  ASSERT_EQ(c.schedule.size(), 1u);
  EXPECT_DOUBLE_EQ(c.schedule[0].duration, 40.0);  // |20 - 0| / 0.5
  EXPECT_EQ(c.source_text, kGood);
}

TEST(Config, OverridesApplyBeforeValidation) {
  const RunConfig c = parse_run_config(kGood, "f.toml", {"model.drive_radius=0.005", "layers.friction=none"});
  EXPECT_DOUBLE_EQ(c.model.p.drive_radius, 0.005);
  EXPECT_EQ(c.model.layers.friction, ajx::physics::Friction::None);
  const std::string e = error_of(kGood, {"model.drive_radius=2.0"});
  EXPECT_NE(e.find("model.drive_radius"), std::string::npos) << e;
}

struct BadCase {
  std::string name, from, to, key, range;
};

// Test names and failure messages show the case's name, not its bytes.
void PrintTo(const BadCase& b, std::ostream* os) { *os << b.name; }

class BadInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadInput, NamesFileKeyAndRange) {
  const BadCase& b = GetParam();
  const std::string text = b.from.empty() ? kGood + b.to : replaced(kGood, b.from, b.to);
  const std::string e = error_of(text);
  ASSERT_FALSE(e.empty()) << b.name << " was accepted";
  EXPECT_NE(e.find("sweeps/test.toml"), std::string::npos) << e;
  EXPECT_NE(e.find(b.key), std::string::npos) << e;
  EXPECT_NE(e.find(b.range), std::string::npos) << e;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadInput,
    ::testing::Values(
        BadCase{"unknown_key", "drive_radius = 0.01", "drive_radius = 0.01\nradius_of_drive = 0.01",
                "model.radius_of_drive", "unknown key"},
        BadCase{"unknown_table", "", "\n[modle]\nx = 1\n", "modle", "allowed tables"},
        BadCase{"negative_length", "string_length = 0.826", "string_length = -0.826", "model.string_length", "(0, 100]"},
        BadCase{"negative_mass", "[model]", "[model]\nbead_mass = -0.018", "model.bead_mass", "(0, inf)"},
        BadCase{"zero_mass", "[model]", "[model]\nball_mass = 0", "model.ball_mass", "(0, inf)"},
        BadCase{"R_not_below_l", "drive_radius = 0.01", "drive_radius = 0.9", "model.drive_radius", "0 <= R < l = 0.826"},
        BadCase{"negative_mu", "[model]", "[model]\nmu_kinetic = -0.1", "model.mu_kinetic", "[0, inf)"},
        BadCase{"mu_k_above_mu_s", "[model]", "[model]\nmu_kinetic = 0.5", "model.mu_kinetic", "0 <= μ_k <= μ_s"},
        BadCase{"d_not_below_l", "contact_distance = 0.03", "contact_distance = 0.826", "model.contact_distance",
                "0 < d < l = 0.826"},
        BadCase{"wrong_type", "drive_radius = 0.01", "drive_radius = \"ten mm\"", "model.drive_radius", "expected a number"},
        BadCase{"bad_friction", "friction = \"kinetic\"", "friction = \"sticky\"", "layers.friction",
                "none, kinetic, stick_slip, regularised"},
        BadCase{"restitution_above_1", "friction = \"kinetic\"", "friction = \"kinetic\"\nrestitution = 1.5",
                "layers.restitution", "[0, 1]"},
        BadCase{"zero_regularisation", "friction = \"kinetic\"", "friction = \"kinetic\"\nregularisation = 0",
                "layers.regularisation", "(0, 1000]"},
        BadCase{"stribeck_peak_unresolved", "friction = \"kinetic\"",
                "friction = \"stribeck\"\nregularisation = 1e-3\nstribeck_speed = 1e-3", "layers.stribeck_speed",
                "v_s > ε"},
        BadCase{"bad_method", "[output]", "[integrator]\nmethod = \"rk45\"\n[output]", "integrator.method",
                "euler, rk4, dopri5, dop853"},
        BadCase{"bad_rtol", "[output]", "[integrator]\nrtol = 0\n[output]", "integrator.rtol", "[1e-15, 1)"},
        BadCase{"empty_schedule",
                "[[schedule]]\nkind = \"ramp\"\nfrom = 0.0\nto = 20.0\nrate = 0.5", "", "schedule", "at least one"},
        BadCase{"reversed_ramp_rate", "rate = 0.5", "rate = -0.5", "schedule[0].rate", "(0, 10000]"},
        BadCase{"reversed_ramp_duration", "rate = 0.5", "duration = -10", "schedule[0].duration", "(0, 10000000]"},
        BadCase{"ramp_without_change", "to = 20.0", "to = 0.0", "schedule[0].to", "to != from"},
        BadCase{"negative_omega", "from = 0.0", "from = -3.0", "schedule[0].from", "[0, 2000]"},
        BadCase{"unknown_segment_key", "rate = 0.5", "rate = 0.5\nslope = 2", "schedule[0].slope", "unknown key"},
        BadCase{"bad_sample_interval", "path = \"out/x.h5\"", "path = \"out/x.h5\"\nsample_interval = 0",
                "output.sample_interval", "(0, 1000000]"},
        BadCase{"syntax_error", "", "\n[model\n", "sweeps/test.toml:", ""}),
    [](const ::testing::TestParamInfo<BadCase>& info) { return info.param.name; });

TEST(Config, HangingPresetNeedsTheBottomStop) {
  const std::string e = error_of(kGood, {"layers.bottom_stop=false"});
  EXPECT_NE(e.find("initial.preset"), std::string::npos) << e;
  EXPECT_NE(e.find("layers.bottom_stop = true"), std::string::npos) << e;
}
