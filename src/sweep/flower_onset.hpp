// Where the lagging circular orbit turns into a flower: the Hopf point ω_H, measured from held
// levels of a staircase that goes up through the onset and back down over the same levels.
//
// At each level the relative radius oscillation of the bottom ball over the measured window,
//   a = std(ρ2) / mean(ρ2),
// is ~1e-8 on a circle and several per cent on a flower. Near a supercritical Hopf point the
// limit cycle's amplitude follows the normal form a² = k μ, μ = ω_m − ω_H, and to the next order
//   a² = μ (k + q μ),   μ = max(ω_m − ω_H, 0).
// Each level's a² is the mean of its up and down legs: the up leg reaches the limit cycle from
// the smaller circle, the down leg from the larger flower, so the two bracket it; σ is half
// their difference combined with the window's own sampling error (half the difference of a²
// over the window's halves). k and q are linear and solved for each trial ω_H; ω_H minimises χ²
// (scan, then golden section), and σ(ω_H) is where χ² has risen by max(1, χ²/dof): the error of
// Δχ² = 1 scaled by √(χ²/dof) when the levels scatter more than their σ say. Independently of
// those σ, the spread of ω_H over resamples of the levels (a bootstrap: half its central 68 %
// range) takes the error from the scatter of the levels themselves.
#pragma once
#include <optional>
#include <vector>

namespace ajx::sweep {

inline constexpr int kBootstrapResamples = 400;  // resamples of the levels for the bootstrap

struct OnsetLevel {
  double omega;  // ω_m of the level [any unit, the fit's ω_H comes in the same]
  double a2;     // the mean of the up and down legs' a²
  double sigma;  // its error (> 0)
};

struct HopfFit {
  double omega_h = 0.0;       // the Hopf point
  double sigma = 0.0;         // its error, where χ² has risen by max(1, χ²/dof)
  double k = 0.0, q = 0.0;    // a² = μ (k + q μ)
  double reduced_chi2 = 0.0;  // χ²/dof at the optimum (dof = levels − 3)
  double sigma_unscaled = 0.0;  // where χ² has risen by 1 [the unit of ω]
  double sigma_bootstrap = 0.0; // half the central 68 % range of ω_H over resamples of the levels (NaN if none fit)
  int bootstrap_fits = 0;       // resamples that could be fitted
  int levels = 0;
};

// Needs at least three levels above the first flower (`first_flower`), which fix the parabola;
// none if there are fewer. `resamples`: of the bootstrap (0: none, sigma_bootstrap NaN).
std::optional<HopfFit> fit_hopf(const std::vector<OnsetLevel>& levels, double first_flower,
                                int resamples = kBootstrapResamples);

// The error of a² = (std/mean)² from a window's finite length: half the difference of a² over
// the window's two halves (ρ: the radius samples). NaN for fewer than 4 samples.
double half_window_sigma(const std::vector<double>& rho);

}  // namespace ajx::sweep
