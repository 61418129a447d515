// Pseudo-arclength continuation of locked orbits: a fold of the Table-1 branch is passed and
// located (the Jacobian is singular there, two roots below it, none above), a Hopf-type
// crossing carries the frequency of the crossing pair, and continuation in a model
// parameter lands on the orbit a direct solve finds.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <fmt/format.h>
#include <numbers>

#include "orbits/continuation.hpp"
#include "orbits/orbit_families.hpp"
#include "measured.hpp"

using namespace ajx;
using namespace ajx::orbits;

namespace {

constexpr double kPi = std::numbers::pi;

// The Table-1-type orbit at 4.7π, bead stuck at the table's s.
Vec9 table1_orbit(const physics::Model& m, double s) {
  for (const auto& o : orbits_at({m, 4.7 * kPi, Closure::Stuck, s}))
    if (o.branch == "-/+" && o.rho1 > 0.05) return unknowns(o);
  ADD_FAILURE() << "no Table-1-type orbit";
  return Vec9::Zero();
}

double singular_ratio(const OrbitProblem& pb, const Vec9& X) {
  // On the scaled unknowns (lengths / l, forces / W), as the continuation sees them.
  const Scales sc = scales(pb.model);
  Vec9 d;
  d << Vec3::Constant(sc.length), Vec3::Constant(sc.length), sc.force, sc.force, sc.length;
  const Mat9 J = jacobian(pb, X) * d.asDiagonal();
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(J).singularValues();
  return sv(8) / sv(0);
}

}  // namespace

TEST(Continuation, PassesAndLocatesTheFoldOfTheTable1Branch) {
  const physics::Model m;
  const double s = 0.544298;
  const OrbitProblem pb{m, 4.7 * kPi, Closure::Stuck, s};
  ContinuationOptions opt;
  opt.direction = +1;
  opt.lambda_min = 4.0 * kPi;
  opt.lambda_max = 6.0 * kPi;
  const Branch b = continue_branch(pb, table1_orbit(m, s), "omega", opt);
  const BranchEvent* fold = nullptr;
  for (const auto& e : b.events)
    if (e.kind == EventKind::Fold && !fold) fold = &e;
  ASSERT_NE(fold, nullptr) << "stopped: " << b.stop_reason;
  // Passed: beyond the fold the branch comes back down in ω.
  ASSERT_GT(int(b.points.size()), fold->after_point + 5);
  EXPECT_LT(b.points[fold->after_point + 5].lambda, fold->lambda);
  for (int i = 0; i <= fold->after_point; ++i) EXPECT_LE(b.points[i].lambda, fold->lambda);
  // Located: the bisection leaves it within 2^-40 of a step (≤ 0.02 scaled) of the fold, where
  // the smallest singular value of the Jacobian vanishes linearly; the finite differences
  // (1e-10) dominate. Far from the fold it is O(1e-2).
  OrbitProblem at = pb;
  at.omega = fold->lambda;
  const Vec9 Xf = unknowns(fold->orbit);
  EXPECT_LT(singular_ratio(at, Xf), 1e-7);
  EXPECT_GT(singular_ratio(pb, table1_orbit(m, s)), 1e-4);
  // Two roots just below the fold (one from each side of it), none near it just above.
  at.omega = fold->lambda - 0.01;
  const NewtonResult lower = solve(at, unknowns(b.points[fold->after_point - 2].orbit));
  const NewtonResult upper = solve(at, unknowns(b.points[fold->after_point + 3].orbit));
  ASSERT_TRUE(lower.converged && upper.converged);
  EXPECT_GT((lower.X - upper.X).head<6>().norm(), 1e-4);
  at.omega = fold->lambda + 0.01;
  for (const auto& o : orbits_at(at)) EXPECT_GT((unknowns(o) - Xf).head<6>().norm(), 1e-2);
  report("table1_fold", fmt::format("s {} m: fold at ω {:.6f} rad/s = {:.5f}π, bead radius {:.4f} m, "
                                    "{} points, singular ratio there {:.1e}",
                                    s, fold->lambda, fold->lambda / kPi, fold->orbit.rho1, b.points.size(),
                                    singular_ratio({m, fold->lambda, Closure::Stuck, s}, Xf)));
}

TEST(Continuation, HopfCrossingCarriesTheFrequencyOfTheCrossingPair) {
  // Along the Table-1 branch a complex pair crosses the imaginary axis near 4.70π; at the
  // located crossing some eigenvalue has |Re λ| below the bisection's resolution and its
  // |Im λ| is the reported frequency.
  const physics::Model m;
  const double s = 0.544298;
  ContinuationOptions opt;
  opt.direction = -1;
  opt.lambda_min = 4.0 * kPi;
  opt.lambda_max = 6.0 * kPi;
  const Branch b = continue_branch({m, 4.75 * kPi, Closure::Stuck, s}, table1_orbit(m, s), "omega", opt);
  const BranchEvent* hopf = nullptr;
  for (const auto& e : b.events)
    if (e.kind == EventKind::Hopf && !hopf) hopf = &e;
  ASSERT_NE(hopf, nullptr);
  const Stability st = stability({m, hopf->lambda, Closure::Stuck, s}, unknowns(hopf->orbit));
  double best = 1e300, freq = 0;
  for (int i = 0; i < st.eigenvalues.size(); ++i)
    if (std::abs(st.eigenvalues(i).real()) < best) best = std::abs(st.eigenvalues(i).real()), freq = std::abs(st.eigenvalues(i).imag());
  EXPECT_LT(best, 1e-6);
  EXPECT_NEAR(freq, hopf->frequency, 1e-6 * freq);
  report("table1_hopf", fmt::format("ω {:.6f} rad/s = {:.5f}π, frequency {:.4f} rad/s", hopf->lambda,
                                    hopf->lambda / kPi, hopf->frequency));
}

TEST(Continuation, InADriveRadiusLandsOnTheDirectSolution) {
  // From R = 1 cm to beyond 2 cm on the bottom-stop orbit at 2π: the point where the branch
  // passes R = 2 cm (linear interpolation between two points, error O(step²) ≈ 4e-4 of l)
  // agrees with Newton's solution there.
  const physics::Model m;
  const OrbitProblem pb{m, 2 * kPi, Closure::BottomStop, 0.0};
  const auto found = orbits_at(pb);
  ASSERT_FALSE(found.empty());
  ContinuationOptions opt;
  opt.lambda_min = 0.005;
  opt.lambda_max = 0.025;
  const Branch b = continue_branch(pb, unknowns(found.front()), "drive_radius", opt);
  ASSERT_GT(b.points.size(), 3u);
  for (std::size_t i = 1; i < b.points.size(); ++i) {
    const double a = b.points[i - 1].lambda, c = b.points[i].lambda;
    if ((a - 0.02) * (c - 0.02) > 0) continue;
    const double t = (0.02 - a) / (c - a);
    const Vec9 X = (1 - t) * unknowns(b.points[i - 1].orbit) + t * unknowns(b.points[i].orbit);
    OrbitProblem at = pb;
    at.model.p.drive_radius = 0.02;
    const NewtonResult r = solve(at, X);
    ASSERT_TRUE(r.converged);
    EXPECT_LT((r.X - X).head<6>().norm(), 4e-4 * m.p.string_length);
    return;
  }
  FAIL() << "the branch did not pass R = 2 cm: " << b.stop_reason;
}
