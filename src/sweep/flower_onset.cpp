#include "sweep/flower_onset.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

namespace ajx::sweep {

namespace {

struct Fit {
  double chi2, k, q;
};

// Weighted least squares of a² = μ (k + q μ) at a trial ω_H.
Fit fit_at(const std::vector<OnsetLevel>& lv, double omega_h) {
  const long n = long(lv.size());
  Eigen::MatrixXd A(n, 2);
  Eigen::VectorXd b(n);
  for (long i = 0; i < n; ++i) {
    const double mu = std::max(lv[std::size_t(i)].omega - omega_h, 0.0), w = 1.0 / lv[std::size_t(i)].sigma;
    A(i, 0) = w * mu;
    A(i, 1) = w * mu * mu;
    b(i) = w * lv[std::size_t(i)].a2;
  }
  const Eigen::Vector2d c = A.completeOrthogonalDecomposition().solve(b);
  return {(A * c - b).squaredNorm(), c(0), c(1)};
}

// The minimum of f on [lo, hi]: the best of n samples, then golden section between its neighbours.
template <class F>
double scan_and_refine(F f, double lo, double hi, int n) {
  const double step = (hi - lo) / (n - 1);
  int best = 0;
  double fb = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i)
    if (const double v = f(lo + i * step); v < fb) fb = v, best = i;
  double a = lo + std::max(best - 1, 0) * step, b = lo + std::min(best + 1, n - 1) * step;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int it = 0; it < 100 && b - a > 1e-12 * std::max(1.0, std::abs(a)); ++it) {
    const double x1 = b - g * (b - a), x2 = a + g * (b - a);
    if (f(x1) < f(x2))
      b = x2;
    else
      a = x1;
  }
  return 0.5 * (a + b);
}

// ω_H alone: the minimum of χ² below the third-highest level.
double best_omega(const std::vector<OnsetLevel>& levels) {
  std::vector<double> om;
  for (const OnsetLevel& l : levels) om.push_back(l.omega);
  std::sort(om.begin(), om.end());
  const double lo = om.front() - (om.back() - om.front()), hi = om[om.size() - 3];
  return scan_and_refine([&](double w) { return fit_at(levels, w).chi2; }, lo, hi, 400);
}

// Where χ² (of the fit at ω) reaches `target` on the side `dir` of the optimum w0: expand, then bisect.
template <class F>
double chi2_crossing(F chi2, double w0, double target, double dir, double reach) {
  double step = 1e-4 * std::max(std::abs(w0), 1.0), x = w0;
  while (chi2(x + dir * step) < target && std::abs(x - w0) < reach) {
    x += dir * step;
    step *= 1.5;
  }
  double a = std::min(x, x + dir * step), b = std::max(x, x + dir * step);
  for (int i = 0; i < 60; ++i) {
    const double m = 0.5 * (a + b);
    ((chi2(m) < target) == (dir > 0) ? a : b) = m;
  }
  return 0.5 * (a + b);
}

// The spread of ω_H over resamples of the levels with replacement (a fixed seed: the
// same file gives the same number); a resample without three distinct levels at or above the
// first flower cannot fix the parabola and is skipped.
void bootstrap(const std::vector<OnsetLevel>& levels, double first_flower, int resamples, HopfFit& out) {
  std::mt19937_64 rng(20261128);
  std::uniform_int_distribution<std::size_t> pick(0, levels.size() - 1);
  std::vector<double> found;
  for (int r = 0; r < resamples; ++r) {
    std::vector<OnsetLevel> sample;
    std::vector<double> above;
    for (std::size_t i = 0; i < levels.size(); ++i) {
      sample.push_back(levels[pick(rng)]);
      if (sample.back().omega >= first_flower) above.push_back(sample.back().omega);
    }
    std::sort(above.begin(), above.end());
    if (std::unique(above.begin(), above.end()) - above.begin() < 3) continue;
    found.push_back(best_omega(sample));
  }
  out.bootstrap_fits = int(found.size());
  out.sigma_bootstrap = std::numeric_limits<double>::quiet_NaN();
  if (found.size() < 2) return;
  // Half the central 68 % range: a resample that drops the few levels above ω_H fixes the
  // parabola poorly, and such tails would dominate a standard deviation.
  std::sort(found.begin(), found.end());
  const auto quantile = [&](double q) {
    const double x = q * double(found.size() - 1);
    const std::size_t i = std::size_t(x);
    return i + 1 < found.size() ? found[i] + (x - double(i)) * (found[i + 1] - found[i]) : found.back();
  };
  out.sigma_bootstrap = 0.5 * (quantile(0.8413) - quantile(0.1587));
}

}  // namespace

std::optional<HopfFit> fit_hopf(const std::vector<OnsetLevel>& levels, double first_flower, int resamples) {
  const long above = std::count_if(levels.begin(), levels.end(), [&](const OnsetLevel& l) { return l.omega >= first_flower; });
  if (above < 3) return std::nullopt;
  std::vector<double> om;
  for (const OnsetLevel& l : levels) om.push_back(l.omega);
  std::sort(om.begin(), om.end());
  // ω_H lies below the third-highest level (three points above it fix the parabola).
  const double lo = om.front() - (om.back() - om.front()), hi = om[om.size() - 3];
  const auto chi2 = [&](double w) { return fit_at(levels, w).chi2; };
  HopfFit out;
  out.omega_h = scan_and_refine(chi2, lo, hi, 400);
  const Fit best = fit_at(levels, out.omega_h);
  const int dof = int(levels.size()) - 3;
  out.reduced_chi2 = dof > 0 ? best.chi2 / dof : std::numeric_limits<double>::quiet_NaN();
  const double target = best.chi2 + std::max(dof > 0 ? out.reduced_chi2 : 1.0, 1.0);
  const double reach = 10 * (hi - lo);
  out.sigma = 0.5 * (chi2_crossing(chi2, out.omega_h, target, +1.0, reach) -
                     chi2_crossing(chi2, out.omega_h, target, -1.0, reach));
  out.sigma_unscaled = 0.5 * (chi2_crossing(chi2, out.omega_h, best.chi2 + 1.0, +1.0, reach) -
                              chi2_crossing(chi2, out.omega_h, best.chi2 + 1.0, -1.0, reach));
  bootstrap(levels, first_flower, resamples, out);
  out.k = best.k;
  out.q = best.q;
  out.levels = int(levels.size());
  return out;
}

double half_window_sigma(const std::vector<double>& rho) {
  const std::size_t h = rho.size() / 2;
  if (h < 2) return std::numeric_limits<double>::quiet_NaN();
  const auto a2 = [](auto first, auto last) {
    const double n = double(last - first);
    const double mean = std::accumulate(first, last, 0.0) / n;
    double var = 0.0;
    for (auto it = first; it != last; ++it) var += (*it - mean) * (*it - mean);
    return var / n / (mean * mean);
  };
  return 0.5 * std::abs(a2(rho.begin(), rho.begin() + long(h)) - a2(rho.begin() + long(h), rho.end()));
}

}  // namespace ajx::sweep
