// The string and the friction law at the bead (docs/physics/model.md, "Friction").
// Sliding: T1 = κ T2 with κ from the law, the deflection ψ = arccos(u1·u2) and σ = sgn ṡ.
#pragma once
#include "physics/drive.hpp"
#include "physics/model.hpp"

namespace ajx::physics {

// ψ = arccos(u1·u2) for unit vectors, computed as atan2(|u1×u2|, u1·u2): accurate near 0.
double deflection(const Vec3& u1, const Vec3& u2);

// κ = T1/T2 while sliding with σ = sgn ṡ ∈ {-1, 0, +1} (or tanh(ṡ/ε) ∈ (-1, 1) for the
// regularised layer) and coefficient μ:
//   capstan:        κ = exp(μ ψ σ)
//   point contact:  (T1-T2) cos(ψ/2) = μ σ (T1+T2) sin(ψ/2)  ⇒  κ = (1 + μσ t)/(1 - μσ t), t = tan(ψ/2)
// The point-contact law jams (no positive κ in either direction) when μ tan(ψ/2) >= 1; then
// sliding is impossible and this throws std::domain_error.
double tension_ratio(FrictionLaw law, double mu, double psi, double sigma);

// The friction cone: the bead holds on the string while κ_lo <= T1/T2 <= κ_hi
// (capstan: e^{∓μψ}; point contact: (1 ∓ μ t)/(1 ± μ t)). A jammed point contact holds any
// ratio: κ_lo = 0, κ_hi = +inf.
struct FrictionCone {
  double lo;  // κ at the onset of sliding up (σ = -1)
  double hi;  // κ at the onset of sliding down (σ = +1)
};
FrictionCone friction_cone(FrictionLaw law, double mu, double psi);

// The regularised layers replace the sliding law's μ_k sgn ṡ by a smooth odd function of ṡ,
// μ(|ṡ|) tanh(ṡ/ε), with μ(v) = μ_k (regularised: saturates at μ_k) or the Stribeck curve
//   μ(v) = μ_k + (μ_s − μ_k) exp(−(v/v_s)²)
// (stribeck: a peak near μ_s at v ~ ε when ε ≪ v_s, falling to μ_k for v ≫ v_s).
bool regularised(const Model& m);
// μ(|ṡ|) of the regularised layer (μ_k for `regularised`, the curve above for `stribeck`).
double regularised_mu(const Model& m, double sdot);
// tanh(ṡ/ε), the smooth direction.
double regularised_sigma(const Model& m, double sdot);
// The signed coefficient μ(|ṡ|) tanh(ṡ/ε) that replaces μ_k sgn ṡ.
double regularised_coefficient(const Model& m, double sdot);

// The coefficient while sliding: 0 without friction, μ_k otherwise.
double sliding_mu(const Model& m);
// The coefficient of the cone that holds a stuck or resting bead: μ_s with stick-slip, μ_k in
// the kinetic layer (Coulomb with one coefficient), 0 without friction or when regularised.
double sticking_mu(const Model& m);
// Whether the layer has a stuck mode at all.
bool can_stick(const Model& m);

}  // namespace ajx::physics
