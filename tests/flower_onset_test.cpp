// The Hopf fit of the flower's onset: on levels drawn from the normal form it finds ω_H, and
// its error bar covers the truth as often as a standard error should.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
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
    const auto fit = fit_hopf(levels(15.3, 2e-3, 1e-4, 2e-4, rng), 15.5, 0);
    ASSERT_TRUE(fit);
    chi2 += fit->reduced_chi2 / n;
    dof = fit->levels - 3;
    covered += std::abs(fit->omega_h - 15.3) <= 2 * fit->sigma;
  }
  EXPECT_NEAR(chi2, 1.0, 4.0 * std::sqrt(2.0 / dof / n));
  EXPECT_GE(double(covered) / n, 0.95 - 3.5 * std::sqrt(0.95 * 0.05 / n));
}

TEST(FlowerOnset, AnUnderstatedSigmaIsScaledAndTheBootstrapSeesTheScatter) {
  // The levels scatter 5× more than their stated σ (as a level's up and down legs can agree
  // better than the level's own a² repeats): χ²/dof ≈ 25. The scaled error must match the true
  // spread of ω̂_H over draws, the unscaled one must not (the noise of
  // TheErrorBarCoversTheTruthLikeAStandardError, where the fit is close to linear; with 5× more
  // noise the fit is not, and the scaled error falls to half the spread: measured 0.78 against
  // 1.76). With 24 draws
  // the sample sd has a relative error of 1/√(2·23) ≈ 15 %, so the ratios are asserted within
  // [0.5, 1.6] (about four of those errors), and the unscaled error is 5× too small.
  std::mt19937 rng(11);
  const int n = 24;
  std::vector<double> omega;
  double scaled = 0.0, unscaled = 0.0, boot = 0.0, red = 0.0;
  for (int i = 0; i < n; ++i) {
    auto lv = levels(15.3, 2e-3, 1e-4, 2e-4, rng);
    for (auto& l : lv) l.sigma = 4e-5;  // stated 5× too small
    const auto fit = fit_hopf(lv, 15.5, 60);
    ASSERT_TRUE(fit);
    omega.push_back(fit->omega_h);
    scaled += fit->sigma / n;
    unscaled += fit->sigma_unscaled / n;
    boot += fit->sigma_bootstrap / n;
    red += fit->reduced_chi2 / n;
    EXPECT_GT(fit->bootstrap_fits, 50);
  }
  double mean = 0.0, var = 0.0;
  for (double w : omega) mean += w / n;
  for (double w : omega) var += (w - mean) * (w - mean) / (n - 1);
  const double sd = std::sqrt(var);
  std::printf("measured: χ²/dof %.1f; sd of ω̂_H %.3f, mean σ scaled %.3f, unscaled %.3f, bootstrap %.3f\n", red, sd,
              scaled, unscaled, boot);
  EXPECT_NEAR(red, 25.0, 8.0);
  EXPECT_GT(scaled / sd, 0.5);
  EXPECT_LT(scaled / sd, 1.6);
  // The bootstrap is conservative: a resample keeps on average 63 % of the distinct levels, and
  // loses some of the few above ω_H that fix the parabola (measured 2.2× the spread here): it
  // must not be below the spread, nor far above.
  EXPECT_GT(boot / sd, 0.8);
  EXPECT_LT(boot / sd, 3.5);
  EXPECT_LT(unscaled / sd, 0.35);
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
