// Two-parameter continuation of the threshold points (orbits/threshold_curves.hpp): three points
// of each curve (fold, cone_up, cone_down of the locked orbit; hopf of the lag) are found again by
// the one-parameter continuation in ω (continuation.hpp; lagging_orbit.hpp's lag_branch for the
// lag) started afresh at that fixed value of the second parameter. The tolerance is derived from
// the two solvers' floors: each point solves its equations to the round-off floor of the nine
// equations (default_tolerance) and of its test function (a margin: the same floor; a bordered
// determinant or an eigenvalue of central differences: ε^(2/3)), and the scaled Jacobian
// maps a residual r to an error in ω of at most r / σ_min (σ_min its smallest singular value).
#include <gtest/gtest.h>

#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "measured.hpp"
#include "one_set.hpp"
#include "orbits/continuation.hpp"
#include "orbits/lagging_orbit.hpp"
#include "orbits/orbit_families.hpp"
#include "orbits/threshold_curves.hpp"

using namespace ajx;
using namespace ajx::orbits;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kEps = std::numeric_limits<double>::epsilon();

// On the documented set (one_set.hpp's documented_set), the bead where the staircase's lands.
constexpr double kS = 0.4589;

// ω of the one-parameter events of `kind` on every stuck branch at s, continued in ω afresh.
std::vector<double> one_parameter_events(const physics::Model& m, CurveKind kind, double s) {
  std::vector<double> out;
  const EventKind want = kind == CurveKind::Fold     ? EventKind::Fold
                         : kind == CurveKind::ConeUp ? EventKind::ConeExitUp
                                                     : EventKind::ConeExitDown;
  ContinuationOptions copt;
  copt.lambda_min = 0.5;
  copt.lambda_max = 20 * kPi;
  copt.stability = false;
  for (double w0 : {3 * kPi, 5 * kPi, 8 * kPi, 12 * kPi})
    for (const SteadyOrbit& o : orbits_at({m, w0, Closure::Stuck, s}))
      for (int dir : {-1, +1}) {
        copt.direction = dir;
        for (const BranchEvent& e : continue_branch({m, w0, Closure::Stuck, s}, unknowns(o), "omega", copt).events)
          if (e.kind == want) out.push_back(e.lambda);
      }
  return out;
}

// ω_b of the lag's Hopf points at s (lag_branch over ω_b in [2π, 7π]).
std::vector<double> one_parameter_hopf(const physics::Model& m, double s) {
  std::vector<double> out;
  for (const SteadyOrbit& o : orbits_at({m, 4.5 * kPi, Closure::Stuck, s})) {
    if (!o.admissible) continue;
    for (const LagEvent& e : lag_branch(m, o, 2 * kPi, 7 * kPi).events)
      if (e.complex_pair) out.push_back(e.at.orbit.omega);
  }
  return out;
}

double nearest(const std::vector<double>& v, double x) {
  double best = std::numeric_limits<double>::infinity();
  for (double y : v)
    if (std::abs(y - x) < std::abs(best - x)) best = y;
  return best;
}

// |Δω| allowed between the curve's point and the one-parameter event (see the file's comment):
// both residual floors through the scaled Jacobian, in units of √(g/l) (ω's scale). The lag's
// one-parameter Hopf point is bisected on Re λ < growth_noise, not on Re λ = 0: that offsets it
// by growth_noise / |dRe λ/dω_b|, the slope measured at the point by two solves at fixed p.
double tolerance(const physics::Model& m, const CurvePoint& q, CurveKind kind) {
  const OrbitProblem pb{m, q.omega, Closure::Stuck, kS};
  const double floor_G = 4 * default_tolerance(pb);
  const double floor_g = kind == CurveKind::ConeUp || kind == CurveKind::ConeDown ? floor_G
                                                                                   : 64 * std::cbrt(kEps * kEps);
  double tol = std::sqrt(m.p.gravity / m.p.string_length) * 2 * (floor_G + floor_g) / q.sigma_min;
  if (kind == CurveKind::Hopf) {
    const double dw = 1e-4 * q.omega;
    double re[2];
    for (int k = 0; k < 2; ++k) {
      const OrbitProblem pk{m, q.omega + (k ? dw : -dw), Closure::Stuck, kS};
      const NewtonResult r = solve(pk, unknowns(q.orbit));
      const LagStability st = lag_stability(m, describe(pk, r.X));
      double best = std::numeric_limits<double>::infinity();  // the pair nearest the curve's
      for (int i = 0; i < st.eigenvalues.size(); ++i)
        if (std::abs(std::abs(st.eigenvalues(i).imag()) - q.frequency) < best) {
          best = std::abs(std::abs(st.eigenvalues(i).imag()) - q.frequency);
          re[k] = st.eigenvalues(i).real();
        }
    }
    tol += growth_noise(m, q.omega) / std::abs((re[1] - re[0]) / (2 * dw));
  }
  return tol;
}

void check_three_points(const physics::Model& m0, const std::string& parameter, CurveKind kind, double lo, double hi) {
  CurveOptions opt;
  opt.p_lo = lo;
  opt.p_hi = hi;
  const std::vector<Curve> curves = threshold_curves(m0, parameter, kind, kS, opt);
  ASSERT_FALSE(curves.empty()) << to_string(kind) << ": no curve";
  const Curve& c = curves.front();
  const std::size_t n = c.points.size();
  ASSERT_GE(n, 7u) << c.stop_reason;
  for (std::size_t i : {n / 6, n / 2, 5 * n / 6}) {
    const CurvePoint& q = c.points[i];
    physics::Model m = m0;
    OrbitProblem pb{m, q.omega, Closure::Stuck, kS};
    set_parameter(pb, parameter, q.p);
    m = pb.model;
    // The lag's point is compared in its own ω, ω_b (ω_m = ω_b + (τ − τ_k)/c_a follows from it).
    const double found = kind == CurveKind::Hopf ? nearest(one_parameter_hopf(m, kS), q.omega)
                                                 : nearest(one_parameter_events(m, kind, kS), q.omega);
    const double tol = tolerance(m, q, kind);
    report(fmt::format("{} curve in {} at {} = {:.6g}", to_string(kind), parameter, parameter, q.p),
           fmt::format("omega {:.9f} rad/s (omega_m {:.6f}π), one-parameter {:.9f}, |diff| {:.2e} <= tol {:.2e}",
                       q.omega, q.omega_m / kPi, found, std::abs(found - q.omega), tol));
    EXPECT_NEAR(found, q.omega, tol) << to_string(kind) << " at " << parameter << " = " << q.p;
    // The point is the condition it claims: a margin at zero, or (fold) G_X singular.
    if (kind == CurveKind::ConeUp) EXPECT_NEAR(q.orbit.margins.up, 0.0, 1e-9);
    if (kind == CurveKind::ConeDown) EXPECT_NEAR(q.orbit.margins.down, 0.0, 1e-9);
  }
}

}  // namespace

TEST(ThresholdCurves, FoldAgreesWithTheOneParameterContinuationAtThreePoints) {
  check_three_points(documented_set(false), "drive_radius", CurveKind::Fold, 0.005, 0.03);
}
TEST(ThresholdCurves, ConeUpAgreesWithTheOneParameterContinuationAtThreePoints) {
  check_three_points(documented_set(false), "drive_radius", CurveKind::ConeUp, 0.005, 0.03);
}
TEST(ThresholdCurves, ConeDownAgreesWithTheOneParameterContinuationAtThreePoints) {
  check_three_points(documented_set(false), "drive_radius", CurveKind::ConeDown, 0.005, 0.03);
}
TEST(ThresholdCurves, ConeDownInTheMassAgreesAtThreePoints) {
  check_three_points(documented_set(false), "mass", CurveKind::ConeDown, 0.01, 0.12);
}
TEST(ThresholdCurves, LagHopfAgreesWithTheLagBranchAtThreePoints) {
  check_three_points(documented_set(true), "drive_radius", CurveKind::Hopf, 0.01, 0.02);
}

TEST(ThresholdCurves, RefusesASecondParameterThatIsNotAContinuationParameter) {
  const physics::Model m = documented_set(false);
  const CurveStart st{CurveKind::ConeDown, kS, 10.0, Vec9::Zero()};
  for (const char* bad : {"omega", "top_stop", "tie_inertia", "nonsense"}) {
    try {
      follow_curve(m, bad, st, {});
      ADD_FAILURE() << bad << " accepted";
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(bad), std::string::npos) << what;
      EXPECT_NE(what.find("drive_radius"), std::string::npos) << what;  // the list of allowed ones
    }
  }
}
