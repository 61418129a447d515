// The orbit classifier on trajectories written down analytically, one per class: the paper's
// Table 1 locked orbit, a lagging orbit, an epicycle flower, a fallen driven pendulum, a
// decaying free swing, a drifting orbit, a sub-millimetre orbit; noise; the least-squares
// ω_ball; the azimuth unwrap at and below 4 samples per turn.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include "physics/model.hpp"
#include "sweep/orbit_classifier.hpp"

using namespace ajx::sweep;

namespace {

constexpr double pi = std::numbers::pi;
const OrbitScales scales{};  // l = 0.826 m, d = 0.03 m, g = 9.81, γ = c_D/(2m)

struct P {
  double x, y, z;
};
// A point at horizontal radius rho, azimuth th, height z.
P polar(double rho, double th, double z) { return {rho * std::cos(th), rho * std::sin(th), z}; }

struct Sample {
  P r1, r2;
  double omega_m;
  double L1;
  int mode;
  double T1 = 0.6, T2 = 0.3;
};

struct Traj {
  std::vector<double> t, wm, r1, r2, L1, T1, T2;
  std::vector<int> mode;
  OrbitWindow window() const {
    OrbitWindow w;
    w.t = t;
    w.omega_m = wm;
    w.r1 = r1;
    w.r2 = r2;
    w.L1 = L1;
    w.T1 = T1;
    w.T2 = T2;
    w.mode = mode;
    return w;
  }
  OrbitClassification classify(const ClassifierSettings& s = {}) const { return classify_orbit(window(), scales, s); }
};

// Samples t0, t0 + 1/fs, ... over duration T; noise sigma [m] on positions and on L1.
Traj build(double t0, double T, double fs, const std::function<Sample(double)>& f, double sigma = 0.0,
           unsigned seed = 1) {
  Traj tr;
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  const auto noise = [&] { return sigma > 0 ? sigma * n(rng) : 0.0; };
  const long N = std::lround(T * fs) + 1;
  for (long k = 0; k < N; ++k) {
    const double t = t0 + double(k) / fs;
    const Sample s = f(t);
    tr.t.push_back(t);
    tr.wm.push_back(s.omega_m);
    for (const P& p : {s.r1}) tr.r1.insert(tr.r1.end(), {p.x + noise(), p.y + noise(), p.z + noise()});
    for (const P& p : {s.r2}) tr.r2.insert(tr.r2.end(), {p.x + noise(), p.y + noise(), p.z + noise()});
    tr.L1.push_back(s.L1 + noise());
    tr.T1.push_back(s.T1);
    tr.T2.push_back(s.T2);
    tr.mode.push_back(s.mode);
  }
  return tr;
}

// The paper's Table 1: bead at radius 0.14427 m, height −0.52483 m; the bottom ball on the
// opposite side at 0.11924 m, −0.62353 m; both turning at the motor's ω. Bead stuck (mode 2).
Sample table1(double phase, double omega_m, double scale = 1.0) {
  const double R = 0.01;
  const P r1 = polar(0.14427 * scale, phase + pi, -0.52483);
  const P a = polar(R, phase, 0.0);
  const double L1 = std::sqrt((r1.x - a.x) * (r1.x - a.x) + (r1.y - a.y) * (r1.y - a.y) + r1.z * r1.z);
  return {r1, polar(0.11924 * scale, phase, -0.62353), omega_m, L1, 2};
}

Traj locked(double omega, double t0 = 100.0, double T = 10.0, double fs = 200.0, double sigma = 0.0) {
  return build(t0, T, fs, [&](double t) { return table1(omega * t + 0.3, omega); }, sigma);
}

Traj lagging(double omega_ball, double omega_m, double sigma = 0.0) {
  return build(200.0, 10.0, 200.0, [&](double t) { return table1(omega_ball * t - 1.0, omega_m); }, sigma);
}

// An epicycle: a circle of radius A at ω_p plus one of radius B at ω_s, incommensurate.
// The radius oscillates at Ω = ω_p − ω_s = √3 π (period 1.15 s), B/A = 0.5.
Traj flower(double sigma = 0.0, double B_growth = 0.0) {
  const double wp = 4.8 * pi, Om = std::sqrt(3.0) * pi, ws = wp - Om, t0 = 300.0;
  return build(t0, 10.0, 200.0,
               [=](double t) {
                 const double g = 1.0 + B_growth * (t - t0);
                 const P a1 = polar(0.14, wp * t, 0.0), b1 = polar(0.07 * g, ws * t + 0.4, 0.0);
                 const P a2 = polar(0.12, wp * t + pi, 0.0), b2 = polar(0.05 * g, ws * t + 1.1, 0.0);
                 Sample s;
                 s.r1 = {a1.x + b1.x, a1.y + b1.y, -0.50 + 0.010 * std::cos(Om * t)};
                 s.r2 = {a2.x + b2.x, a2.y + b2.y, -0.62 + 0.012 * std::cos(Om * t + 0.5)};
                 s.omega_m = 15.5 * pi;
                 s.L1 = 0.55 + 0.02 * std::cos(Om * t + 0.3);
                 s.mode = std::cos(Om * t) > 0 ? 2 : 0;
                 return s;
               },
               sigma);
}

// The bead on the bottom ball (L1 = l − d): both balls on one small circle of radius rho,
// the bead d above the ball.
Sample fallen_sample(double rho, double th, double omega_m, int mode = 1, double L1 = 0.826 - 0.03) {
  const double l = 0.826, d = 0.03;
  const double z2 = -std::sqrt(l * l - rho * rho);
  return {polar(rho * (l - d) / l, th, z2 * (l - d) / l), polar(rho, th, z2), omega_m, L1, mode};
}

}  // namespace

TEST(OrbitClassifier, NamesRoundTrip) {
  for (OrbitClass c : {OrbitClass::Fallen, OrbitClass::LockedCircular, OrbitClass::LaggingCircular,
                       OrbitClass::Flower, OrbitClass::NotSettled, OrbitClass::Failed})
    EXPECT_EQ(parse_orbit_class(to_string(c)), c);
  EXPECT_FALSE(parse_orbit_class("spiral").has_value());
  EXPECT_EQ(to_string(OrbitClass::LaggingCircular), "lagging-circular");
}

TEST(OrbitClassifier, ScalesFromParameters) {
  const ajx::physics::Parameters p;
  const OrbitScales s = orbit_scales(p);
  EXPECT_DOUBLE_EQ(s.string_length, p.string_length);
  EXPECT_DOUBLE_EQ(s.contact_distance, p.contact_distance);
  EXPECT_NEAR(s.drag_rate, 0.0479, 1e-4);
  EXPECT_NEAR(s.pendulum_rate(), 3.446, 1e-3);
}

TEST(OrbitClassifier, LockedCircularTable1) {
  const double w = 4.7 * pi;
  const OrbitClassification c = locked(w).classify();
  EXPECT_EQ(c.cls, OrbitClass::LockedCircular) << c.reason;
  EXPECT_GT(c.confidence, 0.95) << c.reason;
  const OrbitStats& s = c.stats;
  EXPECT_EQ(s.samples, 2001);
  for (const BallStats& b : s.ball) {
    EXPECT_TRUE(b.omega_reliable);
    EXPECT_NEAR(b.omega, w, 1e-9 * w);
    EXPECT_NEAR(b.omega_first, w, 1e-9 * w);
    EXPECT_NEAR(b.omega_second, w, 1e-9 * w);
    EXPECT_LT(b.rho.std, 1e-12);
    EXPECT_LT(b.rho_rel_amplitude, 1e-10);
    EXPECT_NEAR(b.rho_trend, 0.0, 1e-10);
  }
  EXPECT_NEAR(s.ball[0].rho.mean, 0.14427, 1e-12);
  EXPECT_NEAR(s.ball[0].z.mean, -0.52483, 1e-12);
  EXPECT_NEAR(s.ball[1].rho.mean, 0.11924, 1e-12);
  EXPECT_NEAR(s.ball[1].z.mean, -0.62353, 1e-12);
  EXPECT_NEAR(s.omega_ball, w, 1e-9 * w);
  EXPECT_NEAR(s.rotation_number, 1.0, 1e-9);
  EXPECT_DOUBLE_EQ(s.mode_fraction[2], 1.0);
  EXPECT_DOUBLE_EQ(s.mode_fraction[1], 0.0);
  EXPECT_DOUBLE_EQ(s.on_ball_fraction, 0.0);
  EXPECT_NEAR(s.T1.mean, 0.6, 1e-12);
  EXPECT_NEAR(s.T2.max, 0.3, 1e-12);
  EXPECT_NEAR(s.L1.std, 0.0, 1e-9);  // the bead keeps its distance from the turning top
  EXPECT_FALSE(s.free_swing_like);
}

TEST(OrbitClassifier, OmegaBallIsTheLeastSquaresSlope) {
  // A clean circle late in a sweep (t ≈ 2000 s, azimuth ≈ 3e4 rad): 1e-6 relative or better.
  const double w = 15.3;
  const Traj tr = locked(w, 2000.0, 7.3, 123.0);
  const OrbitClassification c = tr.classify();
  EXPECT_NEAR(c.stats.ball[0].omega, w, 1e-6 * w);
  EXPECT_NEAR(c.stats.ball[1].omega, w, 1e-6 * w);
  // Least squares, not endpoints: an azimuth wobble of 0.2 rad at 0.75 Hz over 10 s puts
  // the endpoints 0.34 rad apart from the mean motion; the fit is off by ≤ 12α/(ΩT²).
  const double t0 = 50.0, T = 10.0;
  const auto wobble = [&](double t) { return 0.2 * std::sin(2 * pi * 0.75 * (t - t0) + 1.0); };
  const Traj wob = build(t0, T, 200.0, [&](double t) { return table1(w * t + wobble(t), w); });
  const double endpoint = w + (wobble(t0 + T) - wobble(t0)) / T;
  const double ls = wob.classify().stats.ball[1].omega_raw;
  EXPECT_GT(std::abs(endpoint - w), 0.03);
  EXPECT_LT(std::abs(ls - w), 12 * 0.2 / (2 * pi * 0.75 * T * T));
}

TEST(OrbitClassifier, LaggingCircular) {
  const OrbitClassification c = lagging(4.8 * pi, 10 * pi).classify();
  EXPECT_EQ(c.cls, OrbitClass::LaggingCircular) << c.reason;
  EXPECT_GT(c.confidence, 0.95);
  EXPECT_NEAR(c.stats.omega_ball, 4.8 * pi, 1e-9);
  EXPECT_NEAR(c.stats.rotation_number, 0.48, 1e-9);
  // Just below the locked band: still lagging, with little confidence.
  const OrbitClassification near = lagging(0.975 * 10 * pi, 10 * pi).classify();
  EXPECT_EQ(near.cls, OrbitClass::LaggingCircular) << near.reason;
  EXPECT_LT(near.confidence, 0.6);
  // Leading the motor is no steady driven orbit.
  EXPECT_EQ(lagging(11 * pi, 10 * pi).classify().cls, OrbitClass::NotSettled);
}

TEST(OrbitClassifier, SteadyDuringARamp) {
  // Locked: ω_m ramps 4.3π → 4.7π over the window and the balls follow it (ω_ball changes
  // 4.4 % between halves in the lab, 0 in the motor's frame); the radius creeps by 1 %.
  const double w0 = 4.3 * pi, al = 0.04 * pi, t0 = 10.0;
  const Traj lk = build(t0, 10.0, 200.0, [&](double t) {
    const double s = t - t0;
    return table1(w0 * s + 0.5 * al * s * s, w0 + al * s, 1.0 + 0.001 * s);
  });
  const OrbitClassification c = lk.classify();
  EXPECT_EQ(c.cls, OrbitClass::LockedCircular) << c.reason;
  EXPECT_NEAR(c.stats.rotation_number, 1.0, 1e-9);
  EXPECT_GT(std::abs(c.stats.ball[0].omega_half_change), 0.04);
  // Lagging: ω_m ramps 8π → 9π while ω_ball stays at 4.8π (ν changes 6 % between halves).
  const Traj lg = build(t0, 10.0, 200.0, [&](double t) { return table1(4.8 * pi * t, 8 * pi + 0.1 * pi * (t - t0)); });
  const OrbitClassification g = lg.classify();
  EXPECT_EQ(g.cls, OrbitClass::LaggingCircular) << g.reason;
  EXPECT_GT(std::abs(g.stats.ball[0].rotation_half_change), 0.04);
}

TEST(OrbitClassifier, FlowerEpicycle) {
  const OrbitClassification c = flower().classify();
  EXPECT_EQ(c.cls, OrbitClass::Flower) << c.reason;
  EXPECT_GT(c.confidence, 0.9) << c.reason;
  // The pattern turns at ω_p (the larger circle winds, the smaller does not).
  EXPECT_NEAR(c.stats.omega_ball, 4.8 * pi, 0.01 * 4.8 * pi);
  EXPECT_NEAR(c.stats.rotation_number, 4.8 / 15.5, 0.01);
  EXPECT_GT(c.stats.ball[0].rho_rel_amplitude, 0.3);
  EXPECT_NEAR(c.stats.ball[0].rho.min, 0.07, 2e-3);
  EXPECT_NEAR(c.stats.ball[0].rho.max, 0.21, 2e-3);
  EXPECT_NEAR(c.stats.ball[0].rho_cycles, 10.0 * std::sqrt(3.0) / 2.0, 1.0);
  EXPECT_NEAR(c.stats.mode_fraction[0] + c.stats.mode_fraction[2], 1.0, 1e-12);
  // An epicycle whose small circle grows by 80 % over the window is not stationary.
  const OrbitClassification g = flower(0.0, 0.08).classify();
  EXPECT_EQ(g.cls, OrbitClass::NotSettled) << g.reason;
  EXPECT_NE(g.reason.find("radius oscillation changed"), std::string::npos) << g.reason;
  EXPECT_LT(std::abs(c.stats.ball[0].rho_std_half_change), 0.03);  // the steady one
}

TEST(OrbitClassifier, FallenDrivenCircle) {
  // The bead on the bottom ball, the pair on a 1 cm circle at ω_m: a driven spherical
  // pendulum, fallen however well it turns with the motor.
  const double w = 2.0 * pi;
  const Traj tr = build(0.0, 10.0, 200.0, [&](double t) { return fallen_sample(0.01, w * t, w); });
  const OrbitClassification c = tr.classify();
  EXPECT_EQ(c.cls, OrbitClass::Fallen) << c.reason;
  EXPECT_DOUBLE_EQ(c.confidence, 1.0);
  EXPECT_DOUBLE_EQ(c.stats.mode_fraction[1], 1.0);
  EXPECT_NEAR(c.stats.ball[1].omega, w, 1e-9);
  EXPECT_NEAR(c.stats.rotation_number, 1.0, 1e-9);
  // "On the ball" from L1 alone when the mode is not recorded.
  Traj nomode = tr;
  nomode.mode.clear();
  EXPECT_EQ(nomode.classify().cls, OrbitClass::Fallen);
  EXPECT_TRUE(std::isnan(nomode.classify().stats.mode_fraction[1]));
}

TEST(OrbitClassifier, DecayingFreeSwingIsNotLagging) {
  // A conical free swing at √(g/l) left by a resonance, amplitude e^{−0.05 t}, while the
  // motor turns at 20 rad/s: it looks circular and lags, but it decays at the drag rate.
  const double w0 = std::sqrt(9.81 / 0.826);
  const auto swing = [&](int mode, double L1) {
    return [=](double t) { return fallen_sample(0.1 * std::exp(-0.05 * t), w0 * t, 20.0, mode, L1); };
  };
  // The bead on the bottom ball: fallen (the swing is the fallen pendulum's transient).
  const OrbitClassification f = build(40.0, 10.0, 200.0, swing(1, 0.826 - 0.03)).classify();
  EXPECT_EQ(f.cls, OrbitClass::Fallen) << f.reason;
  EXPECT_TRUE(f.stats.free_swing_like);
  EXPECT_NEAR(f.stats.omega_ball, w0, 1e-3 * w0);
  EXPECT_NEAR(f.stats.ball[1].rho_trend, -0.05, 0.005);
  // The bead held on the string above the ball: not settled (the decay drifts the halves).
  const OrbitClassification s = build(40.0, 10.0, 200.0, swing(2, 0.6)).classify();
  EXPECT_EQ(s.cls, OrbitClass::NotSettled) << s.reason;
  EXPECT_TRUE(s.stats.free_swing_like);
  // In a 1.5 s window the half means differ by only 3.7 %, within the half-change
  // tolerance; the decay rate still rules it out.
  const OrbitClassification s2 = build(40.0, 1.5, 200.0, swing(2, 0.6)).classify();
  EXPECT_LT(std::abs(s2.stats.ball[0].rho_half_change), 0.05);
  EXPECT_EQ(s2.cls, OrbitClass::NotSettled) << s2.reason;
  EXPECT_NE(s2.reason.find("decays"), std::string::npos) << s2.reason;
  EXPECT_NE(s2.reason.find("free swing"), std::string::npos) << s2.reason;
}

TEST(OrbitClassifier, DriftingOrbitIsNotSettled) {
  // Locked to the motor but the radius grows linearly, 30 % over the window.
  const double w = 4.5 * pi;
  const Traj tr = build(0.0, 10.0, 200.0, [&](double t) { return table1(w * t, w, 1.0 + 0.03 * t); });
  const OrbitClassification c = tr.classify();
  EXPECT_EQ(c.cls, OrbitClass::NotSettled) << c.reason;
  EXPECT_GT(c.confidence, 0.9);
  EXPECT_NEAR(c.stats.ball[0].rho_half_change, 0.15 / 1.15, 0.01);
  // The bead falling onto the bottom ball halfway through the window.
  const Traj fall = build(0.0, 10.0, 200.0, [&](double t) {
    return t < 5.0 ? table1(w * t, w) : fallen_sample(0.01, w * t, w);
  });
  const OrbitClassification cf = fall.classify();
  EXPECT_EQ(cf.cls, OrbitClass::NotSettled) << cf.reason;
  EXPECT_NE(cf.reason.find("fell onto"), std::string::npos) << cf.reason;
}

TEST(OrbitClassifier, SubMillimetreOrbit) {
  // Radius 0.5 mm "locked" to the motor, bead off the ball: ω_ball is NaN, never locked.
  const double w = 4.7 * pi;
  const Traj tr = build(0.0, 10.0, 200.0, [&](double t) { return table1(w * t, w, 0.5e-3 / 0.14427); }, 2e-5);
  const OrbitClassification c = tr.classify();
  EXPECT_EQ(c.cls, OrbitClass::NotSettled) << c.reason;
  EXPECT_LE(c.confidence, 0.3);
  for (const BallStats& b : c.stats.ball) {
    EXPECT_FALSE(b.radius_ok);
    EXPECT_FALSE(b.omega_reliable);
    EXPECT_TRUE(std::isnan(b.omega));
    EXPECT_TRUE(std::isfinite(b.omega_raw));
  }
  EXPECT_TRUE(std::isnan(c.stats.omega_ball));
  EXPECT_TRUE(std::isnan(c.stats.rotation_number));
  // The same with the bead on the bottom ball: a pendulum hanging nearly still, fallen.
  const Traj hang = build(0.0, 10.0, 200.0, [&](double t) { return fallen_sample(0.5e-3, w * t, w); }, 2e-5);
  const OrbitClassification h = hang.classify();
  EXPECT_EQ(h.cls, OrbitClass::Fallen) << h.reason;
  EXPECT_TRUE(std::isnan(h.stats.omega_ball));
}

TEST(OrbitClassifier, RobustToNoise) {
  // 1 mm of noise on every coordinate and on L1.
  const double sigma = 1e-3;
  const OrbitClassification lk = locked(4.7 * pi, 100.0, 10.0, 200.0, sigma).classify();
  EXPECT_EQ(lk.cls, OrbitClass::LockedCircular) << lk.reason;
  EXPECT_GT(lk.confidence, 0.8);
  EXPECT_NEAR(lk.stats.omega_ball, 4.7 * pi, 1e-3 * 4.7 * pi);
  const OrbitClassification lg = lagging(4.8 * pi, 10 * pi, sigma).classify();
  EXPECT_EQ(lg.cls, OrbitClass::LaggingCircular) << lg.reason;
  EXPECT_GT(lg.confidence, 0.8);
  EXPECT_NEAR(lg.stats.omega_ball, 4.8 * pi, 1e-3 * 4.8 * pi);
  const OrbitClassification fl = flower(sigma).classify();
  EXPECT_EQ(fl.cls, OrbitClass::Flower) << fl.reason;
  EXPECT_GT(fl.confidence, 0.8);
  const double w = 2.0 * pi;
  const OrbitClassification fa =
      build(0.0, 10.0, 200.0, [&](double t) { return fallen_sample(0.01, w * t, w); }, sigma).classify();
  EXPECT_EQ(fa.cls, OrbitClass::Fallen) << fa.reason;
}

TEST(OrbitClassifier, UnwrapAtAndBelowFourSamplesPerTurn) {
  const double w = 2 * pi * 5.0;  // 5 turns per second
  for (double per_turn : {4.0, 5.0, 7.3}) {
    const OrbitClassification c = locked(w, 0.0, 10.0, 5.0 * per_turn).classify();
    EXPECT_TRUE(c.stats.ball[0].unwrap_ok) << per_turn;
    EXPECT_NEAR(c.stats.ball[0].omega, w, 1e-9 * w) << per_turn;
    EXPECT_EQ(c.cls, OrbitClass::LockedCircular) << per_turn << ": " << c.reason;
  }
  // 3 samples per turn: still unwrapped right, but flagged; 1.5: aliased (the raw slope
  // turns backwards) and flagged. Neither is classified locked or lagging.
  for (double per_turn : {3.0, 1.5}) {
    const OrbitClassification c = locked(w, 0.0, 10.0, 5.0 * per_turn).classify();
    EXPECT_FALSE(c.stats.ball[0].unwrap_ok) << per_turn;
    EXPECT_FALSE(c.stats.ball[0].omega_reliable) << per_turn;
    EXPECT_TRUE(std::isnan(c.stats.omega_ball)) << per_turn;
    EXPECT_EQ(c.cls, OrbitClass::NotSettled) << per_turn << ": " << c.reason;
    EXPECT_DOUBLE_EQ(c.confidence, 0.0);
  }
  EXPECT_NEAR(locked(w, 0.0, 10.0, 15.0).classify().stats.ball[0].omega_raw, w, 1e-9 * w);
  EXPECT_LT(locked(w, 0.0, 10.0, 7.5).classify().stats.ball[0].omega_raw, 0.0);
  // A planar swing through the axis flips the azimuth by π: ambiguous, flagged.
  const Traj planar = build(0.0, 10.0, 200.0, [&](double t) {
    const double x = 0.05 * std::cos(3.4 * t);
    return Sample{{x, 0.0, -0.5}, {1.2 * x, 0.0, -0.8}, 20.0, 0.5, 2};
  });
  EXPECT_FALSE(planar.classify().stats.ball[0].unwrap_ok);
}

TEST(OrbitClassifier, FailedAndBadInput) {
  Traj tr = locked(4.7 * pi);
  OrbitWindow w = tr.window();
  w.failed = true;
  w.failure = "step size underflow";
  const OrbitClassification f = classify_orbit(w, scales);
  EXPECT_EQ(f.cls, OrbitClass::Failed);
  EXPECT_DOUBLE_EQ(f.confidence, 1.0);
  EXPECT_NE(f.reason.find("step size underflow"), std::string::npos);
  EXPECT_NEAR(f.stats.omega_ball, 4.7 * pi, 1e-9);  // statistics still there
  // No samples at all, failed.
  OrbitWindow empty;
  empty.failed = true;
  EXPECT_EQ(classify_orbit(empty, scales).cls, OrbitClass::Failed);
  // A NaN sample.
  Traj bad = tr;
  bad.r2[30] = std::nan("");
  EXPECT_EQ(bad.classify().cls, OrbitClass::Failed);
  // Too short to judge.
  Traj shrt = build(0.0, 0.05, 200.0, [&](double t) { return table1(t, 1.0); });
  const OrbitClassification s = shrt.classify();
  EXPECT_EQ(s.cls, OrbitClass::NotSettled);
  EXPECT_DOUBLE_EQ(s.confidence, 0.0);
  // Sizes that disagree are a programming error.
  Traj mis = tr;
  mis.r1.pop_back();
  EXPECT_THROW(mis.classify(), std::invalid_argument);
  Traj mis2 = tr;
  mis2.T1.pop_back();
  EXPECT_THROW(mis2.classify(), std::invalid_argument);
  Traj opt = tr;  // optional arrays may be empty
  opt.T1.clear();
  opt.T2.clear();
  const OrbitClassification o = opt.classify();
  EXPECT_EQ(o.cls, OrbitClass::LockedCircular);
  EXPECT_TRUE(std::isnan(o.stats.T1.mean));
}
