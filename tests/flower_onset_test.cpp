// The Hopf fit of the flower's onset: on levels drawn from the normal form it finds ω_H, and
// its error bar covers the truth as often as a standard error should.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "sweep/flower_onset.hpp"

using ajx::sweep::fit_hopf;
using ajx::sweep::half_window_sigma;
using ajx::sweep::OnsetLevel;

namespace {
// a² = μ (k + q μ), μ = max(ω − ω_H, 0), on levels every 0.5 from 10 to 18, noise σ on each.
std::vector<OnsetLevel> levels(double wh, double k, double q, double sigma, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<OnsetLevel> out;
  for (double w = 10.0; w <= 18.0 + 1e-9; w += 0.5) {
    const double mu = std::max(w - wh, 0.0);
    out.push_back({w, mu * (k + q * mu) + noise(rng), sigma});
  }
  return out;
}
}  // namespace

TEST(FlowerOnset, ExactLevelsGiveTheHopfPointToRoundOff) {
  std::mt19937 rng(1);
  const auto lv = levels(15.3, 2e-3, 1e-4, 0.0, rng);
  std::vector<OnsetLevel> exact = lv;
  for (auto& l : exact) l.sigma = 1e-12;
  const auto fit = fit_hopf(exact, 15.5);
  ASSERT_TRUE(fit);
  EXPECT_NEAR(fit->omega_h, 15.3, 1e-6);
  EXPECT_NEAR(fit->k, 2e-3, 1e-8);
  EXPECT_NEAR(fit->q, 1e-4, 1e-8);
}

TEST(FlowerOnset, TheErrorBarCoversTheTruthLikeAStandardError) {
  // With Gaussian noise of the stated σ, |ω̂_H − ω_H| ≤ 2σ̂ in about 95 % of draws; 200 draws
  // put the observed share within ±3.5 binomial standard errors (≈ 0.05) of that.
  // The mean χ²/dof of the draws is 1 within 4 of its standard errors, √(2/dof)/√n.
  std::mt19937 rng(7);
  int covered = 0, n = 200, dof = 0;
  double chi2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const auto fit = fit_hopf(levels(15.3, 2e-3, 1e-4, 2e-4, rng), 15.5);
    ASSERT_TRUE(fit);
    chi2 += fit->reduced_chi2 / n;
    dof = fit->levels - 3;
    covered += std::abs(fit->omega_h - 15.3) <= 2 * fit->sigma;
  }
  EXPECT_NEAR(chi2, 1.0, 4.0 * std::sqrt(2.0 / dof / n));
  EXPECT_GE(double(covered) / n, 0.95 - 3.5 * std::sqrt(0.95 * 0.05 / n));
}

TEST(FlowerOnset, NeedsThreeLevelsAboveTheFirstFlower) {
  std::mt19937 rng(3);
  auto lv = levels(15.3, 2e-3, 0.0, 1e-5, rng);
  EXPECT_FALSE(fit_hopf(lv, 17.1));  // only 17.5 and 18 above
  EXPECT_TRUE(fit_hopf(lv, 17.0));
}

TEST(FlowerOnset, HalfWindowSigmaOfASteadyCircleIsZeroAndOfAGrowingOneIsNot) {
  std::vector<double> steady(100, 0.2), growing;
  for (int i = 0; i < 100; ++i) growing.push_back(0.2 + 1e-3 * i / 100.0 * std::sin(0.7 * i));
  EXPECT_EQ(half_window_sigma(steady), 0.0);
  EXPECT_GT(half_window_sigma(growing), 0.0);
  EXPECT_TRUE(std::isnan(half_window_sigma({0.2, 0.2, 0.2})));
}
