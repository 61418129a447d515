// Two-parameter continuation: the points that predict a threshold at one parameter set,
// followed in the plane of ω_m and a second parameter p (any continuation parameter, or the
// bead's stuck position s). Each point is a regular root of an extended system in
// Y = (X, ω), X = (p1, p2, F1, F2, s) the unknowns of steady_orbit.hpp with the bead stuck at s,
//   G(X; ω, p) = 0          the nine equations of the locked orbit,
//   g(X, ω, p)  = 0          one defining condition:
//     fold       g = the bordered test function of G_X (MatCont's minimally augmented system):
//                [G_X b; cᵀ 0] [v; g] = [0; 1], b and c the left and right singular vectors of
//                G_X's smallest singular value at the last point; g = 0 ⟺ G_X singular;
//     cone_up    g = margin_up / W' (the bead starts to slide up: the locked orbit's ω1 at s);
//     cone_down  g = margin_down / W' (it starts to slide down: ω_fall at s);
//     hopf       g = Re λ_c / r (the lag of the slipping tie, lagging_orbit.hpp, at ω = ω_b:
//                λ_c its eigenvalue pair followed from point to point; its ω_m is
//                ω_b + (τ − τ_k)/c_a, the lag's ω2 at s).
// Ten equations in eleven unknowns (Y, p): a curve, followed by pseudo-arclength (predict along
// the kernel of the 10×11 Jacobian, correct by Newton on the plane normal to it), in scaled
// unknowns (lengths / l, forces / W' = (m1 + m2) g (1 + ω² l/g), ω / √(g/l), p / |p0|).
// Codimension-2 points, located by bisection on the sign of a test function along the curve:
// where the curve meets another (fold: a cone margin = 0; cone_up/cone_down: det G_X = 0 or the
// other margin = 0; hopf: a cone margin = 0), and where the locked orbit on a fold or cone
// curve changes stability (the curve meets the orbit's own Hopf or loss of stability).
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "orbits/steady_orbit.hpp"

namespace ajx::orbits {

enum class CurveKind { Fold, ConeUp, ConeDown, Hopf };
std::string_view to_string(CurveKind k);
// "fold", "cone_up", "cone_down", "hopf"; throws std::invalid_argument listing them.
CurveKind curve_kind(std::string_view name);
const std::vector<std::string>& curve_kind_names();

// The second parameters: the continuation parameters but ω, with s (continuation.hpp).
const std::vector<std::string>& second_parameters();

// A start: a root of the extended system at the model's own parameter values.
struct CurveStart {
  CurveKind kind;
  double s = 0.0;        // the bead's stuck position [m]
  double omega = 0.0;    // ω of the orbit's frame [rad/s] (ω_b for hopf)
  Vec9 X;
};

struct CurvePoint {
  double p = 0.0;          // the second parameter's value
  double omega = 0.0;      // ω of the orbit's frame [rad/s] (ω_b for hopf)
  double omega_m = 0.0;    // the threshold: ω_m the motor turns at [rad/s] (= omega but for hopf)
  SteadyOrbit orbit;
  int unstable = 0;        // the locked orbit's eigenvalues with Re λ > noise (fold, cone curves)
  double frequency = 0.0;  // hopf: Im λ_c [rad/s]
  double torque = 0.0;     // hopf: τ the tie passes [N m]
  double sigma_min = 0.0;  // smallest singular value of the scaled 10×11 Jacobian (its conditioning)
};

struct Codim2Point {
  std::string kind;        // "fold+cone_up", "cone_down+fold", "hopf+cone_up", "stability", ...
  CurvePoint at;
  int after_point = 0;     // between points after_point and after_point + 1 of the curve
};

struct Curve {
  CurveKind kind;
  std::string parameter;
  double s = 0.0;
  std::vector<CurvePoint> points;   // in order along the curve
  std::vector<Codim2Point> meets;
  std::string stop_reason;          // of the two ends, "lo end: ...; hi end: ..."
};

struct CurveOptions {
  double p_lo = 0.0, p_hi = 0.0;           // the second parameter's interval (0, 0: 0.5 p0 .. 2 p0)
  double omega_lo = 0.5, omega_hi = 0.0;   // the curve stops outside [omega_lo, omega_hi] (0: 20π) [rad/s]
  std::vector<double> start_omega;         // where the one-parameter branches are picked up (default 3π, 5π, 8π, 12π)
  double lag_lo = 2 * 3.141592653589793, lag_hi = 7 * 3.141592653589793;  // hopf: ω_b range of the lag's branches [rad/s]
  double step = 0.01, step_min = 1e-6, step_max = 0.05;  // arclength steps (scaled units)
  int max_points = 2000;                   // per direction
};

// The starts of `kind` at the bead position s: the events of that kind on the one-parameter
// continuations in ω (continuation.hpp) of every stuck branch at s (hopf: the complex
// crossings of lag_branch, lagging_orbit.hpp, over ω_b in [lag_lo, lag_hi], where a motor speed
// gives the lag's τ), each polished on the extended system.
std::vector<CurveStart> curve_starts(const physics::Model& m, CurveKind kind, double s, const CurveOptions& opt);

// The curve through `start` followed both ways in `parameter`, with its codimension-2 points.
Curve follow_curve(const physics::Model& m, const std::string& parameter, const CurveStart& start,
                   const CurveOptions& opt);

// Every curve of `kind` at s in `parameter`: one per start not already on a curve followed.
std::vector<Curve> threshold_curves(const physics::Model& m, const std::string& parameter, CurveKind kind, double s,
                                    const CurveOptions& opt);
// The same for several kinds, the branches in ω that give the starts traced once for all.
std::vector<Curve> threshold_curves(const physics::Model& m, const std::string& parameter,
                                    const std::vector<CurveKind>& kinds, double s, const CurveOptions& opt);

}  // namespace ajx::orbits
