#include "orbits/lagging_orbit.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "numerics/damped_newton.hpp"
#include "orbits/continuation.hpp"
#include "orbits/corotating_frame.hpp"
#include "orbits/orbit_stability.hpp"
#include "orbits/orbit_families.hpp"
#include "physics/astrojax_system.hpp"
#include "physics/tie.hpp"

namespace ajx::orbits {

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
using Vec10 = Eigen::Matrix<double, 10, 1>;
using Mat10 = Eigen::Matrix<double, 10, 10>;
using Vec14 = Eigen::Matrix<double, 14, 1>;  // (q1, q2, ϑ, q̇1, q̇2, ϑ̇), ϑ = R θ the tie's arc [m]

// τ = −R (ŷ·u1) F1 of the unknowns X = (p1, p2, F1, F2, s), top at (R, 0, 0).
double drive_torque(const physics::Model& m, const Vec9& X) {
  const double R = m.p.drive_radius;
  const Vec3 u1 = (X.segment<3>(0) - Vec3(R, 0, 0)).normalized();
  return -R * u1.y() * X(6);
}

// Torques are measured against W R, the weight of the pair on the rod's lever.
double torque_scale(const physics::Model& m) { return scales(m).force * m.p.drive_radius; }

// dw/dt in the frame turning at ω_b with the tie slipping forward (θ = ϑ/R, θ̇ = ϑ̇/R): the
// balls' as corotating_frame.hpp's, and θ̈ = χ̈ (physics::top_kinematics solves it with F1).
Vec14 frame_rhs(const physics::Model& m, const physics::MotorSchedule& motor, double omega_b,
                const physics::Contact& c, const Vec14& w) {
  namespace idx = physics::idx;
  const double R = m.p.drive_radius;
  Vec12 z;
  z << w.segment<6>(0), w.segment<6>(7);
  numerics::Vec y = lab_state(z, omega_b, idx::dim_tie);
  y(idx::chi) = w(6) / R;
  y(idx::chi_dot) = omega_b + w(13) / R;
  const physics::TopKinematics top = physics::top_kinematics(m, motor, c, 0.0, y);
  const physics::Dynamics d = physics::evaluate(m, top, c, y, true);
  const Vec12 dz = frame_derivative(z, d.acc1, d.acc2, omega_b);
  Vec14 dw;
  dw << dz.segment<6>(0), w(13), dz.segment<6>(6), R * top.omega_dot;
  return dw;
}

// Newton on the ten equations (the nine of steady_orbit.hpp at ω = ω_b, and the tie's balance)
// in (X, ω_b), from a guess (numerics/damped_newton.hpp).
struct LagRoot {
  Vec9 X;
  double omega = 0.0;
  bool converged = false;
};
LagRoot solve_lag(const physics::Model& m, double s, double omega_m, Vec9 X, double w) {
  // z = (X, ω_b): the nine equations at ω = ω_b and the tie's balance.
  const auto F = [&](const Vec10& z) {
    Vec10 r;
    r.head<9>() = residual({m, z(9), Closure::Stuck, s}, z.head<9>());
    r(9) = (drive_torque(m, z.head<9>()) - clutch_torque(m, omega_m, z(9))) / torque_scale(m);
    return r;
  };
  const Scales sc = scales(m);
  Vec10 d;
  d << Vec3::Constant(sc.length), Vec3::Constant(sc.length), sc.force, sc.force, sc.length, omega_m;
  Vec10 z;
  z << X, w;
  const auto root = numerics::damped_newton<10>(
      F, z, d, default_tolerance({m, omega_m, Closure::Stuck, s}), 60,
      [](const Mat10& J, const Vec10& r) -> Vec10 { return -J.colPivHouseholderQr().solve(r); },
      [](const Vec10& dx) { return dx; });
  return {root.x.head<9>(), root.x(9), root.converged};
}

// ω_m = ω_b + (τ − τ_k)/c_a; NaN where no motor speed gives τ with the tie slipping forward
// (τ < τ_k, or c_a = 0).
double omega_m_of(const physics::Model& m, double omega_b, double torque) {
  const double w = m.p.tie_damping > 0.0 ? omega_b + (torque - m.p.tie_kinetic_torque) / m.p.tie_damping
                                         : std::numeric_limits<double>::quiet_NaN();
  return w > omega_b ? w : std::numeric_limits<double>::quiet_NaN();
}

LagOrbit make_lag(const physics::Model& m, const SteadyOrbit& o, double omega_m, bool with_stability) {
  LagOrbit L;
  L.orbit = o;
  L.torque = tie_drive_torque(m, o);
  L.omega_m = omega_m;
  if (with_stability) L.st = lag_stability(m, o);
  return L;
}

void require_clutch(const physics::Model& m) {
  if (!m.layers.tie_clutch) throw std::invalid_argument("the lagging orbit needs [layers] tie = \"clutch\"");
  if (!(m.p.drive_radius > 0.0)) throw std::invalid_argument("the lagging orbit needs model.drive_radius > 0");
}

// The points of the stuck branch through X0 at ω0, continued both ways in ω over [lo, hi],
// in order along the branch.
std::vector<BranchPoint> branch_path(const physics::Model& m, double s, double omega0, const Vec9& X0, double lo,
                                     double hi) {
  ContinuationOptions copt;
  copt.lambda_min = lo;
  copt.lambda_max = hi;
  copt.stability = false;
  std::vector<BranchPoint> path;
  for (int dir : {-1, +1}) {
    copt.direction = dir;
    const Branch b = continue_branch({m, omega0, Closure::Stuck, s}, X0, "omega", copt);
    if (dir < 0) path.assign(b.points.rbegin(), b.points.rend());
    else path.insert(path.end(), b.points.begin() + (path.empty() || b.points.empty() ? 0 : 1), b.points.end());
  }
  return path;
}

}  // namespace

double tie_drive_torque(const physics::Model& m, const SteadyOrbit& o) { return drive_torque(m, unknowns(o)); }

double separation(const SteadyOrbit& a, const SteadyOrbit& b) { return (a.p1 - b.p1).norm() + (a.p2 - b.p2).norm(); }

double lag_motor_speed(const physics::Model& m, double omega_b, double torque) { return omega_m_of(m, omega_b, torque); }

double clutch_torque(const physics::Model& m, double omega_m, double omega_ball) {
  return m.p.tie_kinetic_torque + m.p.tie_damping * (omega_m - omega_ball);
}

LagStability lag_stability(const physics::Model& m0, const SteadyOrbit& o) {
  require_clutch(m0);
  const double R = m0.p.drive_radius, wb = o.omega, l = m0.p.string_length, s = o.s;
  // The linearisation sees ω_m only through −c_a χ̇: hold the equilibrium's τ at ω_m = ω_b + 1 rad/s.
  physics::Model m = m0;
  const double tau = tie_drive_torque(m0, o), w_motor = wb + 1.0;
  m.p.tie_kinetic_torque = tau - m.p.tie_damping * (w_motor - wb);
  const physics::MotorSchedule motor(R, {{w_motor, w_motor, 1e9}});
  physics::Contact c(physics::Mode::Stuck, 0, s);
  c.tie.slip = true;
  c.tie.sigma = +1;
  Vec14 w0 = Vec14::Zero();
  w0.segment<3>(0) = o.p1;
  w0.segment<3>(3) = o.p2;
  // The constraint gradients in q = (q1, q2, ϑ) at ϑ = 0, a = (R, 0, 0), ∂a/∂ϑ = ŷ:
  //   g1 = |q1 − a| − s:      (u1, 0, −u1·ŷ);   g2 = |q2 − q1| − (l − s):  (−u2, u2, 0).
  const Vec3 a(R, 0, 0), u1 = (o.p1 - a).normalized(), u2 = (o.p2 - o.p1).normalized();
  Eigen::Matrix<double, 2, 7> J = Eigen::Matrix<double, 2, 7>::Zero();
  J.block<1, 3>(0, 0) = u1.transpose();
  J(0, 6) = -u1.y();
  J.block<1, 3>(1, 0) = -u2.transpose();
  J.block<1, 3>(1, 3) = u2.transpose();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(Eigen::MatrixXd(J), Eigen::ComputeFullV);
  const Eigen::MatrixXd K = svd.matrixV().rightCols(5);
  // The symmetry: all of (q1, q2, ϑ) turned about z, ξ = (ẑ×q1, ẑ×q2, R); first basis vector.
  Eigen::Matrix<double, 7, 1> xi;
  xi << Vec3::UnitZ().cross(o.p1), Vec3::UnitZ().cross(o.p2), R;
  xi.normalize();
  const Eigen::MatrixXd rest = K - xi * (xi.transpose() * K);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd2(rest, Eigen::ComputeThinU);
  Eigen::Matrix<double, 7, 5> N;
  N.col(0) = xi;
  N.rightCols<4>() = svd2.matrixU().leftCols(4);
  Eigen::Matrix<double, 14, 10> P = Eigen::Matrix<double, 14, 10>::Zero();
  P.block<7, 5>(0, 0) = N;
  P.block<7, 5>(7, 5) = N;
  // Central differences as in orbit_stability.cpp: steps ε^(1/3) of the shorter link L and of L ω_b.
  const double L = std::min(s, l - s), h = std::cbrt(kEps);
  const double vscale = L * std::max(wb, std::sqrt(m.p.gravity / L));
  Eigen::Matrix<double, 10, 10> B;
  for (int j = 0; j < 10; ++j) {
    const double hj = h * (j < 5 ? L : vscale);
    const Vec14 dw = hj * P.col(j);
    B.col(j) = P.transpose() * ((frame_rhs(m, motor, wb, c, w0 + dw) - frame_rhs(m, motor, wb, c, w0 - dw)) / (2 * hj));
  }
  // B ξ = 0: the first column vanishes, and the other nine eigenvalues are those of the rest.
  LagStability st;
  st.symmetry_eigenvalue = B(0, 0);
  Eigen::EigenSolver<Eigen::MatrixXd> es(B.bottomRightCorner<9, 9>());
  const Eigen::VectorXcd ev = es.eigenvalues();
  const std::vector<int> order = growth_order(ev);
  st.eigenvalues.resize(ev.size());
  for (int i = 0; i < int(ev.size()); ++i) st.eigenvalues(i) = ev(order[i]);
  st.growth = st.eigenvalues(0).real();
  st.frequency = std::abs(st.eigenvalues(0).imag());
  st.stable = st.growth < growth_noise(m, wb);
  return st;
}

std::vector<LagOrbit> lag_orbits(const physics::Model& m, double s, double omega_m, const LagSearch& opt) {
  require_clutch(m);
  const double lo = opt.omega_hi > opt.omega_lo ? opt.omega_lo : 0.1 * omega_m;
  const double hi = opt.omega_hi > opt.omega_lo ? opt.omega_hi : omega_m;
  const auto f = [&](const BranchPoint& p) {
    return tie_drive_torque(m, p.orbit) - clutch_torque(m, omega_m, p.lambda);
  };
  std::vector<LagOrbit> out;
  std::vector<std::vector<BranchPoint>> traced;
  constexpr int kStarts = 8;  // the stuck family's branches at s, picked up at 8 speeds across [lo, hi]
  for (int k = 0; k < kStarts; ++k) {
    const double w0 = lo + (hi - lo) * (k + 0.5) / kStarts;
    for (const SteadyOrbit& o : orbits_at({m, w0, Closure::Stuck, s})) {
      // A start on a branch already traced over [lo, hi] adds nothing.
      if (std::any_of(traced.begin(), traced.end(),
                      [&](const std::vector<BranchPoint>& b) { return on_branch(b, o, m.p.string_length); }))
        continue;
      const std::vector<BranchPoint>& path = traced.emplace_back(branch_path(m, s, w0, unknowns(o), lo, hi));
      for (std::size_t i = 0; i + 1 < path.size(); ++i) {
        const double fa = f(path[i]), fb = f(path[i + 1]);
        if (!(fa * fb <= 0.0) || fa == fb) continue;
        // The secant's point as the guess for the ten-equation Newton.
        const double t = fa / (fa - fb);
        const Vec9 X = (1 - t) * unknowns(path[i].orbit) + t * unknowns(path[i + 1].orbit);
        const double w = (1 - t) * path[i].lambda + t * path[i + 1].lambda;
        const LagRoot r = solve_lag(m, s, omega_m, X, w);
        if (!r.converged || !(r.omega > lo && r.omega < hi)) continue;
        const SteadyOrbit orbit = describe({m, r.omega, Closure::Stuck, s}, r.X);
        const bool seen = std::any_of(out.begin(), out.end(), [&](const LagOrbit& q) {
          return std::abs(q.orbit.omega - r.omega) <= 1e-8 * omega_m &&
                 separation(q.orbit, orbit) <= 1e-7 * m.p.string_length;
        });
        if (!seen) out.push_back(make_lag(m, orbit, omega_m, opt.stability));
      }
    }
  }
  std::sort(out.begin(), out.end(), [](const LagOrbit& x, const LagOrbit& y) { return x.orbit.omega < y.orbit.omega; });
  return out;
}

LagBranch lag_branch(const physics::Model& m, const SteadyOrbit& start, double omega_lo, double omega_hi) {
  require_clutch(m);
  const double s = start.s;
  LagBranch br;
  for (const BranchPoint& p : branch_path(m, s, start.omega, unknowns(start), omega_lo, omega_hi)) {
    const double tau = tie_drive_torque(m, p.orbit);
    br.points.push_back(make_lag(m, p.orbit, omega_m_of(m, p.lambda, tau), true));
  }
  // Bisection in ω_b between two neighbours whose predicate differs; each trial orbit solved at
  // fixed ω_b from the interpolated unknowns.
  const auto locate = [&](const LagOrbit& a, const LagOrbit& b, auto pred) {
    LagOrbit lo = a, hi = b;
    const bool at_lo = pred(a);
    for (int k = 0; k < 60 && std::abs(hi.orbit.omega - lo.orbit.omega) > 1e-10 * hi.orbit.omega; ++k) {
      const double w = 0.5 * (lo.orbit.omega + hi.orbit.omega);
      const Vec9 X = 0.5 * (unknowns(lo.orbit) + unknowns(hi.orbit));
      const NewtonResult r = solve({m, w, Closure::Stuck, s}, X);
      if (!r.converged) break;
      const SteadyOrbit o = describe({m, w, Closure::Stuck, s}, r.X);
      const LagOrbit mid = make_lag(m, o, omega_m_of(m, w, tie_drive_torque(m, o)), true);
      (pred(mid) == at_lo ? lo : hi) = mid;
    }
    return hi;
  };
  const auto stable = [](const LagOrbit& L) { return L.st.stable; };
  const auto held = [](const LagOrbit& L) { return L.orbit.admissible; };
  for (std::size_t i = 0; i + 1 < br.points.size(); ++i) {
    const LagOrbit &a = br.points[i], &b = br.points[i + 1];
    // "As τ grows": orient each pair by its torque.
    const bool rising = b.torque >= a.torque;
    const LagOrbit &before = rising ? a : b, &after = rising ? b : a;
    if (stable(a) != stable(b)) {
      const LagOrbit at = locate(before, after, stable);
      br.events.push_back({stable(before) ? LagEventKind::StabilityLoss : LagEventKind::StabilityGain, at,
                           at.st.frequency > 1e-6 * at.orbit.omega});
    }
    if (held(a) != held(b))
      br.events.push_back({held(before) ? LagEventKind::ConeExit : LagEventKind::ConeEntry, locate(before, after, held)});
  }
  return br;
}

}  // namespace ajx::orbits
