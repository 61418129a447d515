// The immutable model: parameters in SI units and the layers of physics chosen.
// Read once (config), shared read-only by every integrator (MuJoCo's mjModel).
#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace ajx::physics {

struct Parameters {
  double string_length = 0.826;      // l [m]
  double bead_mass = 0.018;          // m1 [kg], the middle ball
  double ball_mass = 0.018;          // m2 [kg], the bottom ball
  double drag = 1.7245e-3;           // c_D [kg/s], force -c_D v on each ball
  double mu_static = 0.25676;        // μ_s [1]
  double mu_kinetic = 0.17176;       // μ_k [1]
  double gravity = 9.81;             // g [m/s²]
  double drive_radius = 0.01;        // R [m], to calibrate (1-20 mm)
  double contact_distance = 0.03;    // d [m], L2 >= d (bead resting on the bottom ball)
  double top_stop = 0.05;            // s_min [m], L1 >= s_min (used by the top-stop layer)
  // The tie of the string to the motor's rod, used by the tie-clutch layer (physics/tie.hpp):
  double tie_static_torque = 1.0;    // τ_s [N m], the largest torque the tie holds without slipping
  double tie_kinetic_torque = 1.0;   // τ_k [N m], the torque it passes on while slipping, τ_k <= τ_s
  double tie_inertia = 5e-8;         // I_a [kg m²], of the tie about the motor axis (0.5 g at 1 cm)
  double tie_damping = 1e-7;         // c_a [N m s], viscous part of the clutch: c_a (ω_m - χ̇) while slipping
  // The pair couple, used by the diagnostic layer pair_couple = "motor_clutch" (physics/pair_couple.hpp):
  double couple_torque = 0.0;        // τ_c [N m], the couple's magnitude between motor and lower segment
  double couple_slip_rate = 1.0;     // Ω_ε [rad/s], slip rate of tanh((ω_m − β̇)/Ω_ε)
};

// Friction between bead and string:
//  None         frictionless, T1 = T2;
//  Kinetic      sliding friction μ_k only: a model without stick. Where ṡ = 0 finds the
//               forces inside the μ_k cone the bead is held there (the Filippov solution of
//               the Coulomb law), and the run reports it as a violated assumption;
//  StickSlip    sliding with μ_k, sticking while the μ_s cone holds (the full model);
//  Regularised  sgn ṡ replaced by tanh(ṡ/ε), no stuck mode: for comparison only (it creeps).
//               It saturates at μ_k, so it cannot hold a bead that needs μ_k < μ* < μ_s;
//  Stribeck     μ(ṡ) = [μ_k + (μ_s − μ_k) exp(−(ṡ/v_s)²)] tanh(ṡ/ε): the regularisation with a
//               peak near μ_s at slip ~ ε (physics/string_friction.hpp), no stuck mode: it holds
//               such a bead by creeping at ṡ ~ ε. For comparison only.
enum class Friction { None, Kinetic, StickSlip, Regularised, Stribeck };
// How T1/T2 depends on the deflection ψ of the string at the bead
// (docs/physics/model.md, "Friction").
enum class FrictionLaw { Capstan, PointContact };
// A couple about ẑ on the pair (physics/pair_couple.hpp): none, or kinetic friction between the
// motor's rotation and the lower segment's (a diagnostic, not a part of the Astrojax).
enum class PairCouple { None, MotorClutch };

struct Layers {
  Friction friction = Friction::StickSlip;
  FrictionLaw friction_law = FrictionLaw::Capstan;
  double regularisation = 1e-3;      // ε of tanh(ṡ/ε) for Friction::Regularised and ::Stribeck [m/s]
  double stribeck_speed = 1e-2;      // v_s, the slip speed over which the Stribeck peak decays [m/s]
  bool bottom_stop = true;           // one-sided contact L2 >= d
  bool top_stop = true;              // one-sided contact L1 >= s_min
  bool slack = true;                 // the string may go slack (else negative tensions are reported)
  double restitution = 0.0;          // e of the re-taut impact of a slack string, in [0, 1]
  bool tie_clutch = false;           // the tie slips on the rod past τ_s (else it is rigid: χ = φ)
  PairCouple pair_couple = PairCouple::None;  // the diagnostic couple on the pair (off by default)
};

struct Model {
  Parameters p;
  Layers layers;
};

// One violated bound: the key (as spelled in configuration files), the value and the
// allowed range in words. Configuration adds the file name.
struct ParameterIssue {
  std::string key;
  double value;
  std::string allowed;
};

// Every bound the physics needs (lengths and masses positive, R < l, d < l, μ >= 0, ...).
std::vector<ParameterIssue> validate(const Model& model);

std::string_view to_string(Friction f);
std::string_view to_string(FrictionLaw f);
std::string_view to_string(PairCouple c);

}  // namespace ajx::physics
