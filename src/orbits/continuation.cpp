#include "orbits/continuation.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "physics/parameter_table.hpp"

namespace ajx::orbits {

// ω and the closure's s*, then the model parameters the table marks (physics/parameter_table.hpp).
const std::vector<std::string>& continuation_parameters() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n{"omega", "s"};
    for (std::string& k : physics::continuation_parameter_keys()) n.push_back(std::move(k));
    return n;
  }();
  return names;
}

namespace {
void check_known(std::string_view name) {
  const auto& names = continuation_parameters();
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    std::string allowed;
    for (const auto& n : names) allowed += (allowed.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown continuation parameter '" + std::string(name) + "'; allowed: " + allowed);
  }
}
}  // namespace

double parameter_value(const OrbitProblem& pb, std::string_view name) {
  check_known(name);
  if (name == "omega") return pb.omega;
  if (name == "s") return pb.s_star;
  return physics::parameter(pb.model.p, name);
}

void set_parameter(OrbitProblem& pb, std::string_view name, double value) {
  check_known(name);
  if (name == "omega") pb.omega = value;
  else if (name == "s") pb.s_star = value;
  else physics::set_parameter(pb.model.p, name, value);
}

std::string_view to_string(EventKind k) {
  switch (k) {
    case EventKind::Fold: return "fold";
    case EventKind::BranchPoint: return "branch_point";
    case EventKind::StabilityLoss: return "stability_loss";
    case EventKind::StabilityGain: return "stability_gain";
    case EventKind::Hopf: return "hopf";
    case EventKind::ConeExitUp: return "cone_exit_up";
    case EventKind::ConeExitDown: return "cone_exit_down";
    case EventKind::Slack: return "slack";
  }
  return "?";
}

namespace {

using Vec10 = Eigen::Matrix<double, 10, 1>;
using Mat10 = Eigen::Matrix<double, 10, 10>;
using Mat9x10 = Eigen::Matrix<double, 9, 10>;
constexpr double kEps = std::numeric_limits<double>::epsilon();

// The branch in scaled unknowns Z = (X / dX, λ / λ_s).
struct Curve {
  OrbitProblem base;
  std::string name;
  Vec9 dX;
  double ls;

  OrbitProblem at(const Vec10& Z) const {
    OrbitProblem q = base;
    set_parameter(q, name, Z(9) * ls);
    return q;
  }
  Vec9 X(const Vec10& Z) const { return Z.head<9>().cwiseProduct(dX); }
  Vec9 G(const Vec10& Z) const { return residual(at(Z), X(Z)); }
  Mat9x10 GZ(const Vec10& Z) const {
    Mat9x10 A;
    A.leftCols<9>() = jacobian(at(Z), X(Z)) * dX.asDiagonal();
    const double h = std::cbrt(kEps) * std::max(1.0, std::abs(Z(9)));
    Vec10 zp = Z, zm = Z;
    zp(9) += h;
    zm(9) -= h;
    A.col(9) = (G(zp) - G(zm)) / (2 * h);
    return A;
  }
  double tol(const Vec10& Z) const { return default_tolerance(at(Z)); }
};

// Unit vector spanning ker A, oriented along `orient` (or with sign(t_λ) = dir when orient = 0).
Vec10 tangent(const Mat9x10& A, const Vec10& orient, int dir) {
  Eigen::JacobiSVD<Mat9x10> svd(A, Eigen::ComputeFullV);
  Vec10 t = svd.matrixV().col(9).normalized();
  const double sgn = orient.squaredNorm() > 0 ? t.dot(orient) : t(9) * dir;
  return sgn < 0 ? Vec10(-t) : t;
}

// Newton on [G(Z); n·(Z − Zp)] = 0.
struct Corrected {
  Vec10 Z;
  int iterations = 0;
  bool ok = false;
};
Corrected correct(const Curve& c, const Vec10& Zp, const Vec10& n) {
  Corrected out{Zp, 0, false};
  for (int it = 0; it < 12; ++it) {
    const Vec9 g = c.G(out.Z);
    if (!g.allFinite()) return out;
    const double plane = n.dot(out.Z - Zp);
    if (g.lpNorm<Eigen::Infinity>() <= 4 * c.tol(out.Z) && std::abs(plane) < 1e-13) {
      out.ok = true;
      out.iterations = it;
      return out;
    }
    Mat10 A;
    A.topRows<9>() = c.GZ(out.Z);
    A.row(9) = n.transpose();
    Vec10 rhs;
    rhs << -g, -plane;
    const Vec10 dZ = A.partialPivLu().solve(rhs);
    if (!dZ.allFinite() || dZ.norm() > 0.2) return out;
    out.Z += dZ;
  }
  return out;
}

struct Tests {
  Vec10 Z, t;
  double det_aug = 0;
  BranchPoint point;
};

// One continuation: the curve in scaled unknowns, and the test functions at its points.
class Continuer {
 public:
  Continuer(const OrbitProblem& pb, const std::string& parameter, const ContinuationOptions& opt)
      : pb_(pb), opt_(opt), c_{pb, parameter, {}, 1.0} {
    const Scales sc = scales(pb.model);
    // Forces in units of the largest of weight and centripetal pull at the start, W (1 + ω² l/g):
    // on a whirling branch the tensions grow as ω², and steps measured in W alone would crawl.
    const double fs = sc.force * (1.0 + pb.omega * pb.omega * sc.length / pb.model.p.gravity);
    c_.dX << Vec3::Constant(sc.length), Vec3::Constant(sc.length), fs, fs, sc.length;
    const double lambda0 = parameter_value(pb, parameter);
    // ω_m in units of the pendulum frequency √(g/l); s in l; others in their own size.
    c_.ls = parameter == "omega" ? std::sqrt(pb.model.p.gravity / pb.model.p.string_length)
            : parameter == "s"   ? pb.model.p.string_length
                                 : (lambda0 != 0 ? std::abs(lambda0) : 1.0);
    rate_scale_ = pb.omega + std::sqrt(pb.model.p.gravity / pb.model.p.string_length);
    noise_ = growth_noise(pb.model, pb.omega);
  }

  Vec10 scaled(const Vec9& X, double lambda) const {
    Vec10 Z;
    Z << X.cwiseQuotient(c_.dX), lambda / c_.ls;
    return Z;
  }

  // The point Z with its tangent (oriented along `orient`, or by `dir` at the start), the
  // augmented determinant, the orbit and, if asked, its stability.
  Tests make(const Vec10& Z, const Vec10& orient, int dir) const {
    Tests T;
    T.Z = Z;
    const Mat9x10 A = c_.GZ(Z);
    T.t = tangent(A, orient, dir);
    Mat10 aug;
    aug.topRows<9>() = A;
    aug.row(9) = T.t.transpose();
    T.det_aug = aug.determinant();
    const OrbitProblem q = c_.at(Z);
    T.point.lambda = Z(9) * c_.ls;
    T.point.orbit = describe(q, c_.X(Z));
    T.point.tangent_lambda = T.t(9);
    if (opt_.stability) {
      T.point.stab = stability(q, c_.X(Z));
      // Eigenvalues within the finite-difference noise of zero do not count.
      for (int i = 0; i < T.point.stab.eigenvalues.size(); ++i)
        T.point.unstable += T.point.stab.eigenvalues(i).real() > noise_;
    }
    return T;
  }

  // The signed test functions whose sign changes are events: fold, branch point, the cone's
  // upper and lower margins, the smaller tension, the count of unstable eigenvalues.
  std::array<double, 6> values(const Tests& T) const {
    const bool skip_up = pb_.closure == Closure::ConeUp, skip_down = pb_.closure == Closure::ConeDown;
    const SteadyOrbit& o = T.point.orbit;
    return std::array<double, 6>{T.t(9), T.det_aug, skip_up ? 1.0 : o.margins.up,
                                 skip_down || std::isinf(o.margins.down) ? 1.0 : o.margins.down,
                                 std::min(o.T1, o.T2), double(T.point.unstable)};
  }

  Corrected correct(const Vec10& Zp, const Vec10& n) const { return orbits::correct(c_, Zp, n); }

  // Events between cur and next: bisection on the sign of each test function that changed.
  void add_events(const Tests& cur, const Tests& next, Branch& br) const {
    const auto v0 = values(cur), v1 = values(next);
    for (int k = 0; k < 6; ++k) {
      const bool changed = k == 5 ? v0[k] != v1[k] : (v0[k] < 0) != (v1[k] < 0);
      if (!changed || !std::isfinite(v0[k]) || !std::isfinite(v1[k])) continue;
      const Tests at = locate(cur, next, k, int(std::min(v0[5], v1[5])));
      BranchEvent e;
      e.lambda = at.point.lambda;
      e.orbit = at.point.orbit;
      e.after_point = int(br.points.size()) - 1;
      classify_event(e, k, at, v1[k] < v0[k], next.point.lambda > cur.point.lambda);
      br.events.push_back(e);
    }
  }

  // Why the branch ends at `cur`, or "" to go on.
  std::string stop_reason(const Tests& cur) const {
    const double lambda = cur.point.lambda;
    if (lambda < opt_.lambda_min || lambda > opt_.lambda_max) return "left the parameter range";
    const double s = cur.point.orbit.s, l = pb_.model.p.string_length;
    if (!(s > 0 && s < l)) return "the bead left the string";
    if (c_.name == "omega" && !(lambda > 0)) return "ω_m reached 0";
    return "";
  }

 private:
  // Test function k's zero between cur and next, bisected on the segment (corrected onto the
  // curve at each midpoint). A change in the count of unstable eigenvalues is located on the
  // real part of the crossing one: the (n_cross+1)-th largest, n_cross the smaller count (the
  // count itself has a noise threshold).
  Tests locate(const Tests& cur, const Tests& next, int k, int n_cross) const {
    const auto located = [&](const Tests& T) {
      return k == 5 ? T.point.stab.eigenvalues(n_cross).real() : values(T)[k];
    };
    const Vec10 d = (next.Z - cur.Z).normalized();
    const double f0 = located(cur);
    double a = 0, b = 1;
    Tests at = next;
    for (int it = 0; it < 40; ++it) {
      const double m = 0.5 * (a + b);
      const Corrected cm = correct(cur.Z + m * (next.Z - cur.Z), d);
      if (!cm.ok) break;
      Tests tm = make(cm.Z, cur.t, 0);
      const bool same = (located(tm) < 0) == (f0 < 0);
      (same ? a : b) = m;
      if (!same) at = tm;
    }
    return at;
  }

  void classify_event(BranchEvent& e, int k, const Tests& at, bool gain, bool increasing) const {
    switch (k) {
      case 0: e.kind = EventKind::Fold; break;
      case 1: e.kind = EventKind::BranchPoint; break;
      case 2: e.kind = EventKind::ConeExitUp; break;
      case 3: e.kind = EventKind::ConeExitDown; break;
      case 4: e.kind = EventKind::Slack; break;
      case 5: {
        // The crossing eigenvalue: the one nearest the imaginary axis where it was located.
        const Eigen::VectorXcd& ev = at.point.stab.eigenvalues;
        int j = 0;
        for (int i = 1; i < ev.size(); ++i)
          if (std::abs(ev(i).real()) < std::abs(ev(j).real())) j = i;
        e.frequency = std::abs(ev(j).imag());
        e.kind = e.frequency > 1e-6 * rate_scale_ ? EventKind::Hopf
                 : gain                           ? EventKind::StabilityGain
                                                  : EventKind::StabilityLoss;
        e.note = (gain ? "stabilising" : "destabilising") + std::string(" with λ ") +
                 (increasing ? "increasing" : "decreasing");
        break;
      }
    }
  }

  const OrbitProblem& pb_;
  const ContinuationOptions& opt_;
  Curve c_;
  double rate_scale_ = 0, noise_ = 0;
};

}  // namespace

Branch continue_branch(OrbitProblem pb, const Vec9& X0, const std::string& parameter, const ContinuationOptions& opt) {
  const Continuer run(pb, parameter, opt);
  Branch br;
  br.parameter = parameter;
  br.closure = pb.closure;
  const NewtonResult start = solve(pb, X0);
  if (!start.converged) {
    br.stop_reason = "no orbit at the start (Newton did not converge)";
    return br;
  }
  Tests cur = run.make(run.scaled(start.X, parameter_value(pb, parameter)), Vec10::Zero(), opt.direction >= 0 ? 1 : -1);
  br.points.push_back(cur.point);
  // Pseudo-arclength: predict along the tangent, correct on the plane normal to it.
  double h = opt.step;
  while (int(br.points.size()) < opt.max_points) {
    const Corrected nx = run.correct(cur.Z + h * cur.t, cur.t);
    Tests next;
    bool ok = nx.ok;
    if (ok) {
      next = run.make(nx.Z, cur.t, 0);
      ok = next.t.dot(cur.t) > 0.9;  // a sharp turn: a smaller step, not a jump to another branch
    }
    if (!ok) {
      h *= 0.5;
      if (h < opt.step_min) {
        br.stop_reason = "the corrector failed at the smallest step";
        break;
      }
      continue;
    }
    run.add_events(cur, next, br);
    br.points.push_back(next.point);
    cur = next;
    if (nx.iterations <= 3) h = std::min(1.5 * h, opt.step_max);
    br.stop_reason = run.stop_reason(cur);
    if (br.stop_reason.empty() && opt.stop_at && opt.stop_at(cur.point)) br.stop_reason = "the caller's stop";
    if (!br.stop_reason.empty()) break;
  }
  if (br.stop_reason.empty()) br.stop_reason = "max_points reached";
  std::sort(br.events.begin(), br.events.end(),
            [](const BranchEvent& a, const BranchEvent& b) { return a.after_point < b.after_point; });
  return br;
}

}  // namespace ajx::orbits
