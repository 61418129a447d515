#include "orbits/threshold_curves.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "orbits/continuation.hpp"
#include "orbits/lagging_orbit.hpp"
#include "orbits/orbit_families.hpp"
#include "orbits/orbit_stability.hpp"
#include "physics/parameter_table.hpp"

namespace ajx::orbits {

std::string_view to_string(CurveKind k) {
  switch (k) {
    case CurveKind::Fold: return "fold";
    case CurveKind::ConeUp: return "cone_up";
    case CurveKind::ConeDown: return "cone_down";
    case CurveKind::Hopf: return "hopf";
  }
  return "?";
}

const std::vector<std::string>& curve_kind_names() {
  static const std::vector<std::string> names{"fold", "cone_up", "cone_down", "hopf"};
  return names;
}

CurveKind curve_kind(std::string_view name) {
  for (CurveKind k : {CurveKind::Fold, CurveKind::ConeUp, CurveKind::ConeDown, CurveKind::Hopf})
    if (to_string(k) == name) return k;
  throw std::invalid_argument("unknown curve '" + std::string(name) + "'; allowed: fold, cone_up, cone_down, hopf");
}

const std::vector<std::string>& second_parameters() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const std::string& k : continuation_parameters())
      if (k != "omega") n.push_back(k);
    return n;
  }();
  return names;
}

namespace {

using Vec10 = Eigen::Matrix<double, 10, 1>;
using Vec11 = Eigen::Matrix<double, 11, 1>;
using Mat10 = Eigen::Matrix<double, 10, 10>;
using Mat11 = Eigen::Matrix<double, 11, 11>;
using Mat10x11 = Eigen::Matrix<double, 10, 11>;
constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kPi = std::numbers::pi;
// The floor of a test function computed from central differences (G_X, the lag's matrix):
// truncation h² and round-off ε/h at h = ε^(1/3), both ε^(2/3).
const double kFdFloor = std::cbrt(kEps * kEps);

// The extended system in scaled unknowns Z = (X / dX, ω / ω_s, p / p_s), with the state the
// defining condition carries from point to point (the fold's borders, the lag's eigenvalue).
class Extended {
 public:
  Extended(const physics::Model& m, const std::string& parameter, CurveKind kind, double s, double omega0)
      : base_{m, omega0, Closure::Stuck, s}, name_(parameter), kind_(kind) {
    const Scales sc = scales(m);
    const double fs = sc.force * (1.0 + omega0 * omega0 * sc.length / m.p.gravity);
    dX_ << Vec3::Constant(sc.length), Vec3::Constant(sc.length), fs, fs, sc.length;
    force_ = fs;
    ws_ = std::sqrt(m.p.gravity / m.p.string_length);
    const double p0 = parameter_value(base_, parameter);
    ps_ = parameter == "s" ? m.p.string_length : (p0 != 0 ? std::abs(p0) : 1.0);
    rate_ = omega0 + ws_;  // the fastest rate of the orbit [1/s], as growth_noise's
    b_.setZero();
    c_.setZero();
  }

  OrbitProblem at(const Vec11& Z) const {
    OrbitProblem q = base_;
    q.omega = Z(9) * ws_;
    set_parameter(q, name_, Z(10) * ps_);
    return q;
  }
  Vec9 X(const Vec11& Z) const { return Z.head<9>().cwiseProduct(dX_); }
  Vec11 scaled(const Vec9& X, double omega, double p) const {
    Vec11 Z;
    Z << X.cwiseQuotient(dX_), omega / ws_, p / ps_;
    return Z;
  }
  double p_of(const Vec11& Z) const { return Z(10) * ps_; }
  CurveKind kind() const { return kind_; }
  const std::string& name() const { return name_; }

  // G_X in scaled unknowns.
  Mat9 GX(const OrbitProblem& q, const Vec9& X) const { return jacobian(q, X) * dX_.asDiagonal(); }

  // The defining condition g (scaled, O(1)).
  double g(const Vec11& Z) const {
    const OrbitProblem q = at(Z);
    const Vec9 x = X(Z);
    switch (kind_) {
      case CurveKind::Fold: return bordered(GX(q, x));
      case CurveKind::ConeUp: return describe(q, x).margins.up / force_;
      case CurveKind::ConeDown: return describe(q, x).margins.down / force_;
      case CurveKind::Hopf: return tracked(q, x).real() / rate_;
    }
    return 0.0;
  }
  Vec10 F(const Vec11& Z) const {
    Vec10 r;
    r.head<9>() = residual(at(Z), X(Z));
    r(9) = g(Z);
    return r;
  }
  Mat10x11 FZ(const Vec11& Z) const {
    const double h = std::cbrt(kEps);
    Mat10x11 A;
    for (int j = 0; j < 11; ++j) {
      Vec11 zp = Z, zm = Z;
      zp(j) += h;
      zm(j) -= h;
      A.col(j) = (F(zp) - F(zm)) / (2 * h);
    }
    return A;
  }
  // Newton's tolerances: the nine equations' round-off floor (steady_orbit.hpp), and g's own:
  // a margin is computed from X directly (the same floor), a bordered determinant or an
  // eigenvalue from central differences (kFdFloor).
  double tol_G(const Vec11& Z) const { return 4 * default_tolerance(at(Z)); }
  double tol_g(const Vec11& Z) const {
    return kind_ == CurveKind::ConeUp || kind_ == CurveKind::ConeDown ? tol_G(Z) : 64 * kFdFloor;
  }

  // After a point is accepted: the fold's borders from G_X's smallest singular pair, each sign
  // kept continuous; the lag's eigenvalue to follow.
  void accept(const Vec11& Z) {
    const OrbitProblem q = at(Z);
    const Vec9 x = X(Z);
    if (kind_ == CurveKind::Fold) {
      Eigen::JacobiSVD<Mat9> svd(GX(q, x), Eigen::ComputeFullU | Eigen::ComputeFullV);
      Vec9 b = svd.matrixU().col(8), c = svd.matrixV().col(8);
      if (b.dot(b_) < 0) b = -b;
      if (c.dot(c_) < 0) c = -c;
      b_ = b;
      c_ = c;
    }
    if (kind_ == CurveKind::Hopf) lambda_ = tracked(q, x);
  }
  // At a start: the lag's eigenvalue nearest the imaginary axis with Im λ > 0.
  void start_hopf(const Vec11& Z) {
    const OrbitProblem q = at(Z);
    const LagStability st = lag_stability(q.model, describe(q, X(Z)));
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i < st.eigenvalues.size(); ++i)
      if (st.eigenvalues(i).imag() > 0 && std::abs(st.eigenvalues(i).real()) < best) {
        best = std::abs(st.eigenvalues(i).real());
        lambda_ = st.eigenvalues(i);
      }
  }
  std::complex<double> tracked(const OrbitProblem& q, const Vec9& x) const {
    const LagStability st = lag_stability(q.model, describe(q, x));
    std::complex<double> best = st.eigenvalues(0);
    for (int i = 1; i < st.eigenvalues.size(); ++i)
      if (std::abs(st.eigenvalues(i) - lambda_) < std::abs(best - lambda_)) best = st.eigenvalues(i);
    return best;
  }
  double force() const { return force_; }

 private:
  // [A b; cᵀ 0] [v; g] = [0; 1]: g = 0 exactly where A is singular (b, c not in its ranges).
  double bordered(const Mat9& A) const {
    Mat10 M = Mat10::Zero();
    M.topLeftCorner<9, 9>() = A;
    M.topRightCorner<9, 1>() = b_;
    M.bottomLeftCorner<1, 9>() = c_.transpose();
    Vec10 rhs = Vec10::Zero();
    rhs(9) = 1.0;
    return M.partialPivLu().solve(rhs)(9);
  }

  OrbitProblem base_;
  std::string name_;
  CurveKind kind_;
  Vec9 dX_, b_, c_;
  double force_ = 1, ws_ = 1, ps_ = 1, rate_ = 1;
  std::complex<double> lambda_{0.0, 0.0};
};

struct Corrected {
  Vec11 Z;
  int iterations = 0;
  bool ok = false;
};
// Newton on [F(Z); n·(Z − Zp)] = 0. Converged when the equations are at their floors, or when
// the step has shrunk to round-off with the nine equations met (g's floor is an estimate).
Corrected correct(const Extended& e, const Vec11& Zp, const Vec11& n) {
  Corrected out{Zp, 0, false};
  for (int it = 0; it < 12; ++it) {
    const Vec10 f = e.F(out.Z);
    if (!f.allFinite()) return out;
    const double plane = n.dot(out.Z - Zp);
    const bool G_ok = f.head<9>().lpNorm<Eigen::Infinity>() <= e.tol_G(out.Z);
    if (G_ok && std::abs(f(9)) <= e.tol_g(out.Z) && std::abs(plane) < 1e-12) {
      out.ok = true;
      out.iterations = it;
      return out;
    }
    Mat11 A;
    A.topRows<10>() = e.FZ(out.Z);
    A.row(10) = n.transpose();
    Vec11 rhs;
    rhs << -f, -plane;
    const Vec11 dZ = A.partialPivLu().solve(rhs);
    if (!dZ.allFinite() || dZ.norm() > 0.2) return out;
    out.Z += dZ;
    if (G_ok && dZ.norm() < 1e-11) {
      out.ok = std::abs(e.F(out.Z)(9)) <= 1e3 * e.tol_g(out.Z);
      out.iterations = it + 1;
      return out;
    }
  }
  return out;
}

// A point with its tangent and the test functions of the codimension-2 points.
struct Probe {
  Vec11 Z, t;
  CurvePoint point;
  std::vector<std::pair<std::string, double>> tests;
};

Probe make_probe(const Extended& e, const Vec11& Z, const Vec11& orient, int dir) {
  Probe P;
  P.Z = Z;
  const Mat10x11 A = e.FZ(Z);
  Eigen::JacobiSVD<Mat10x11> svd(A, Eigen::ComputeFullV);
  Vec11 t = svd.matrixV().col(10).normalized();
  const double sgn = orient.squaredNorm() > 0 ? t.dot(orient) : t(10) * dir;
  P.t = sgn < 0 ? Vec11(-t) : t;
  const OrbitProblem q = e.at(Z);
  const Vec9 x = e.X(Z);
  CurvePoint& c = P.point;
  c.p = e.p_of(Z);
  c.omega = q.omega;
  c.omega_m = q.omega;
  c.orbit = describe(q, x);
  c.sigma_min = svd.singularValues()(9);
  const double up = c.orbit.margins.up / e.force(), down = c.orbit.margins.down / e.force();
  const double slack = std::min(c.orbit.T1, c.orbit.T2);
  if (e.kind() == CurveKind::Hopf) {
    const std::complex<double> lc = e.tracked(q, x);
    c.frequency = std::abs(lc.imag());
    c.torque = tie_drive_torque(q.model, c.orbit);
    c.omega_m = lag_motor_speed(q.model, q.omega, c.torque);
    P.tests = {{"hopf+cone_up", up}, {"hopf+cone_down", down}, {"slack", slack}};
    return P;
  }
  const Stability st = stability(q, x);
  for (int i = 0; i < st.eigenvalues.size(); ++i) c.unstable += st.eigenvalues(i).real() > growth_noise(q.model, q.omega);
  const std::string k(to_string(e.kind()));
  const double det = e.kind() == CurveKind::Fold ? 1.0 : e.GX(q, x).determinant();
  if (e.kind() == CurveKind::Fold) P.tests = {{"fold+cone_up", up}, {"fold+cone_down", down}};
  else if (e.kind() == CurveKind::ConeUp) P.tests = {{"cone_up+fold", det}, {"cone_up+cone_down", down}};
  else P.tests = {{"cone_down+fold", det}, {"cone_down+cone_up", up}};
  P.tests.push_back({"slack", slack});
  // The locked orbit's stability along a fold or cone curve (on a fold curve one eigenvalue
  // sits at zero, and the count is noise there).
  if (e.kind() != CurveKind::Fold) P.tests.push_back({"stability", c.unstable > 0 ? -1.0 : 1.0});
  return P;
}

// The codimension-2 points between two neighbours: bisection on each test function whose sign
// changed, every midpoint corrected onto the curve.
void add_meets(const Extended& e, const Probe& a, const Probe& b, int after, std::vector<Codim2Point>& out) {
  for (std::size_t k = 0; k < a.tests.size(); ++k) {
    const double fa = a.tests[k].second, fb = b.tests[k].second;
    if (!std::isfinite(fa) || !std::isfinite(fb) || (fa < 0) == (fb < 0)) continue;
    const Vec11 d = (b.Z - a.Z).normalized();
    double lo = 0, hi = 1;
    Probe at = b;
    for (int it = 0; it < 40; ++it) {
      const double mid = 0.5 * (lo + hi);
      const Corrected cm = correct(e, a.Z + mid * (b.Z - a.Z), d);
      if (!cm.ok) break;
      const Probe pm = make_probe(e, cm.Z, a.t, 0);
      const bool same = (pm.tests[k].second < 0) == (fa < 0);
      (same ? lo : hi) = mid;
      if (!same) at = pm;
    }
    std::string kind = a.tests[k].first;
    if (kind == "stability") kind += fb < 0 ? " (the locked orbit turns unstable)" : " (the locked orbit turns stable)";
    out.push_back({kind, at.point, after});
  }
}

// Why the curve ends at P, or "".
std::string stop_reason(const Extended& e, const Probe& P, const CurveOptions& opt, double s_lo, double s_hi) {
  const double p = P.point.p, w = P.point.omega;
  if (p < opt.p_lo || p > opt.p_hi) return "left the parameter range";
  if (const physics::ParameterInfo* info = physics::find_parameter(e.name()); info && !info->in_range(p))
    return "left the parameter's allowed range " + info->range();
  if (e.name() == "mass" && !(p > 0)) return "the mass reached 0";
  if (e.name() == "s" && !(p > s_lo && p < s_hi)) return "the bead reached a stop";
  if (w < opt.omega_lo || w > opt.omega_hi) return "left the ω range";
  if (!std::isfinite(P.point.orbit.rho1 + P.point.orbit.rho2 + P.point.orbit.T1 + P.point.orbit.T2))
    return "the orbit is not finite";
  return "";
}

// The options with their defaults filled in for the model m and the parameter.
CurveOptions resolved(const physics::Model& m, const std::string& parameter, double s, CurveOptions opt) {
  const double p0 = parameter_value({m, 1.0, Closure::Stuck, s}, parameter);
  if (!(opt.p_lo < opt.p_hi)) {
    opt.p_lo = p0 > 0 ? 0.5 * p0 : -1.0;
    opt.p_hi = p0 > 0 ? 2.0 * p0 : 1.0;
  }
  if (!(opt.omega_hi > opt.omega_lo)) opt.omega_hi = 20 * kPi;
  if (opt.start_omega.empty()) opt.start_omega = {3 * kPi, 5 * kPi, 8 * kPi, 12 * kPi};
  return opt;
}

// One direction from the start: points after the start, and the codimension-2 points.
struct Half {
  std::vector<CurvePoint> points;
  std::vector<Codim2Point> meets;
  std::string stop;
};
Half walk(Extended e, const Vec11& Z0, int dir, const CurveOptions& opt, double s_lo, double s_hi) {
  Half out;
  e.accept(Z0);
  Probe cur = make_probe(e, Z0, Vec11::Zero(), dir);
  double h = opt.step;
  int n = 0;
  while (n < opt.max_points) {
    const Corrected nx = correct(e, cur.Z + h * cur.t, cur.t);
    Probe next;
    bool ok = nx.ok;
    if (ok) {
      next = make_probe(e, nx.Z, cur.t, 0);
      ok = next.t.dot(cur.t) > 0.9;  // a sharp turn: a smaller step, not a jump to another curve
    }
    if (!ok) {
      h *= 0.5;
      if (h < opt.step_min) {
        out.stop = "the corrector failed at the smallest step";
        return out;
      }
      continue;
    }
    add_meets(e, cur, next, n, out.meets);
    out.points.push_back(next.point);
    ++n;
    e.accept(next.Z);
    cur = next;
    if (nx.iterations <= 3) h = std::min(1.5 * h, opt.step_max);
    out.stop = stop_reason(e, cur, opt, s_lo, s_hi);
    if (!out.stop.empty()) return out;
  }
  out.stop = "max_points reached";
  return out;
}

std::pair<double, double> stops(const physics::Model& m) {
  const double l = m.p.string_length;
  return {m.layers.top_stop ? m.p.top_stop : 0.0, m.layers.bottom_stop ? l - m.p.contact_distance : l};
}

// The points of the stuck branch at s through X0 at ω0, continued both ways in ω, in order.
std::vector<BranchPoint> omega_path(const physics::Model& m, double s, double w0, const Vec9& X0,
                                    const CurveOptions& opt, std::vector<BranchEvent>& events) {
  ContinuationOptions copt;
  copt.lambda_min = opt.omega_lo;
  copt.lambda_max = opt.omega_hi;
  copt.stability = false;
  std::vector<BranchPoint> path;
  for (int dir : {-1, +1}) {
    copt.direction = dir;
    const Branch b = continue_branch({m, w0, Closure::Stuck, s}, X0, "omega", copt);
    events.insert(events.end(), b.events.begin(), b.events.end());
    if (dir < 0) path.assign(b.points.rbegin(), b.points.rend());
    else path.insert(path.end(), b.points.begin() + (path.empty() || b.points.empty() ? 0 : 1), b.points.end());
  }
  return path;
}

bool matches(CurveKind k, EventKind e) {
  return (k == CurveKind::Fold && e == EventKind::Fold) || (k == CurveKind::ConeUp && e == EventKind::ConeExitUp) ||
         (k == CurveKind::ConeDown && e == EventKind::ConeExitDown);
}

}  // namespace

namespace {
// The one-parameter events of every stuck branch at s, continued in ω both ways from the orbits
// at each start frequency (a branch already traced is not traced again).
std::vector<BranchEvent> stuck_events(const physics::Model& m, double s, const CurveOptions& opt) {
  std::vector<BranchEvent> events;
  std::vector<std::vector<BranchPoint>> traced;
  for (double w0 : opt.start_omega)
    for (const SteadyOrbit& o : orbits_at({m, w0, Closure::Stuck, s})) {
      if (std::any_of(traced.begin(), traced.end(),
                      [&](const std::vector<BranchPoint>& b) { return on_branch(b, o, m.p.string_length); }))
        continue;
      traced.push_back(omega_path(m, s, w0, unknowns(o), opt, events));
    }
  return events;
}

// The starts of `kind` among the events (hopf: from the lag's branches).
std::vector<CurveStart> starts_of(const physics::Model& m, CurveKind kind, double s, const CurveOptions& opt,
                                  const std::vector<BranchEvent>& events) {
  std::vector<CurveStart> raw;
  if (kind == CurveKind::Hopf) {
    if (!m.layers.tie_clutch) throw std::invalid_argument("the hopf curve needs [layers] tie = \"clutch\"");
    // The held stuck orbits at the middle of the lag's range, each branch continued in ω_b.
    const double lo = opt.lag_lo, hi = opt.lag_hi;
    std::vector<LagBranch> done;
    for (const SteadyOrbit& o : orbits_at({m, 0.5 * (lo + hi), Closure::Stuck, s})) {
      if (!o.admissible) continue;
      if (std::any_of(done.begin(), done.end(),
                      [&](const LagBranch& b) { return on_branch(b.points, o, m.p.string_length); }))
        continue;
      const LagBranch& br = done.emplace_back(lag_branch(m, o, lo, hi));
      // A Hopf point whose τ no motor speed passes (ω_m NaN: τ < τ_k) is no lag the clutch drives.
      for (const LagEvent& e : br.events)
        if (e.complex_pair && (e.kind == LagEventKind::StabilityLoss || e.kind == LagEventKind::StabilityGain) &&
            std::isfinite(e.at.omega_m))
          raw.push_back({kind, s, e.at.orbit.omega, unknowns(e.at.orbit)});
    }
  } else {
    for (const BranchEvent& e : events)
      if (matches(kind, e.kind)) raw.push_back({kind, s, e.lambda, unknowns(e.orbit)});
  }
  // The same event found from two starts of one branch: kept once.
  std::vector<CurveStart> out;
  for (const CurveStart& c : raw) {
    const bool seen = std::any_of(out.begin(), out.end(), [&](const CurveStart& q) {
      return std::abs(q.omega - c.omega) <= 1e-6 * c.omega &&
             (q.X.head<6>() - c.X.head<6>()).norm() <= 1e-5 * m.p.string_length;
    });
    if (!seen) out.push_back(c);
  }
  std::sort(out.begin(), out.end(), [](const CurveStart& a, const CurveStart& b) { return a.omega < b.omega; });
  return out;
}
}  // namespace

std::vector<CurveStart> curve_starts(const physics::Model& m, CurveKind kind, double s, const CurveOptions& opt0) {
  const CurveOptions opt = resolved(m, "s", s, opt0);
  return starts_of(m, kind, s, opt, kind == CurveKind::Hopf ? std::vector<BranchEvent>{} : stuck_events(m, s, opt));
}

Curve follow_curve(const physics::Model& m, const std::string& parameter, const CurveStart& start,
                   const CurveOptions& opt0) {
  const auto& allowed = second_parameters();
  if (std::find(allowed.begin(), allowed.end(), parameter) == allowed.end()) {
    std::string list;
    for (const auto& n : allowed) list += (list.empty() ? "" : ", ") + n;
    throw std::invalid_argument("'" + parameter + "' is not a second parameter; allowed: " + list);
  }
  const CurveOptions opt = resolved(m, parameter, start.s, opt0);
  Curve cv;
  cv.kind = start.kind;
  cv.parameter = parameter;
  cv.s = start.s;
  Extended e(m, parameter, start.kind, start.s, start.omega);
  const double p0 = parameter_value({m, start.omega, Closure::Stuck, start.s}, parameter);
  Vec11 Z0 = e.scaled(start.X, start.omega, p0);
  if (start.kind == CurveKind::Hopf) e.start_hopf(Z0);
  e.accept(Z0);
  // Polished at p0: the plane p = p0.
  Vec11 ep = Vec11::Zero();
  ep(10) = 1.0;
  const Corrected c0 = correct(e, Z0, ep);
  if (!c0.ok) {
    cv.stop_reason = "the start did not converge on the extended system";
    return cv;
  }
  const auto [s_lo, s_hi] = stops(m);
  const Half back = walk(e, c0.Z, -1, opt, s_lo, s_hi), fwd = walk(e, c0.Z, +1, opt, s_lo, s_hi);
  const int nb = int(back.points.size());
  for (int i = nb - 1; i >= 0; --i) cv.points.push_back(back.points[i]);
  Extended e0 = e;
  e0.accept(c0.Z);
  cv.points.push_back(make_probe(e0, c0.Z, Vec11::Zero(), 1).point);
  cv.points.insert(cv.points.end(), fwd.points.begin(), fwd.points.end());
  // The backward half's point k (after its start) sits at nb − 1 − k; a meet after its point k
  // lies between the joined points nb − 1 − k and nb − k.
  for (Codim2Point c : back.meets) {
    c.after_point = nb - 1 - c.after_point;
    cv.meets.push_back(c);
  }
  for (Codim2Point c : fwd.meets) {
    c.after_point += nb;
    cv.meets.push_back(c);
  }
  std::sort(cv.meets.begin(), cv.meets.end(),
            [](const Codim2Point& a, const Codim2Point& b) { return a.after_point < b.after_point; });
  cv.stop_reason = "low end: " + back.stop + "; high end: " + fwd.stop;
  return cv;
}

std::vector<Curve> threshold_curves(const physics::Model& m, const std::string& parameter,
                                    const std::vector<CurveKind>& kinds, double s, const CurveOptions& opt0) {
  const CurveOptions opt = resolved(m, "s", s, opt0);
  const bool stuck = std::any_of(kinds.begin(), kinds.end(), [](CurveKind k) { return k != CurveKind::Hopf; });
  const std::vector<BranchEvent> events = stuck ? stuck_events(m, s, opt) : std::vector<BranchEvent>{};
  std::vector<Curve> out;
  for (CurveKind kind : kinds) {
    const std::size_t first = out.size();
    for (const CurveStart& st : starts_of(m, kind, s, opt, events)) {
      // A start on a curve already followed (the curve passes p0 more than once) adds nothing.
      const double p0 = parameter_value({m, st.omega, Closure::Stuck, s}, parameter);
      const bool on = std::any_of(out.begin() + first, out.end(), [&](const Curve& c) {
        for (std::size_t i = 0; i + 1 < c.points.size(); ++i) {
          const CurvePoint &a = c.points[i], &b = c.points[i + 1];
          if ((a.p - p0) * (b.p - p0) > 0 || a.p == b.p) continue;
          const double t = (p0 - a.p) / (b.p - a.p);
          if (std::abs(a.omega + t * (b.omega - a.omega) - st.omega) < 1e-4 * st.omega) return true;
        }
        return false;
      });
      if (!on) out.push_back(follow_curve(m, parameter, st, opt0));
    }
  }
  return out;
}

std::vector<Curve> threshold_curves(const physics::Model& m, const std::string& parameter, CurveKind kind, double s,
                                    const CurveOptions& opt) {
  return threshold_curves(m, parameter, std::vector<CurveKind>{kind}, s, opt);
}

}  // namespace ajx::orbits
