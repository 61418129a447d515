// Attractors matched across ω_m (sweep/basin_match.hpp): the half-widths are the orbit's measured
// swing plus the classifier's drift tolerances; two locked orbits with the bead stuck at different
// places s are two attractors, and each keeps its label across a level step larger than its bands;
// a flower's stuck bead place within its swing does not split it; fallen is one attractor whatever
// its features; single linkage joins a continuum; between levels, an attractor further than the
// distance bound starts a new label, coexisting families keep theirs, and a vanished one is taken up.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "sweep/basin_match.hpp"
#include "sweep/orbit_classifier.hpp"

using namespace ajx::sweep;

namespace {

constexpr double pi = std::numbers::pi, l = 0.826;
const DriftTolerances kDrift = [] {
  const ClassifierSettings c;
  return DriftTolerances{c.radius_drift_tol, c.omega_drift_tol, c.L1_drift_tol};
}();
const std::int32_t locked = std::int32_t(OrbitClass::LockedCircular), fallen = std::int32_t(OrbitClass::Fallen);

// A settled locked orbit at ω_m: ω_ball = ω_m, radii ρ1, ρ2, the bead stuck at s; a window
// whose statistics swing by `swing` (a residual oscillation left from the start).
WindowFeatures locked_window(double omega, double rho1, double rho2, double s, double swing = 1e-4) {
  return {omega, omega, omega, rho1, swing, rho2, swing, s, swing};
}

std::vector<std::string> names() {
  std::vector<std::string> n;
  for (const auto& c : kOrbitClasses) n.emplace_back(c.name);
  return n;
}

BasinMatch match(const std::vector<MatchLevel>& levels, const std::vector<MatchSample>& s) {
  bool split[kNumOrbitClasses];
  for (std::size_t k = 0; k < kNumOrbitClasses; ++k) split[k] = basin_split_class(OrbitClass(k));
  const std::vector<std::string> n = names();
  return match_attractors(levels, s, std::span<const bool>(split, kNumOrbitClasses), n);
}

}  // namespace

TEST(BasinMatch, HalfWidthsAreTheMeasuredSwingPlusTheDriftTolerances) {
  const MatchSample m = match_sample(0, locked, {10.0, 10.2, 9.8, 0.14, 0.001, 0.12, 0.002, 0.54, 0.003}, kDrift, l);
  EXPECT_DOUBLE_EQ(m.x[0], std::log(10.0));
  EXPECT_DOUBLE_EQ(m.x[3], 0.54 / l);
  // h_ω = |ω_bead − ω_bottom|/(2 ω_ball) + δ_ω; h_ρ = (e + δ_ρ ρ̄)/l; h_s = (e + δ_s l)/l with
  // e = √2 max(σ_ρ1, σ_ρ2, σ_s), the orbit's extent in the string's configuration (here σ_s's).
  const double e = std::sqrt(2.0) * 0.003;
  EXPECT_NEAR(m.h[0], 0.4 / 20.0 + kDrift.omega, 1e-15);  // 10.2 − 9.8 rounds
  EXPECT_DOUBLE_EQ(m.h[1], (e + kDrift.radius * 0.14) / l);
  EXPECT_DOUBLE_EQ(m.h[2], (e + kDrift.radius * 0.12) / l);
  EXPECT_DOUBLE_EQ(m.h[3], (e + kDrift.L1 * l) / l);
  // An undefined ω_ball (balls on the axis): no feature, no swing of it.
  const MatchSample u = match_sample(0, locked, {NAN, NAN, NAN, 0.01, 0.0, 0.01, 0.0, 0.5, 0.0}, kDrift, l);
  EXPECT_TRUE(std::isnan(u.x[0]));
  EXPECT_FALSE(same_orbit(u, m));
}

TEST(BasinMatch, TwoLockedOrbitsWithDifferentPlacesOfTheBeadAreTwoAttractorsAndKeepTheirLabelsAcrossALevelStep) {
  // Level 0 at 4.13π: the bead stuck at s = 0.54 m (Table 1's orbit) or at 0.67 m (lower on the
  // string, smaller radii), 5 starts each scattered within their windows' swing.
  const double w0 = 4.13 * pi, w1 = 5.2 * pi;
  std::vector<MatchSample> s;
  for (int k = 0; k < 5; ++k) {
    const double e = 2e-4 * (k - 2);
    s.push_back(match_sample(0, locked, locked_window(w0, 0.144 + e, 0.119 + e, 0.540 + e), kDrift, l));
    s.push_back(match_sample(0, locked, locked_window(w0, 0.070 + e, 0.060 + e, 0.670 + e), kDrift, l));
  }
  // Level 1 at 5.2π: both orbits continued: ω_ball = ω_m moved by ln(5.2/4.13) = 0.23, far more
  // than their bands (2 % each), the bead a centimetre further down.
  for (int k = 0; k < 5; ++k) {
    const double e = 2e-4 * (k - 2);
    s.push_back(match_sample(1, locked, locked_window(w1, 0.150 + e, 0.125 + e, 0.550 + e), kDrift, l));
    s.push_back(match_sample(1, locked, locked_window(w1, 0.075 + e, 0.064 + e, 0.680 + e), kDrift, l));
  }
  s.push_back(match_sample(1, -1, locked_window(w1, 0.1, 0.1, 0.6), kDrift, l));  // not computed
  ASSERT_FALSE(same_orbit(s[0], s[10])) << "the level step moves the orbit beyond its bands";
  ASSERT_FALSE(same_orbit(s[0], s[1])) << "the two places of the bead are told apart";
  const BasinMatch m = match({{0, w0}, {0, w1}}, s);
  ASSERT_EQ(m.attractors.size(), 2u);
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(m.label[std::size_t(2 * k)], m.label[0]);
    EXPECT_EQ(m.label[std::size_t(2 * k + 1)], m.label[1]);
    EXPECT_EQ(m.label[std::size_t(10 + 2 * k)], m.label[0]) << "s = 0.54 m keeps its label at the next level";
    EXPECT_EQ(m.label[std::size_t(11 + 2 * k)], m.label[1]) << "s = 0.67 m keeps its label at the next level";
  }
  EXPECT_NE(m.label[0], m.label[1]);
  EXPECT_EQ(m.label.back(), -1);
  EXPECT_EQ(m.attractors[std::size_t(m.label[0])].name, "locked-circular A");
  EXPECT_EQ(m.attractors[std::size_t(m.label[1])].name, "locked-circular B");
}

TEST(BasinMatch, OneToOneTheNearestFirstAndANewLabelForAnOrbitWithoutPartner) {
  const double w0 = 5.0 * pi, w1 = 5.5 * pi;
  std::vector<MatchSample> s{match_sample(0, locked, locked_window(w0, 0.10, 0.08, 0.60), kDrift, l),
                             match_sample(1, locked, locked_window(w1, 0.20, 0.18, 0.30), kDrift, l),
                             match_sample(1, locked, locked_window(w1, 0.11, 0.09, 0.61), kDrift, l)};
  const BasinMatch m = match({{0, w0}, {0, w1}}, s);
  EXPECT_EQ(m.label[2], m.label[0]) << "the nearer takes the label";
  EXPECT_NE(m.label[1], m.label[0]) << "the other is a new attractor";
  // Another part (variant) has its own labels, even where its orbits are the same.
  std::vector<MatchSample> t = s;
  t[0].level = 2;
  const BasinMatch p = match({{0, w0}, {0, w1}, {1, w0}}, t);
  EXPECT_EQ(p.attractors[std::size_t(p.label[0])].part, 1);
  EXPECT_EQ(p.attractors[std::size_t(p.label[0])].name, "locked-circular");
}

TEST(BasinMatch, FallenIsOneAttractorWhateverItsFeaturesAndAContinuumIsJoined) {
  std::vector<MatchSample> s;
  for (int k = 0; k < 4; ++k)  // leftover swings from 1 to 30 cm: one attractor at every level
    for (int lev = 0; lev < 2; ++lev)
      s.push_back(match_sample(lev, fallen, {NAN, NAN, NAN, 0.01 + 0.1 * k, 0.01, 0.01 + 0.1 * k, 0.01, 0.79, 1e-4},
                               kDrift, l));
  // A chain of locked orbits 3 mm apart in s, each band a centimetre wide: single linkage joins
  // them into one attractor although the ends are 3 cm apart.
  const double w = 4.5 * pi;
  for (int k = 0; k < 10; ++k)
    s.push_back(match_sample(0, locked, locked_window(w, 0.12, 0.10, 0.50 + 0.003 * k), kDrift, l));
  ASSERT_FALSE(same_orbit(s[8], s[17]));
  const BasinMatch m = match({{0, w}, {0, 5.0 * pi}}, s);
  std::set<std::int32_t> fallen_labels, locked_labels;
  for (std::size_t i = 0; i < 8; ++i) fallen_labels.insert(m.label[i]);
  for (std::size_t i = 8; i < s.size(); ++i) locked_labels.insert(m.label[i]);
  EXPECT_EQ(fallen_labels.size(), 1u);
  EXPECT_EQ(locked_labels.size(), 1u);
  EXPECT_EQ(m.attractors[std::size_t(m.label[0])].name, "fallen");
}

namespace {

const std::int32_t flower = std::int32_t(OrbitClass::Flower);

// A flower: ω_ball, mean radii swinging by ±√2 σ, the bead stuck at s (σ_s = 0).
WindowFeatures flower_window(double omega_ball, double rho, double sigma, double s) {
  return {omega_ball, omega_ball, omega_ball, rho, sigma, 0.8 * rho, sigma, s, 0.0};
}

std::set<std::int32_t> labels_of(const BasinMatch& m, std::size_t from, std::size_t to) {
  std::set<std::int32_t> out;
  for (std::size_t i = from; i < to; ++i) out.insert(m.label[i]);
  return out;
}

}  // namespace

TEST(BasinMatch, AStuckBeadPlaceWithinAFlowersSwingIsOneFlowerButNotWithinALockedOrbits) {
  // The clutch's flowers at 6.27π: radii swinging by ±10 cm, the bead stuck 4 cm apart from one
  // start to the next (s from 0.45 to 0.57 m): one attractor. Locked orbits with the same places
  // and no swing are four (4 cm against bands of ±8 mm).
  const double w = 6.27 * pi;
  std::vector<MatchSample> s;
  for (int k = 0; k < 4; ++k) s.push_back(match_sample(0, flower, flower_window(1.33 * pi, 0.18, 0.07, 0.45 + 0.04 * k), kDrift, l));
  for (int k = 0; k < 4; ++k) s.push_back(match_sample(0, locked, locked_window(w, 0.12, 0.10, 0.45 + 0.04 * k), kDrift, l));
  const BasinMatch m = match({{0, w}}, s);
  EXPECT_EQ(labels_of(m, 0, 4).size(), 1u);
  EXPECT_EQ(labels_of(m, 4, 8).size(), 4u);
}

TEST(BasinMatch, AnAttractorBeyondTheDistanceBoundStartsANewLabelEvenAlone) {
  // A flower at 5.2π turning at ω_ball = 4.2π; at 6.27π the only flower turns at 1.33π: ln ω_ball
  // moved by 1.15, beyond its bands and beyond ln(6.27/5.2) = 0.19, the most a continued orbit's
  // ω_ball moves: a new attractor, not the old one's continuation.
  std::vector<MatchSample> s{match_sample(0, flower, flower_window(4.2 * pi, 0.18, 0.07, 0.42), kDrift, l),
                             match_sample(1, flower, flower_window(1.33 * pi, 0.18, 0.07, 0.45), kDrift, l),
                             match_sample(2, flower, flower_window(1.32 * pi, 0.19, 0.07, 0.47), kDrift, l)};
  const BasinMatch m = match({{0, 5.2 * pi}, {0, 6.27 * pi}, {0, 7.33 * pi}}, s);
  EXPECT_NE(m.label[1], m.label[0]);
  EXPECT_EQ(m.label[2], m.label[1]) << "the slow flower continues from 6.27π to 7.33π";
  EXPECT_EQ(m.attractors.size(), 2u);
}

TEST(BasinMatch, TwoCoexistingFamiliesKeepTheirLabelsAndAVanishedOneIsTakenUpAgain) {
  // Two families of flowers coexist at 5.2π to 7.33π (ω_ball 4.1π with s = 0.46 m, and 1.3π with
  // the bead lower); the slow one vanishes at 8.4π to 15π and is seen again at 16.9π.
  const std::vector<MatchLevel> levels{{0, 5.2 * pi}, {0, 6.27 * pi}, {0, 7.33 * pi}, {0, 8.4 * pi}, {0, 16.93 * pi}};
  std::vector<MatchSample> s;
  for (int lev = 0; lev < 3; ++lev) {
    s.push_back(match_sample(lev, flower, flower_window(4.1 * pi, 0.19, 0.02, 0.46), kDrift, l));
    s.push_back(match_sample(lev, flower, flower_window(1.3 * pi, 0.17, 0.08, 0.50 + 0.01 * lev), kDrift, l));
  }
  s.push_back(match_sample(3, locked, locked_window(8.4 * pi, 0.1, 0.08, 0.7), kDrift, l));
  s.push_back(match_sample(4, flower, flower_window(1.28 * pi, 0.13, 0.05, 0.55), kDrift, l));
  const BasinMatch m = match(levels, s);
  for (int lev = 1; lev < 3; ++lev) {
    EXPECT_EQ(m.label[std::size_t(2 * lev)], m.label[0]);
    EXPECT_EQ(m.label[std::size_t(2 * lev + 1)], m.label[1]);
  }
  EXPECT_NE(m.label[0], m.label[1]);
  EXPECT_EQ(m.label.back(), m.label[1]) << "the slow flower's label, last seen at 7.33π";
  EXPECT_EQ(m.attractors[std::size_t(m.label[0])].name, "flower A");
  EXPECT_EQ(m.attractors[std::size_t(m.label[1])].name, "flower B");
}
