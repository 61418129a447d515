// Friction laws at the bead: capstan and the corrected point contact.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "physics/string_friction.hpp"

using namespace ajx::physics;

TEST(StringFriction, DeflectionOfUnitVectors) {
  EXPECT_DOUBLE_EQ(deflection(Vec3::UnitZ(), Vec3::UnitZ()), 0.0);
  EXPECT_NEAR(deflection(Vec3::UnitZ(), Vec3::UnitX()), M_PI / 2, 1e-15);
  // Accurate near 0, where arccos loses half the digits.
  const double a = 1e-9;
  EXPECT_NEAR(deflection(Vec3(0, 0, -1), Vec3(std::sin(a), 0, -std::cos(a))), a, 1e-22);
}

TEST(StringFriction, StraightStringOrNoSlipHasNoFriction) {
  for (auto law : {FrictionLaw::Capstan, FrictionLaw::PointContact}) {
    EXPECT_EQ(tension_ratio(law, 0.2, 0.0, +1), 1.0);
    EXPECT_EQ(tension_ratio(law, 0.2, 1.0, 0), 1.0);
    EXPECT_EQ(tension_ratio(law, 0.0, 1.0, -1), 1.0);
  }
}

TEST(StringFriction, CapstanRatiosAreReciprocal) {
  const double mu = 0.17176;
  for (double psi : {0.1, 1.0, 2.5, 3.1}) {
    EXPECT_NEAR(tension_ratio(FrictionLaw::Capstan, mu, psi, +1) * tension_ratio(FrictionLaw::Capstan, mu, psi, -1),
                1.0, 1e-15);
    EXPECT_NEAR(tension_ratio(FrictionLaw::Capstan, mu, psi, +1), std::exp(mu * psi), 1e-15);
  }
}

TEST(StringFriction, PointContactAgreesWithCapstanToSecondOrder) {
  // Both expand as 1 + μσψ + μ²ψ²/2 + O(ψ³): the difference must shrink 8× per halving of ψ.
  const double mu = 0.25;
  double prev = 0.0;
  for (double psi = 0.4; psi > 0.01; psi /= 2) {
    const double diff = std::abs(tension_ratio(FrictionLaw::PointContact, mu, psi, +1) -
                                 tension_ratio(FrictionLaw::Capstan, mu, psi, +1));
    if (prev > 0.0) {
      EXPECT_NEAR(std::log2(prev / diff), 3.0, 0.15) << "psi = " << psi;
    }
    prev = diff;
  }
}

TEST(StringFriction, FrictionPowerIsNeverNegative) {
  // (T1 - T2) ṡ = (κ - 1) T2 ṡ >= 0 for T2 >= 0 and σ = sgn ṡ: κ > 1 exactly when σ > 0.
  for (auto law : {FrictionLaw::Capstan, FrictionLaw::PointContact})
    for (double psi : {0.01, 0.5, 1.5, 2.5})
      for (int sigma : {-1, +1}) {
        const double kappa = tension_ratio(law, 0.3, psi, sigma);
        EXPECT_GE((kappa - 1.0) * sigma, 0.0);
      }
}

TEST(StringFriction, PointContactJamsWhenTheConeIsTooWide) {
  const double mu = 0.5;
  const double psi_jam = 2 * std::atan(1 / mu);  // μ tan(ψ/2) = 1
  EXPECT_NO_THROW(tension_ratio(FrictionLaw::PointContact, mu, 0.99 * psi_jam, +1));
  EXPECT_THROW(tension_ratio(FrictionLaw::PointContact, mu, 1.01 * psi_jam, +1), std::domain_error);
  EXPECT_THROW(tension_ratio(FrictionLaw::PointContact, mu, 1.01 * psi_jam, -1), std::domain_error);
  const FrictionCone cone = friction_cone(FrictionLaw::PointContact, mu, 1.01 * psi_jam);
  EXPECT_EQ(cone.lo, 0.0);
  EXPECT_EQ(cone.hi, std::numeric_limits<double>::infinity());
  // The capstan law is well posed for every ψ.
  EXPECT_NO_THROW(tension_ratio(FrictionLaw::Capstan, mu, 3.1, +1));
}

namespace {
// The paper's coefficients, with the Stribeck layer at ε ≪ v_s.
Model stribeck(double eps, double v_s) {
  Model m;
  m.layers.friction = Friction::Stribeck;
  m.layers.regularisation = eps;
  m.layers.stribeck_speed = v_s;
  return m;
}
}  // namespace

TEST(StringFriction, StribeckPeaksNearMuStaticAndTendsToMuKinetic) {
  // f(v) = [μ_k + Δ e^{-(v/v_s)²}] tanh(v/ε), Δ = μ_s − μ_k. Both factors stay below their
  // bounds, so f < μ_s everywhere; at v = kε, f >= μ_s − Δ (kε/v_s)² − μ_s (1 − tanh k), which
  // for k = 5 and ε/v_s = 1e-3 bounds the peak from below. For v ≫ v_s, |f − μ_k| <=
  // Δ e^{-(v/v_s)²} + μ_k (1 − tanh(v/ε)).
  const double eps = 1e-5, v_s = 1e-2;
  const Model m = stribeck(eps, v_s);
  const double mu_s = m.p.mu_static, mu_k = m.p.mu_kinetic, delta = mu_s - mu_k;
  double peak = 0.0, v_peak = 0.0;
  for (double v = 1e-8; v < 1.0; v *= 1.01) {
    const double f = regularised_coefficient(m, v);
    ASSERT_LT(f, mu_s) << "v = " << v;
    if (f > peak) peak = f, v_peak = v;
  }
  const double k = 5.0;
  EXPECT_GE(peak, mu_s - delta * std::pow(k * eps / v_s, 2) - mu_s * (1.0 - std::tanh(k)));
  EXPECT_GT(v_peak, eps);
  EXPECT_LT(v_peak, 10 * k * eps);
  for (double v : {5 * v_s, 10 * v_s, 1.0}) {
    const double bound = delta * std::exp(-std::pow(v / v_s, 2)) + mu_k * (1.0 - std::tanh(v / eps));
    EXPECT_NEAR(regularised_coefficient(m, v), mu_k, bound + 1e-16) << "v = " << v;
  }
  // The tanh law, by contrast, never exceeds μ_k.
  Model tanh_law = m;
  tanh_law.layers.friction = Friction::Regularised;
  for (double v = 1e-8; v < 1.0; v *= 1.1) EXPECT_LE(regularised_coefficient(tanh_law, v), mu_k);
}

TEST(StringFriction, StribeckIsOddAndDissipative) {
  // f(−v) = −f(v) exactly (exp(−x²) is even, tanh is odd), f(0) = 0, and the friction power
  // (T1 − T2) ṡ = (κ − 1) T2 ṡ is never negative for either law of κ.
  const Model m = stribeck(1e-3, 1e-2);
  EXPECT_EQ(regularised_coefficient(m, 0.0), 0.0);
  for (double v = 1e-7; v < 10.0; v *= 1.37) {
    EXPECT_EQ(regularised_coefficient(m, -v), -regularised_coefficient(m, v)) << "v = " << v;
    for (auto law : {FrictionLaw::Capstan, FrictionLaw::PointContact})
      for (double sdot : {v, -v}) {
        const double kappa = tension_ratio(law, regularised_mu(m, sdot), 1.0, regularised_sigma(m, sdot));
        EXPECT_GE((kappa - 1.0) * sdot, 0.0);
      }
  }
}
