// The orbit classifier; the criteria are documented in orbit_classifier.hpp.
#include "sweep/orbit_classifier.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "physics/model.hpp"

namespace ajx::sweep {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = std::numbers::pi;

// Samples [b, e).
struct Range {
  std::size_t b = 0, e = 0;
  std::size_t size() const { return e - b; }
};

template <class Get>
Moments moments_of(Range r, Get x) {
  Moments m;
  if (r.size() == 0) return m;
  double s = 0, lo = x(r.b), hi = x(r.b);
  for (std::size_t k = r.b; k < r.e; ++k) {
    const double v = x(k);
    s += v;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  m.mean = s / double(r.size());
  double q = 0;
  for (std::size_t k = r.b; k < r.e; ++k) q += (x(k) - m.mean) * (x(k) - m.mean);
  m.std = std::sqrt(q / double(r.size()));
  m.min = lo;
  m.max = hi;
  return m;
}

double mean_of(std::span<const double> x, Range r) {
  return moments_of(r, [&](std::size_t k) { return x[k]; }).mean;
}

// Least-squares line y ≈ mean_y + slope (t − mean_t), centred for accuracy at large t.
struct Fit {
  double slope = kNaN, mean_t = kNaN, mean_y = kNaN, res_std = kNaN;
  double at(double t) const { return mean_y + slope * (t - mean_t); }
};

Fit fit_line(std::span<const double> t, std::span<const double> y, Range r) {
  Fit f;
  if (r.size() < 2) return f;
  double st = 0, sy = 0;
  for (std::size_t k = r.b; k < r.e; ++k) {
    st += t[k];
    sy += y[k];
  }
  f.mean_t = st / double(r.size());
  f.mean_y = sy / double(r.size());
  double sxx = 0, sxy = 0;
  for (std::size_t k = r.b; k < r.e; ++k) {
    const double dt = t[k] - f.mean_t;
    sxx += dt * dt;
    sxy += dt * (y[k] - f.mean_y);
  }
  f.slope = sxx > 0 ? sxy / sxx : 0.0;
  double q = 0;
  for (std::size_t k = r.b; k < r.e; ++k) {
    const double e = y[k] - f.at(t[k]);
    q += e * e;
  }
  f.res_std = std::sqrt(q / double(r.size()));
  return f;
}

// Oscillation cycles of y about its trend: sign changes of the residual, counted with a
// hysteresis of half its standard deviation, halved.
double cycles_about(std::span<const double> t, std::span<const double> y, const Fit& f) {
  if (!(f.res_std > 0)) return 0.0;
  const double h = 0.5 * f.res_std;
  int state = 0;
  long flips = 0;
  for (std::size_t k = 0; k < y.size(); ++k) {
    const double e = y[k] - f.at(t[k]);
    const int s = e > h ? 1 : (e < -h ? -1 : 0);
    if (s != 0 && s != state) {
      if (state != 0) ++flips;
      state = s;
    }
  }
  return 0.5 * double(flips);
}

// A scalar signal over the window, with its change between halves.
struct Signal {
  Moments all;
  Fit fit;
  double amplitude = kNaN;  // √2 × residual std
  double cycles = kNaN;     // oscillation cycles in the window
  double mean1 = kNaN, mean2 = kNaN, std1 = kNaN, std2 = kNaN;
  double mean_allowance = 0;  // bound on |mean2 − mean1| from the oscillation alone
};

Signal analyse(std::span<const double> t, std::span<const double> y, std::size_t half, double min_cycles) {
  Signal s;
  const Range all{0, y.size()}, h1{0, half}, h2{half, y.size()};
  auto get = [&](std::size_t k) { return y[k]; };
  s.all = moments_of(all, get);
  s.fit = fit_line(t, y, all);
  s.amplitude = std::sqrt(2.0) * s.fit.res_std;
  s.cycles = cycles_about(t, y, s.fit);
  const Moments m1 = moments_of(h1, get), m2 = moments_of(h2, get);
  s.mean1 = m1.mean;
  s.mean2 = m2.mean;
  s.std1 = m1.std;
  s.std2 = m2.std;
  // Each half holds n/2 cycles; its mean is off by at most a/(π n/2); two halves.
  if (s.cycles >= min_cycles) s.mean_allowance = 2.0 * s.amplitude / (kPi * 0.5 * s.cycles);
  return s;
}

double clamp01(double x) { return std::isfinite(x) ? std::clamp(x, 0.0, 1.0) : 0.0; }
// Margin of q ≤ X: 0 at X, 1 at X/2.  Margin of q ≥ X (or of exceeding X): 0 at X, 1 at 1.5 X.
double upper_margin(double q, double X) { return X > 0 ? clamp01((X - q) / (0.5 * X)) : (q <= X ? 1.0 : 0.0); }
double lower_margin(double q, double X) { return X > 0 ? clamp01((q - X) / (0.5 * X)) : (q >= X ? 1.0 : 0.0); }

// One steadiness test: quantity q must stay ≤ X.
struct Test {
  std::string what;
  double q, X;
};

bool all_finite(std::span<const double> x) {
  return std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); });
}

void check_sizes(const OrbitWindow& w) {
  const std::size_t N = w.t.size();
  const auto size_error = [](const char* what) {
    throw std::invalid_argument(fmt::format("classify_orbit: {} has the wrong number of values", what));
  };
  if (w.omega_m.size() != N) size_error("omega_m");
  if (w.r1.size() != 3 * N) size_error("r1 (3N)");
  if (w.r2.size() != 3 * N) size_error("r2 (3N)");
  if (w.L1.size() != N) size_error("L1");
  if (!w.T1.empty() && w.T1.size() != N) size_error("T1");
  if (!w.T2.empty() && w.T2.size() != N) size_error("T2");
  if (!w.mode.empty() && w.mode.size() != N) size_error("mode");
  for (std::size_t k = 1; k < N; ++k)
    if (w.t[k] < w.t[k - 1]) throw std::invalid_argument("classify_orbit: t must not decrease");
}

// ---- features: the statistics of the window (OrbitStats) -----------------------------------

// The motor, the string, the tensions, the modes and the bead on the bottom ball.
void string_features(const OrbitWindow& w, const OrbitScales& sc, const ClassifierSettings& cfg, std::size_t half,
                     OrbitStats& st) {
  const std::size_t N = w.t.size();
  const Range all{0, N}, h1{0, half}, h2{half, N};
  st.omega_m = moments_of(all, [&](std::size_t k) { return w.omega_m[k]; });
  const double l = sc.string_length, d = sc.contact_distance;
  const Signal L1 = analyse(w.t, w.L1, half, cfg.min_cycles);
  st.L1 = L1.all;
  st.L1_half_change = (L1.mean2 - L1.mean1) / l;
  st.L1_half_allowance = L1.mean_allowance / l;
  if (!w.T1.empty()) st.T1 = moments_of(all, [&](std::size_t k) { return w.T1[k]; });
  if (!w.T2.empty()) st.T2 = moments_of(all, [&](std::size_t k) { return w.T2[k]; });
  if (!w.mode.empty()) {
    std::array<long, 5> count{};
    for (int m : w.mode)
      if (m >= 0 && m < 5) ++count[std::size_t(m)];
    for (std::size_t m = 0; m < 5; ++m) st.mode_fraction[m] = double(count[m]) / double(N);
  }
  const auto on_ball = [&](std::size_t k) {
    return (!w.mode.empty() && w.mode[k] == 1) || std::abs(l - w.L1[k] - d) <= cfg.on_ball_tol * d;
  };
  const auto on_ball_fraction = [&](Range r) {
    long n = 0;
    for (std::size_t k = r.b; k < r.e; ++k) n += on_ball(k) ? 1 : 0;
    return double(n) / double(r.size());
  };
  st.on_ball_fraction = on_ball_fraction(all);
  st.on_ball_first = on_ball_fraction(h1);
  st.on_ball_second = on_ball_fraction(h2);
}

// One ball's radius, height and unwrapped azimuth from its positions r (3N). wm1, wm2: the
// mean ω_m of the two halves; omega_m: over the window.
void ball_features(const OrbitWindow& w, std::span<const double> r, const ClassifierSettings& cfg, std::size_t half,
                   double wm1, double wm2, double omega_m, BallStats& b) {
  const std::size_t N = w.t.size();
  const Range all{0, N}, h1{0, half}, h2{half, N};
  const double tau = 0.5 * (w.t[N - 1] - w.t[0]);
  std::vector<double> rho(N), z(N), theta(N);
  const double step_limit = 2 * kPi / cfg.min_samples_per_turn * (1 + 1e-9);
  double max_step = 0, prev = 0;
  long under = 0;
  for (std::size_t k = 0; k < N; ++k) {
    const double x = r[3 * k], y = r[3 * k + 1];
    rho[k] = std::hypot(x, y);
    z[k] = r[3 * k + 2];
    const double a = std::atan2(y, x);
    if (k == 0) {
      theta[k] = a;
    } else {
      const double step = std::remainder(a - prev, 2 * kPi);
      theta[k] = theta[k - 1] + step;
      max_step = std::max(max_step, std::abs(step));
      if (std::abs(step) > step_limit) ++under;
    }
    prev = a;
  }
  b.max_azimuth_step = max_step;
  b.undersampled_fraction = double(under) / double(N - 1);
  b.z = moments_of(all, [&](std::size_t k) { return z[k]; });
  const Signal R = analyse(w.t, rho, half, cfg.min_cycles);
  b.rho = R.all;
  b.rho_amplitude = R.amplitude;
  b.rho_rel_amplitude = R.amplitude / R.all.mean;
  b.rho_cycles = R.cycles;
  b.rho_trend = R.fit.slope / R.all.mean;
  b.rho_half_change = (R.mean2 - R.mean1) / R.all.mean;
  b.rho_half_allowance = R.mean_allowance / R.all.mean;
  b.rho_std_half_change = (R.std2 - R.std1) / (0.5 * (R.std1 + R.std2));
  b.radius_ok = R.all.mean >= cfg.radius_floor;
  b.unwrap_ok = max_step <= cfg.ambiguous_step && b.undersampled_fraction <= cfg.max_undersampled_fraction;
  b.omega_reliable = b.radius_ok && b.unwrap_ok;

  const Fit th = fit_line(w.t, theta, all);
  b.omega_raw = th.slope;
  b.omega = b.omega_reliable ? th.slope : kNaN;
  b.omega_first = fit_line(w.t, theta, h1).slope;
  b.omega_second = fit_line(w.t, theta, h2).slope;
  if (std::abs(b.omega_raw) > 1e-12) {
    b.omega_half_change = (b.omega_second - b.omega_first) / std::abs(b.omega_raw);
    const double nu = b.omega_raw / omega_m;
    if (std::isfinite(nu) && std::abs(nu) > 1e-12 && wm1 != 0 && wm2 != 0)
      b.rotation_half_change = (b.omega_second / wm2 - b.omega_first / wm1) / std::abs(nu);
    // A wobble of amplitude α with n/2 cycles per half biases each half's slope by at
    // most 6α/(π (n/2) τ); two halves. The wobble is the radius oscillation's.
    double allow = 0;
    if (R.cycles >= cfg.min_cycles)
      allow = 2.0 * 6.0 * std::sqrt(2.0) * th.res_std / (kPi * 0.5 * R.cycles * tau);
    b.omega_half_allowance = allow / std::abs(b.omega_raw);
  }
}

// The balls with a usable radius and with a reliable ω_ball.
struct BallCounts {
  int rho = 0, omega = 0;
};
BallCounts ball_counts(const OrbitStats& st) {
  BallCounts n;
  for (const BallStats& b : st.ball) {
    n.rho += b.radius_ok ? 1 : 0;
    n.omega += b.omega_reliable ? 1 : 0;
  }
  return n;
}

// The radius trend a circular orbit may have: max_rate_in_drag_units drag rates [1/s].
double max_radius_rate(const OrbitScales& sc, const ClassifierSettings& cfg) {
  return cfg.max_rate_in_drag_units * sc.drag_rate;
}

// The window's features, st.samples and st.omega_pendulum already set; half: the first
// sample of the second half.
void orbit_features(const OrbitWindow& w, const OrbitScales& sc, const ClassifierSettings& cfg, std::size_t half,
                    OrbitStats& st) {
  const std::size_t N = w.t.size();
  st.t_begin = w.t[0];
  st.t_end = w.t[N - 1];
  string_features(w, sc, cfg, half, st);
  const double wm1 = mean_of(w.omega_m, {0, half}), wm2 = mean_of(w.omega_m, {half, N});
  for (int i = 0; i < 2; ++i)
    ball_features(w, i == 0 ? w.r1 : w.r2, cfg, half, wm1, wm2, st.omega_m.mean, st.ball[std::size_t(i)]);

  double omega_sum = 0;
  for (const BallStats& b : st.ball)
    if (b.omega_reliable) omega_sum += b.omega;
  const int n_omega = ball_counts(st).omega;
  if (n_omega > 0) st.omega_ball = omega_sum / n_omega;
  if (st.omega_m.mean != 0) st.rotation_number = st.omega_ball / st.omega_m.mean;
  const double max_rate = max_radius_rate(sc, cfg);
  for (const BallStats& b : st.ball)
    if (b.omega_reliable && b.rho_trend < -max_rate &&
        std::abs(b.omega / st.omega_pendulum - 1) <= cfg.free_swing_band)
      st.free_swing_like = true;
}

// ---- decision over the features (the rules of orbit_classifier.hpp) -----------------------

void settle_on(OrbitClassification& out, OrbitClass cls, double confidence, std::string reason) {
  out.cls = cls;
  out.confidence = confidence;
  out.reason = std::move(reason);
}

// Rule 3: fallen when the bead is on the bottom ball in both halves; not settled when in one.
// True when decided.
bool decide_fallen(const OrbitStats& st, const ClassifierSettings& cfg, OrbitClassification& out) {
  const double F = cfg.fallen_fraction;
  const double f_lo = std::min(st.on_ball_first, st.on_ball_second);
  const double f_hi = std::max(st.on_ball_first, st.on_ball_second);
  if (f_lo >= F) {
    std::string what;
    if (ball_counts(st).rho == 0)
      what = "; hanging within the radius floor";
    else if (st.free_swing_like)
      what = fmt::format("; decaying free swing at {:.3g} rad/s (transient)", st.omega_ball);
    else if (std::isfinite(st.omega_ball))
      what = fmt::format("; w_ball {:.4g} rad/s, radius {:.3g} m", st.omega_ball,
                         0.5 * (st.ball[0].rho.mean + st.ball[1].rho.mean));
    settle_on(out, OrbitClass::Fallen, lower_margin(f_lo, F),
              fmt::format("fallen: bead on the bottom ball {:.0f}% of the window{}", 100 * st.on_ball_fraction, what));
    return true;
  }
  if (f_hi >= F) {
    settle_on(out, OrbitClass::NotSettled, lower_margin(f_hi - f_lo, cfg.on_ball_change_tol),
              fmt::format("not settled: bead {} the bottom ball in the window (on it {:.0f}% then {:.0f}%)",
                          st.on_ball_second > st.on_ball_first ? "fell onto" : "rose from", 100 * st.on_ball_first,
                          100 * st.on_ball_second));
    return true;
  }
  return false;
}

// Rule 4: the steadiness tests between halves. Not settled on the worst failed one (true);
// else the smallest margin of all in steady_margin.
bool decide_unsteady(const OrbitStats& st, const ClassifierSettings& cfg, OrbitClassification& out,
                     double& steady_margin) {
  const double f_lo = std::min(st.on_ball_first, st.on_ball_second);
  const double f_hi = std::max(st.on_ball_first, st.on_ball_second);
  std::vector<Test> tests;
  tests.push_back({"on-ball fraction", f_hi - f_lo, cfg.on_ball_change_tol});
  tests.push_back({"mean L1 (rel. to l)", std::abs(st.L1_half_change), cfg.L1_drift_tol + st.L1_half_allowance});
  for (int i = 0; i < 2; ++i) {
    const BallStats& b = st.ball[std::size_t(i)];
    const char* who = i == 0 ? "bead" : "ball";
    if (b.radius_ok)
      tests.push_back({fmt::format("{} mean radius", who), std::abs(b.rho_half_change),
                       cfg.radius_drift_tol + b.rho_half_allowance});
    if (b.omega_reliable && std::isfinite(b.omega_half_change)) {
      double q = std::abs(b.omega_half_change);
      if (std::isfinite(b.rotation_half_change)) q = std::min(q, std::abs(b.rotation_half_change));
      tests.push_back({fmt::format("{} w_ball", who), q, cfg.omega_drift_tol + b.omega_half_allowance});
    }
  }
  const Test* worst = nullptr;
  for (const Test& t : tests)
    if (t.q > t.X && (!worst || t.q / t.X > worst->q / worst->X)) worst = &t;
  steady_margin = 1.0;
  for (const Test& t : tests) steady_margin = std::min(steady_margin, upper_margin(t.q, t.X));
  if (!worst) return false;
  settle_on(out, OrbitClass::NotSettled, lower_margin(worst->q, worst->X),
            fmt::format("not settled: {} changed by {:.3g} between halves (tolerance {:.3g})", worst->what, worst->q,
                        worst->X));
  return true;
}

// What the circular and flower rules share: the largest relative radius oscillation of a
// ball with a usable radius (and which ball), the margins found so far, the penalty.
struct Shape {
  double rel_amp = 0;
  int ball = 0;
  double steady_margin = 1.0, off_ball_margin = 1.0;
  double penalty = 1.0;
};

// Rules 7 and 8: a circular orbit must not decay or grow at a drag-like rate; then locked,
// lagging or not settled by its rotation number.
void decide_circular(const OrbitStats& st, const OrbitScales& sc, const ClassifierSettings& cfg, const Shape& sh,
                     OrbitClassification& out) {
  const double max_rate = max_radius_rate(sc, cfg);
  const double A_max = cfg.circular_max_rel_amplitude;
  double worst_rate = 0;
  for (const BallStats& b : st.ball)
    if (b.radius_ok && std::abs(b.rho_trend) > std::abs(worst_rate)) worst_rate = b.rho_trend;
  if (std::abs(worst_rate) > max_rate) {
    settle_on(out, OrbitClass::NotSettled, lower_margin(std::abs(worst_rate), max_rate),
              fmt::format("not settled: radius {} at {:.3g}/s (limit {:.3g}/s = {:g} drag rate){}",
                          worst_rate < 0 ? "decays" : "grows", std::abs(worst_rate), max_rate,
                          cfg.max_rate_in_drag_units,
                          st.free_swing_like ? fmt::format(", a free swing at {:.3g} rad/s", st.omega_ball) : ""));
    return;
  }
  const double nu = st.rotation_number;
  const int n_omega = ball_counts(st).omega;
  if (n_omega == 0 || !std::isfinite(nu)) {
    settle_on(out, OrbitClass::NotSettled, 0.0,
              n_omega == 0 ? "not settled: circular but w_ball unreliable (azimuth under-sampled)"
                           : "not settled: circular but the motor is at rest");
    return;
  }
  double m = std::min({sh.steady_margin, upper_margin(sh.rel_amp, A_max), upper_margin(std::abs(worst_rate), max_rate),
                       sh.off_ball_margin});
  const double tol = cfg.locked_tol;
  if (std::abs(nu - 1) <= tol) {
    settle_on(out, OrbitClass::LockedCircular, sh.penalty * std::min(m, upper_margin(std::abs(nu - 1), tol)),
              fmt::format("locked: rotation number {:.4f}, radius oscillation {:.1f}%", nu, 100 * sh.rel_amp));
  } else if (nu > 0 && nu < 1 - tol) {
    settle_on(out, OrbitClass::LaggingCircular, sh.penalty * std::min(m, lower_margin(1 - nu, tol)),
              fmt::format("lagging: rotation number {:.4f} (w_ball {:.4g} rad/s), radius oscillation {:.1f}%", nu,
                          st.omega_ball, 100 * sh.rel_amp));
  } else {
    settle_on(out, OrbitClass::NotSettled, sh.penalty * (nu <= 0 ? 1.0 : lower_margin(nu - 1, tol)),
              fmt::format("not settled: circular but {} the motor (rotation number {:.4f})",
                          nu <= 0 ? "turning against" : "leading", nu));
  }
}

// Rule 9: not circular, a flower if quasi-periodic and stationary.
void decide_flower(const OrbitStats& st, const ClassifierSettings& cfg, const Shape& sh, OrbitClassification& out) {
  const double A_max = cfg.circular_max_rel_amplitude;
  const BallStats& sb = st.ball[std::size_t(sh.ball)];
  if (!(sb.rho_cycles >= cfg.min_cycles)) {
    settle_on(out, OrbitClass::NotSettled, 0.0,
              fmt::format("not settled: radius oscillation {:.1f}% with only {:g} cycles in the window",
                          100 * sh.rel_amp, sb.rho_cycles));
    return;
  }
  double spread_margin = 1.0;
  for (int i = 0; i < 2; ++i) {
    const BallStats& b = st.ball[std::size_t(i)];
    if (!b.radius_ok || b.rho_rel_amplitude <= A_max) continue;
    // A half's standard deviation over n/2 cycles is off by at most 1/(2π n) relative.
    const double X = cfg.spread_drift_tol + 1.0 / (kPi * b.rho_cycles);
    const double q = std::abs(b.rho_std_half_change);
    if (!(q <= X)) {
      settle_on(out, OrbitClass::NotSettled, lower_margin(q, X),
                fmt::format("not settled: {} radius oscillation changed by {:.3g} between halves (tolerance {:.3g})",
                            i == 0 ? "bead" : "ball", q, X));
      return;
    }
    spread_margin = std::min(spread_margin, upper_margin(q, X));
  }
  const int n_omega = ball_counts(st).omega;
  const double penalty = n_omega == 0 ? sh.penalty * 0.5 : sh.penalty;
  settle_on(out, OrbitClass::Flower,
            penalty * std::min({sh.steady_margin, spread_margin, lower_margin(sh.rel_amp, A_max), sh.off_ball_margin}),
            n_omega > 0 ? fmt::format("flower: radius oscillation {:.1f}% over {:g} cycles, w_ball {:.4g} rad/s "
                                      "(rotation number {:.4f})",
                                      100 * sh.rel_amp, sb.rho_cycles, st.omega_ball, st.rotation_number)
                        : fmt::format("flower: radius oscillation {:.1f}% over {:g} cycles, pattern rotation undefined",
                                      100 * sh.rel_amp, sb.rho_cycles));
}

// Rules 3 to 9 over the features of a window long enough to judge.
void decide(const OrbitStats& st, const OrbitScales& sc, const ClassifierSettings& cfg, OrbitClassification& out) {
  if (decide_fallen(st, cfg, out)) return;
  Shape sh;
  if (decide_unsteady(st, cfg, out, sh.steady_margin)) return;
  // --- 5. no orbit
  const BallCounts n = ball_counts(st);
  if (n.rho == 0) {
    settle_on(out, OrbitClass::NotSettled, cfg.no_orbit_confidence,
              fmt::format("not settled: both balls within {:.3g} m of the axis with the bead off the bottom ball",
                          cfg.radius_floor));
    return;
  }
  // --- 6. shape
  for (int i = 0; i < 2; ++i) {
    const BallStats& b = st.ball[std::size_t(i)];
    if (b.radius_ok && b.rho_rel_amplitude > sh.rel_amp) {
      sh.rel_amp = b.rho_rel_amplitude;
      sh.ball = i;
    }
  }
  sh.off_ball_margin = upper_margin(std::max(st.on_ball_first, st.on_ball_second), cfg.fallen_fraction);
  sh.penalty = (n.rho == 1 || n.omega == 1) ? cfg.single_ball_penalty : 1.0;
  if (sh.rel_amp <= cfg.circular_max_rel_amplitude)
    decide_circular(st, sc, cfg, sh, out);
  else
    decide_flower(st, cfg, sh, out);
}

}  // namespace

double OrbitScales::pendulum_rate() const { return std::sqrt(gravity / string_length); }

OrbitScales orbit_scales(const physics::Parameters& p) {
  OrbitScales s;
  s.string_length = p.string_length;
  s.contact_distance = p.contact_distance;
  s.gravity = p.gravity;
  s.drag_rate = p.drag / (p.bead_mass + p.ball_mass);
  return s;
}

OrbitClassification classify_orbit(const OrbitWindow& w, const OrbitScales& sc, const ClassifierSettings& cfg) {
  check_sizes(w);
  const std::size_t N = w.t.size();
  OrbitClassification out;
  OrbitStats& st = out.stats;
  st.samples = long(N);
  st.omega_pendulum = sc.pendulum_rate();

  // --- 1. failed
  const bool finite = all_finite(w.t) && all_finite(w.omega_m) && all_finite(w.r1) && all_finite(w.r2) &&
                      all_finite(w.L1) && all_finite(w.T1) && all_finite(w.T2);
  if (w.failed || !finite) {
    settle_on(out, OrbitClass::Failed, 1.0,
              w.failed ? fmt::format("failed: {}", w.failure.empty() ? "integration failed" : w.failure)
                       : std::string("failed: non-finite samples"));
    if (!finite || N == 0) return out;  // else the caller's failure, with the statistics below
  }

  // --- 2. too short
  const auto too_short = [&] {
    if (out.cls != OrbitClass::Failed) settle_on(out, OrbitClass::NotSettled, 0.0, "not settled: window too short");
  };
  if (N < std::size_t(std::max(cfg.min_samples, 4)) || !(w.t[N - 1] > w.t[0])) {
    too_short();
    return out;
  }
  const double t_mid = 0.5 * (w.t[0] + w.t[N - 1]);
  const std::size_t half = std::size_t(std::lower_bound(w.t.begin(), w.t.end(), t_mid) - w.t.begin());
  if (half < 2 || N - half < 2) {
    too_short();
    return out;
  }

  orbit_features(w, sc, cfg, half, st);
  if (out.cls == OrbitClass::Failed) return out;  // the caller's failure, with statistics
  decide(st, sc, cfg, out);
  return out;
}

namespace {
using S = ClassifierSettings;
// The settings `--set classifier.NAME=value` may change (every one a number > 0).
const ClassifierSettingInfo kTunable[] = {
    {"radius_floor", &S::radius_floor, "m", "mean radius below which a ball's azimuth, so ω_ball, is not trusted"},
    {"min_samples_per_turn", &S::min_samples_per_turn, "", "azimuth steps above 2π/this are under-sampled"},
    {"on_ball_tol", &S::on_ball_tol, "", "|l − L1 − d| <= this·d counts as the bead on the bottom ball"},
    {"fallen_fraction", &S::fallen_fraction, "", "fallen when the bead is on the ball this share of each half window"},
    {"radius_drift_tol", &S::radius_drift_tol, "", "steady: |Δρ̄|/ρ̄ between the window's halves"},
    {"omega_drift_tol", &S::omega_drift_tol, "", "steady: min(|Δω_ball|/|ω_ball|, |Δν|/|ν|) between the halves"},
    {"L1_drift_tol", &S::L1_drift_tol, "", "steady: |ΔL̄1|/l between the halves"},
    {"spread_drift_tol", &S::spread_drift_tol, "", "a steady flower: |Δσ_ρ|/σ_ρ between the halves"},
    {"min_cycles", &S::min_cycles, "", "oscillation cycles per window for the drift allowance and for a flower"},
    {"max_rate_in_drag_units", &S::max_rate_in_drag_units, "", "circular: |ρ̇/ρ| <= this·γ, γ the drag rate"},
    {"circular_max_rel_amplitude", &S::circular_max_rel_amplitude, "", "circular: the radius's amplitude a/ρ̄ at most this"},
    {"locked_tol", &S::locked_tol, "", "locked: |ν − 1| at most this, ν = ω_ball/ω_m"},
    {"free_swing_band", &S::free_swing_band, "", "a free swing: |ω_ball/√(g/l) − 1| within this"},
};
}  // namespace

std::span<const ClassifierSettingInfo> classifier_setting_table() { return kTunable; }

ClassifierSettings parse_classifier_settings(const std::vector<std::string>& name_values) {
  S settings;
  for (const std::string& kv : name_values) {
    const auto eq = kv.find('=');
    // Keys are "classifier.NAME", as every --set names its section.
    constexpr std::string_view kSection = "classifier.";
    const std::string full = kv.substr(0, eq);
    if (full.rfind(kSection, 0) != 0)
      throw std::invalid_argument(fmt::format("{}: expected classifier.NAME=value (did you mean classifier.{}?)", kv, kv));
    const std::string key = full.substr(kSection.size());
    std::string names;
    bool found = false;
    for (const ClassifierSettingInfo& info : kTunable) {
      const std::string_view name = info.name;
      const auto member = info.field;
      names += std::string(names.empty() ? "" : ", ") + "classifier." + std::string(name);
      if (key != name) continue;
      double v = std::numeric_limits<double>::quiet_NaN();
      try {
        v = std::stod(kv.substr(eq + 1));
      } catch (const std::exception&) {
      }
      if (eq == std::string::npos || !(v > 0.0) || !std::isfinite(v))
        throw std::invalid_argument(fmt::format("{}: expected {}=<number > 0>", kv, name));
      settings.*member = v;
      found = true;
    }
    if (!found) throw std::invalid_argument(fmt::format("{}: unknown classifier setting; allowed: {}", kv, names));
  }
  return settings;
}

}  // namespace ajx::sweep
