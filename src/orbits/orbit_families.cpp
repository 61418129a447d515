#include "orbits/orbit_families.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace ajx::orbits {

Vec9 unknowns(const SteadyOrbit& o) {
  Vec9 X;
  X << o.p1, o.p2, o.F1, o.F2, o.s;
  return X;
}

std::vector<Vec9> planar_guesses(const physics::Model& m, double omega, double L1, double L2, int n) {
  const physics::Parameters& p = m.p;
  const double m1 = p.bead_mass, m2 = p.ball_mass, M = m1 + m2, g = p.gravity, R = p.drive_radius;
  const double w2 = omega * omega;
  const auto F = [&](const Eigen::Vector2d& th, Eigen::Matrix2d* J) {
    const double s1 = std::sin(th(0)), c1 = std::cos(th(0)), s2 = std::sin(th(1)), c2 = std::cos(th(1));
    const double x1 = R + L1 * s1, x2 = x1 + L2 * s2, mx = m1 * x1 + m2 * x2;
    if (J) {
      *J << M * g * c1 + w2 * mx * s1 - w2 * M * L1 * c1 * c1, -w2 * m2 * L2 * c2 * c1,
          -w2 * L1 * c1 * c2, g * c2 + w2 * x2 * s2 - w2 * L2 * c2 * c2;
    }
    return Eigen::Vector2d(M * g * s1 - w2 * mx * c1, g * s2 - w2 * x2 * c2);
  };
  constexpr double half_pi = 0.5 * std::numbers::pi;
  std::vector<Eigen::Vector2d> roots;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      Eigen::Vector2d th(-half_pi + (i + 0.5) * (2 * half_pi / n), -half_pi + (j + 0.5) * (2 * half_pi / n));
      bool ok = false;
      for (int it = 0; it < 60; ++it) {
        Eigen::Matrix2d J;
        const Eigen::Vector2d f = F(th, &J);
        if (f.lpNorm<Eigen::Infinity>() < 1e-13 * M * g * (1 + w2 * (L1 + L2) / g)) {
          ok = true;
          break;
        }
        Eigen::Vector2d d = J.fullPivLu().solve(-f);
        if (!d.allFinite()) break;
        if (d.norm() > 0.3) d *= 0.3 / d.norm();
        th += d;
        if (std::abs(th(0)) >= half_pi || std::abs(th(1)) >= half_pi) break;
      }
      if (!ok) continue;
      if (std::none_of(roots.begin(), roots.end(), [&](const Eigen::Vector2d& r) { return (r - th).norm() < 1e-7; }))
        roots.push_back(th);
    }
  std::vector<Vec9> out;
  for (const auto& th : roots) {
    const double x1 = R + L1 * std::sin(th(0)), z1 = -L1 * std::cos(th(0));
    Vec9 X;
    X << x1, 0, z1, x1 + L2 * std::sin(th(1)), 0, z1 - L2 * std::cos(th(1)), M * g / std::cos(th(0)),
        m2 * g / std::cos(th(1)), L1;
    out.push_back(X);
  }
  return out;
}

namespace {
// From the drag-free root (exact for c_D = 0) to the model's drag in steps: a drag that
// turns the orbit far out of the plane needs the path, not one Newton jump. Given up once the
// step falls to min_step.
NewtonResult drag_homotopy(const OrbitProblem& pb, const Vec9& guess, double min_step) {
  OrbitProblem q = pb;
  q.model.p.drag = 0.0;
  NewtonResult r = solve(q, guess);
  double frac = 0.0, step = 0.125;
  while (r.converged && frac < 1.0 && step > min_step) {
    const double next = std::min(1.0, frac + step);
    q.model.p.drag = next * pb.model.p.drag;
    const NewtonResult t = solve(q, r.X);
    if (t.converged) {
      r = t;
      frac = next;
      step *= 1.5;
    } else {
      step *= 0.5;
    }
  }
  if (frac < 1.0) r.converged = false;
  return r;
}
}  // namespace

std::vector<SteadyOrbit> orbits_at(const OrbitProblem& pb, const SolveEffort& effort) {
  const double l = pb.model.p.string_length;
  const double s = pb.closure == Closure::BottomStop ? l - pb.model.p.contact_distance : pb.s_star;
  std::vector<SteadyOrbit> out;
  for (const Vec9& guess : planar_guesses(pb.model, pb.omega, s, l - s, effort.starts)) {
    NewtonResult r = solve(pb, guess);
    if (!r.converged) r = drag_homotopy(pb, guess, effort.homotopy_min_step);
    if (!r.converged) continue;
    const bool seen = std::any_of(out.begin(), out.end(), [&](const SteadyOrbit& o) {
      return (unknowns(o).head<6>() - r.X.head<6>()).norm() < 1e-8 * l;
    });
    if (!seen) out.push_back(describe(pb, r.X));
  }
  std::sort(out.begin(), out.end(), [](const SteadyOrbit& a, const SteadyOrbit& b) { return a.p2.x() < b.p2.x(); });
  return out;
}

namespace {
// The orbit of `candidates` on the same branch nearest to o (for sign changes along s).
const SteadyOrbit* neighbour(const SteadyOrbit& o, const std::vector<SteadyOrbit>& candidates) {
  const SteadyOrbit* best = nullptr;
  double dist = 0;
  for (const auto& c : candidates) {
    if (c.branch != o.branch) continue;
    const double d = (c.p1 - o.p1).norm() + (c.p2 - o.p2).norm();
    if (!best || d < dist) best = &c, dist = d;
  }
  return best;
}

void add_unique(std::vector<SteadyOrbit>& list, const SteadyOrbit& o, double l) {
  const bool seen = std::any_of(list.begin(), list.end(), [&](const SteadyOrbit& q) {
    return q.closure == o.closure && (q.p1 - o.p1).norm() + (q.p2 - o.p2).norm() < 1e-8 * l;
  });
  if (!seen) list.push_back(o);
}
}  // namespace

std::vector<double> stuck_grid(const physics::Model& m, int n) {
  const physics::Parameters& p = m.p;
  const double l = p.string_length;
  const double s_lo = m.layers.top_stop ? p.top_stop : 1e-3 * l;
  const double s_hi = m.layers.bottom_stop ? l - p.contact_distance : (1 - 1e-3) * l;
  n = std::max(n, 2);
  std::vector<double> s(n);
  for (int k = 0; k < n; ++k) s[k] = s_lo + (s_hi - s_lo) * k / (n - 1);
  return s;
}

OrbitCatalogue find_orbits(const physics::Model& m, double omega, const CatalogueOptions& opt) {
  const double l = m.p.string_length;
  OrbitCatalogue cat;
  std::vector<std::vector<SteadyOrbit>> rows;
  const std::vector<double> grid = stuck_grid(m, opt.s_points);
  const int n = int(grid.size());
  for (const double s : grid) {
    rows.push_back(orbits_at({m, omega, Closure::Stuck, s}));
    cat.stuck.insert(cat.stuck.end(), rows.back().begin(), rows.back().end());
  }
  if (m.layers.bottom_stop) cat.bottom = orbits_at({m, omega, Closure::BottomStop, 0.0});
  // Between neighbouring s on one branch, a sign change of T1 − T2 brackets a frictionless
  // orbit, and of a cone margin an edge: solve for it from the interpolated guess.
  const auto refine = [&](const SteadyOrbit& a, const SteadyOrbit& b, Closure c, double fa, double fb,
                          std::vector<SteadyOrbit>& list) {
    if (!(fa * fb < 0) || !std::isfinite(fa) || !std::isfinite(fb)) return;
    const double t = fa / (fa - fb);
    OrbitProblem pb{m, omega, c, 0.0};
    const NewtonResult r = solve(pb, (1 - t) * unknowns(a) + t * unknowns(b));
    if (r.converged) add_unique(list, describe(pb, r.X), l);
  };
  for (int k = 0; k + 1 < n; ++k)
    for (const SteadyOrbit& a : rows[k]) {
      const SteadyOrbit* b = neighbour(a, rows[k + 1]);
      if (!b) continue;
      refine(a, *b, Closure::Frictionless, a.F1 - a.F2, b->F1 - b->F2, cat.frictionless);
      refine(a, *b, Closure::ConeUp, a.margins.up, b->margins.up, cat.edges);
      refine(a, *b, Closure::ConeDown, a.margins.down, b->margins.down, cat.edges);
    }
  return cat;
}

}  // namespace ajx::orbits
