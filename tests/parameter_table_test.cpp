// The parameter table reaches every place a parameter is used: [model] and its ranges, --set,
// the [grid] axes, the /chains/model columns, the continuation, the resolved configuration
// stored in files, and the configuration reference. And every key the reader reads is in the
// key catalogue, and every catalogue entry is read by some file of the repository's corpus.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <fmt/format.h>

#include "config/config.hpp"
#include "config/key_catalogue.hpp"
#include "config/resolved.hpp"
#include "orbits/continuation.hpp"
#include "physics/parameter_table.hpp"
#include "sweep/orbit_classifier.hpp"

using namespace ajx;

namespace {

const char* kSchedule = "[[schedule]]\nkind = \"hold\"\nomega = 10.0\nduration = 1.0\n";
const char* kProtocol =
    "[protocol]\n[[protocol.segment]]\nkind = \"ramp\"\nfrom = 10.0\nto = 11.0\nrate = 1.0\nwindow = 1.0\n";

// A value other than the default that keeps every cross-parameter bound (R < l, μ_k <= μ_s, ...).
// (τ_s grows instead: its default equals τ_k's, which must not exceed it.)
double other_value(const physics::ParameterInfo& p) {
  const double d = p.default_value();
  return d == 0.0 ? 1e-3 : (p.key == "tie_static_torque" ? 1.1 : 0.9) * d;
}

double resolved(const config::CommonConfig& c, const std::string& key) {
  for (const auto& s : config::resolved_settings(c))
    if (s.key == key) return std::get<double>(s.value);
  ADD_FAILURE() << key << " not in the resolved configuration";
  return NAN;
}

}  // namespace

TEST(ParameterTable, EveryParameterIsReadFromModelAndSetByOverride) {
  for (const physics::ParameterInfo& p : physics::kParameters) {
    SCOPED_TRACE(std::string(p.key));
    const double v = other_value(p);
    ASSERT_NE(v, p.default_value());
    const auto a = config::parse_run_config(fmt::format("[model]\n{} = {}\n{}", p.key, v, kSchedule), "t.toml", {});
    EXPECT_EQ(a.model.p.*p.field, v);
    const auto b = config::parse_run_config(kSchedule, "t.toml", {fmt::format("model.{}={}", p.key, v)});
    EXPECT_EQ(b.model.p.*p.field, v);
    EXPECT_EQ(resolved(b, fmt::format("model.{}", p.key)), v);
  }
}

TEST(ParameterTable, EveryParameterOutsideItsRangeIsRefusedNamingIt) {
  for (const physics::ParameterInfo& p : physics::kParameters) {
    SCOPED_TRACE(std::string(p.key));
    const double bad = p.lo_open ? p.lo : p.lo - 1.0;
    try {
      config::parse_run_config(fmt::format("[model]\n{} = {}\n{}", p.key, bad, kSchedule), "t.toml", {});
      ADD_FAILURE() << "accepted " << bad;
    } catch (const config::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(fmt::format("model.{}", p.key)), std::string::npos) << e.what();
    }
  }
}

TEST(ParameterTable, GridAxesAreTheMarkedParametersAndSetTheirChains) {
  for (const physics::ParameterInfo& p : physics::kParameters) {
    SCOPED_TRACE(std::string(p.key));
    const std::string text = fmt::format("{}[grid]\n{} = [{}]\n", kProtocol, p.key, other_value(p));
    if (!p.grid_axis) {
      EXPECT_THROW(config::parse_sweep_config(text, "t.toml", {}), config::ConfigError);
      continue;
    }
    const auto c = config::parse_sweep_config(text, "t.toml", {});
    const auto points = sweep::expand_grid(c.model, c, c.source_name);
    ASSERT_EQ(points.size(), 1u);
    EXPECT_EQ(points[0].model.p.*p.field, other_value(p));
  }
  // The alias sets both masses.
  const auto c = config::parse_sweep_config(fmt::format("{}[grid]\nmass = [0.05]\n", kProtocol), "t.toml", {});
  const auto g = sweep::expand_grid(c.model, c, c.source_name);
  EXPECT_EQ(g[0].model.p.bead_mass, 0.05);
  EXPECT_EQ(g[0].model.p.ball_mass, 0.05);
}

TEST(ParameterTable, ModelColumnsFollowTheTable) {
  physics::Parameters p;
  std::stringstream names(physics::parameter_columns());
  std::size_t j = 0;
  for (const physics::ParameterInfo& info : physics::kParameters) {
    p.*info.field = other_value(info);
    std::string name;
    ASSERT_TRUE(std::getline(names, name, ','));
    EXPECT_EQ(name.substr(0, name.find(" [")), info.key);
    EXPECT_EQ(physics::parameter_row(p).at(j++), other_value(info));
  }
  EXPECT_EQ(physics::parameter_row(p).size(), std::size(physics::kParameters));
}

TEST(ParameterTable, ContinuationParametersAreTheMarkedOnes) {
  const auto& names = orbits::continuation_parameters();
  for (const physics::ParameterInfo& p : physics::kParameters) {
    SCOPED_TRACE(std::string(p.key));
    const bool listed = std::find(names.begin(), names.end(), p.key) != names.end();
    EXPECT_EQ(listed, p.continuation);
    if (!listed) continue;
    orbits::OrbitProblem pb{};
    orbits::set_parameter(pb, p.key, 0.123);
    EXPECT_EQ(pb.model.p.*p.field, 0.123);
    EXPECT_EQ(orbits::parameter_value(pb, p.key), 0.123);
  }
}

TEST(ParameterTable, EveryParameterAndLayerIsInTheReference) {
  const std::string md = config::key_reference_markdown();
  for (const physics::ParameterInfo& p : physics::kParameters) {
    EXPECT_NE(config::find_key("model", p.key), nullptr) << p.key;
    EXPECT_NE(md.find(fmt::format("| `{}` |", p.key)), std::string::npos) << p.key;
    if (p.grid_axis) EXPECT_NE(config::find_key("grid", p.key), nullptr) << p.key;
  }
  for (const physics::LayerInfo& l : physics::layer_table()) {
    EXPECT_NE(config::find_key("layers", l.key), nullptr) << l.key;
    EXPECT_NE(md.find(fmt::format("| `{}` |", l.key)), std::string::npos) << l.key;
  }
}

TEST(ParameterTable, LayersRoundTripThroughTheResolvedConfiguration) {
  for (const physics::LayerInfo& l : physics::layer_table()) {
    SCOPED_TRACE(std::string(l.key));
    std::string value;
    std::string extra;
    using K = physics::LayerInfo::Kind;
    if (l.kind == K::Word) value = fmt::format("\"{}\"", l.words.back());
    if (l.kind == K::Boolean) value = l.default_value() == "true" ? "false" : "true";
    if (l.kind == K::Number) value = fmt::format("{}", 0.5 * l.hi);
    if (l.key == "tie") extra = "[model]\ntie_static_torque = 1e-3\ntie_kinetic_torque = 1e-3\n";
    if (l.key == "pair_couple") extra = "[model]\ncouple_torque = 1e-3\n";
    if (l.key == "bottom_stop") extra = "[initial]\npreset = \"table1\"\n";  // "hanging" needs the stop
    const auto c = config::parse_run_config(fmt::format("{}[layers]\n{} = {}\n{}", extra, l.key, value, kSchedule),
                                            "t.toml", {});
    for (const auto& s : config::resolved_settings(c))
      if (s.key == fmt::format("layers.{}", l.key)) {
        const std::string got = std::holds_alternative<double>(s.value) ? fmt::format("{}", std::get<double>(s.value))
                                                                          : std::get<std::string>(s.value);
        std::string want = value;
        want.erase(std::remove(want.begin(), want.end(), '"'), want.end());
        EXPECT_EQ(got, want);
      }
  }
}

TEST(ParameterTable, DocumentedDefaultsAreTheReadersDefaults) {
  const auto c = config::parse_run_config(kSchedule, "t.toml", {});
  for (const auto& s : config::resolved_settings(c)) {
    const auto dot = s.key.find('.');
    const config::KeyInfo* k = config::find_key(s.key.substr(0, dot), s.key.substr(dot + 1));
    ASSERT_NE(k, nullptr) << s.key;
    if (const double* v = std::get_if<double>(&s.value)) {
      char* end = nullptr;
      const double documented = std::strtod(k->fallback.c_str(), &end);
      if (end && *end == '\0' && !k->fallback.empty()) EXPECT_EQ(documented, *v) << s.key;
    } else if (k->fallback.find('"') == std::string::npos) {
      EXPECT_EQ(k->fallback, std::get<std::string>(s.value)) << s.key;
    }
  }
}

// Every configuration file of the repository, parsed as a run, a sweep and an orbits file:
// bad input ends in ConfigError, never in the reader's "key not in the catalogue"; and every
// catalogue entry is read by at least one of them (else it documents a key nobody reads, or
// the corpus misses a key: add a case to tests/data/keys/).
TEST(KeyCatalogue, EveryKeyReadIsDocumentedAndEveryDocumentedKeyIsRead) {
  namespace fs = std::filesystem;
  const fs::path src(ASTROJAX_SOURCE_DIR);
  std::size_t files = 0;
  for (const fs::path dir : {src / "sweeps", src / "tests/data", src / "tests/bad_input/files"})
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
      if (e.path().extension() != ".toml") continue;
      std::ifstream in(e.path());
      std::stringstream ss;
      ss << in.rdbuf();
      const std::string text = ss.str(), name = e.path().filename().string();
      ++files;
      for (int kind = 0; kind < 3; ++kind) try {
          if (kind == 0) config::parse_run_config(text, name, {});
          if (kind == 1) config::parse_sweep_config(text, name, {});
          if (kind == 2) config::parse_orbits_config(text, name, {});
        } catch (const config::ConfigError&) {
        } catch (const std::logic_error& e) {
          ADD_FAILURE() << name << ": " << e.what();
        }
    }
  EXPECT_GT(files, 50u);
  const auto read = config::keys_read();
  for (const config::KeyInfo& k : config::key_catalogue()) {
    if (k.section == "classifier") {  // given on the command line, not in files
      EXPECT_NO_THROW(sweep::parse_classifier_settings({fmt::format("classifier.{}=1", k.key)})) << k.key;
      continue;
    }
    EXPECT_TRUE(std::binary_search(read.begin(), read.end(), k.section + "." + k.key))
        << k.section << "." << k.key << " is never read by any file of the corpus";
  }
}
