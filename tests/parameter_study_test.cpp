// The paper's parameter study (its Fig. 9) as properties of the co-rotating equilibria: with
// m1 = m2 = m the orbit's geometry does not depend on m and the tensions scale with m, except
// through the drag. In the scaled unknowns X̂ = (p/l, F/W, s/l), W = 2 m g, the force balance
//   −m ω² P p = −F1 u1 + F2 u2 − c_D Ω×p − m g ẑ     (divided by W)
// reads  ω² P p/(2g) + (−F̂1 u1 + F̂2 u2) − ε ω² ẑ×p/(2g) − ẑ/2 = 0  with ε = c_D/(m ω):
// m enters only through the small parameter ε (6.4e-3 at m = 18 g, 4.8π).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <fmt/format.h>
#include <numbers>
#include <vector>

#include "measured.hpp"
#include "orbits/orbit_families.hpp"
#include "orbits/steady_orbit.hpp"

using namespace ajx;
using namespace ajx::orbits;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kLight = 0.018, kHeavy = 0.1;  // m [kg], the paper's two masses

physics::Model with_mass(double m, double drag) {
  physics::Model model;
  model.p.bead_mass = model.p.ball_mass = m;
  model.p.drag = drag;
  model.p.drive_radius = 0.015;
  model.p.contact_distance = 0.035;
  return model;
}

// X in units of l (positions, s) and W = (m1 + m2) g (forces).
Vec9 scaled(const physics::Model& m, const Vec9& X) {
  const Scales sc = scales(m);
  Vec9 out = X / sc.length;
  out.segment<2>(6) = X.segment<2>(6) / sc.force;
  return out;
}
Vec9 unscaled(const physics::Model& m, const Vec9& Xh) {
  const Scales sc = scales(m);
  Vec9 out = Xh * sc.length;
  out.segment<2>(6) = Xh.segment<2>(6) * sc.force;
  return out;
}

// ∂r/∂X̂: the Jacobian in the scaled unknowns.
Mat9 scaled_jacobian(const OrbitProblem& pb, const Vec9& X) {
  const Scales sc = scales(pb.model);
  Mat9 J = jacobian(pb, X);
  J.leftCols<6>() *= sc.length;
  J.col(6) *= sc.force;
  J.col(7) *= sc.force;
  J.col(8) *= sc.length;
  return J;
}

double smallest_singular_value(const Mat9& J) {
  return Eigen::JacobiSVD<Mat9>(J).singularValues()(8);
}

// dX̂/dε = −Ĵ⁻¹ ∂r/∂ε, with ∂r/∂ε = −ω² ẑ×p_i/(2g) in ball i's force rows (m1 = m2).
Vec9 sensitivity(const OrbitProblem& pb, const Vec9& X) {
  const double k = -pb.omega * pb.omega / (2.0 * pb.model.p.gravity);
  const Vec3 z = Vec3::UnitZ();
  Vec9 dr = Vec9::Zero();
  dr.segment<3>(0) = k * z.cross(Vec3(X.segment<3>(0)));
  dr.segment<3>(3) = k * z.cross(Vec3(X.segment<3>(3)));
  return -scaled_jacobian(pb, X).fullPivLu().solve(dr);
}

std::vector<SteadyOrbit> every_orbit(const OrbitCatalogue& c) {
  std::vector<SteadyOrbit> all = c.stuck;
  for (const auto* list : {&c.bottom, &c.frictionless, &c.edges}) all.insert(all.end(), list->begin(), list->end());
  return all;
}

}  // namespace

TEST(ParameterStudy, WithoutDragTheGeometryIsIndependentOfMassAndTensionsScaleWithIt) {
  const physics::Model light = with_mass(kLight, 0.0), heavy = with_mass(kHeavy, 0.0);
  double worst_ratio = 0.0;  // measured difference over its bound, worst case
  int compared = 0;
  for (double w : {4.8 * kPi, 15.0 * kPi}) {
    const auto a = every_orbit(find_orbits(light, w, {21})), b = every_orbit(find_orbits(heavy, w, {21}));
    ASSERT_EQ(a.size(), b.size()) << "the same orbits at both masses, ω_m = " << w / kPi << "π";
    for (const SteadyOrbit& oa : a) {
      const OrbitProblem pa{light, w, oa.closure, oa.s};
      const Vec9 Xa = scaled(light, unknowns(oa));
      // The partner: same closure (and s for the stuck family), nearest in X̂.
      const SteadyOrbit* ob = nullptr;
      double nearest = INFINITY;
      for (const SteadyOrbit& o : b) {
        if (o.closure != oa.closure || (oa.closure == Closure::Stuck && o.s != oa.s)) continue;
        const double dist = (scaled(heavy, unknowns(o)) - Xa).norm();
        if (dist < nearest) nearest = dist, ob = &o;
      }
      ASSERT_NE(ob, nullptr);
      // Both solves stop at a scaled residual ≤ tol (Newton's tolerance, the same for both: it
      // depends on ω, l, g only), and the scaled equations are the same, so the roots differ by
      // at most |Ĵ⁻¹| (r_a + r_b) ≤ 2 tol / σ_min(Ĵ) (2-norm, which bounds every component).
      const double tol = default_tolerance(pa);
      ASSERT_LE(oa.residual, tol);
      ASSERT_LE(ob->residual, tol);
      const double bound = 2.0 * tol / smallest_singular_value(scaled_jacobian(pa, unknowns(oa)));
      const Vec9 Xb = scaled(heavy, unknowns(*ob));
      const double diff = (Xb - Xa).lpNorm<Eigen::Infinity>();
      EXPECT_LE(diff, bound) << to_string(oa.closure) << " at s = " << oa.s << ", ω_m = " << w / kPi << "π";
      // T1, T2 and the ball's push are homogeneous in the pulls: T/(m g) is X̂'s as well.
      const double Wa = scales(light).force, Wb = scales(heavy).force;
      for (auto [ta, tb] : {std::pair{oa.T1, ob->T1}, {oa.T2, ob->T2}, {oa.contact, ob->contact}})
        EXPECT_LE(std::abs(tb / Wb - ta / Wa), bound) << "tension not ∝ m: " << ta << " N and " << tb << " N";
      worst_ratio = std::max(worst_ratio, diff / bound);
      ++compared;
    }
  }
  EXPECT_GT(compared, 50);  // the stuck family, the bottom stop, frictionless orbits, cone edges
  report("parameter study without drag: orbits compared at 4.8π and 15π", std::to_string(compared));
  report("parameter study without drag: largest |ΔX̂| over its bound 2 tol/σ_min", fmt::format("{:.3g}", worst_ratio));
}

TEST(ParameterStudy, WithThePapersDragTheChangeIsBoundedByTheDragParameter) {
  // From m = 18 g to 0.1 kg at the paper's c_D, ε = c_D/(m ω) changes by Δε and the scaled root
  // moves by ΔX̂ = ∫ S dε, S = dX̂/dε = −Ĵ⁻¹ ∂r/∂ε. So |ΔX̂_i| ≤ max |S_i| |Δε| over the way, which
  // is sampled at both ends and in the middle of the ε interval (S varies smoothly there: the
  // three samples differ by less than their size, checked), plus the solvers' 2 tol/σ_min.
  const double cD = physics::Parameters{}.drag;
  const physics::Model light = with_mass(kLight, cD), heavy = with_mass(kHeavy, cD);
  double worst_shape = 0.0, worst_phase = 0.0, worst_T = 0.0, worst_ratio = 0.0, worst_bound_mm = 0.0;
  int compared = 0;
  for (double w : {4.8 * kPi, 15.0 * kPi}) {
    const double eps_a = cD / (kLight * w), eps_b = cD / (kHeavy * w), d_eps = eps_b - eps_a;
    const physics::Model middle = with_mass(cD / (0.5 * (eps_a + eps_b) * w), cD);
    const OrbitCatalogue cat = find_orbits(light, w, {21});
    std::vector<SteadyOrbit> chosen = cat.frictionless;
    chosen.insert(chosen.end(), cat.bottom.begin(), cat.bottom.end());
    for (const auto& o : cat.stuck)
      if (o.admissible) chosen.push_back(o);
    for (const SteadyOrbit& oa : chosen) {
      const Vec9 Xa = unknowns(oa);
      std::vector<Vec9> S{sensitivity({light, w, oa.closure, oa.s}, Xa)};
      Vec9 Xb;
      for (const physics::Model* m : {&middle, &heavy}) {
        const OrbitProblem pb{*m, w, oa.closure, oa.s};
        const NewtonResult nb = solve(pb, unscaled(*m, scaled(light, Xa)));
        ASSERT_TRUE(nb.converged) << to_string(oa.closure) << " at s = " << oa.s << ": no partner at m = " << m->p.bead_mass;
        S.push_back(sensitivity(pb, nb.X));
        Xb = nb.X;
      }
      Vec9 S_max = S[0].cwiseAbs();
      for (const Vec9& Si : S) S_max = S_max.cwiseMax(Si.cwiseAbs());
      ASSERT_LT((S[2] - S[0]).lpNorm<Eigen::Infinity>(), S_max.maxCoeff())
          << "S changes by more than its size: the sampled bound does not apply";
      const double tol = default_tolerance({light, w, oa.closure, oa.s});
      const double solver = 2.0 * tol / smallest_singular_value(scaled_jacobian({light, w, oa.closure, oa.s}, Xa));
      const Vec9 dX = scaled(heavy, Xb) - scaled(light, Xa);
      for (int i = 0; i < 9; ++i) {
        const double bound = S_max(i) * std::abs(d_eps) + solver;
        EXPECT_LE(std::abs(dX(i)), bound) << "component " << i << " of " << to_string(oa.closure) << " at s = " << oa.s
                                          << ", ω_m = " << w / kPi << "π";
        worst_ratio = std::max(worst_ratio, std::abs(dX(i)) / bound);
      }
      worst_bound_mm = std::max(worst_bound_mm, 1e3 * light.p.string_length * S_max.head<6>().maxCoeff() * std::abs(d_eps));
      // What the paper compares, the shape (radii, heights), apart from the azimuth relative to
      // the top, which the drag sets (the string's pull along the orbit balances it).
      for (int b = 0; b < 2; ++b) {
        const Vec3 pa = Xa.segment<3>(3 * b), pb = Xb.segment<3>(3 * b);
        worst_shape = std::max({worst_shape, std::abs(std::hypot(pa.x(), pa.y()) - std::hypot(pb.x(), pb.y())),
                                std::abs(pa.z() - pb.z())});
        worst_phase = std::max(worst_phase, std::abs(std::remainder(std::atan2(pa.y(), pa.x()) - std::atan2(pb.y(), pb.x()),
                                                                     2 * kPi)) * std::hypot(pa.x(), pa.y()));
      }
      worst_T = std::max(worst_T, dX.segment<2>(6).lpNorm<Eigen::Infinity>() * 2.0);  // Δ(T/(m g)) = 2 ΔF̂
      ++compared;
    }
  }
  EXPECT_GT(compared, 10);
  report("parameter study with c_D: orbits compared (frictionless, bottom stop, held stuck) at 4.8π and 15π",
         std::to_string(compared));
  report("parameter study with c_D: largest change of a ball's radius or height, 18 g -> 0.1 kg",
         fmt::format("{:.3f} mm", 1e3 * worst_shape));
  report("parameter study with c_D: largest move of a ball along its orbit (azimuth change × radius)",
         fmt::format("{:.1f} mm", 1e3 * worst_phase));
  report("parameter study with c_D: largest change of T/(m g)", fmt::format("{:.3g}", worst_T));
  report("parameter study with c_D: largest derived bound max|S| Δε on a position", fmt::format("{:.1f} mm", worst_bound_mm));
  report("parameter study with c_D: largest |ΔX̂_i| over its bound", fmt::format("{:.3f}", worst_ratio));
}
