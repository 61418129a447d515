#include "results/run_file.hpp"

#include <fmt/format.h>

#include "physics/energy.hpp"
#include "physics/tie.hpp"
#include "results/provenance.hpp"

namespace ajx::results {

void Trajectory::add(const sim::Sample& s, const physics::Parameters& p, const physics::MotorSchedule& schedule) {
  t.push_back(s.t);
  for (int i = 0; i < 3; ++i) {
    r1.push_back(s.y(physics::idx::r1 + i));
    r2.push_back(s.y(physics::idx::r2 + i));
    v1.push_back(s.y(physics::idx::v1 + i));
    v2.push_back(s.y(physics::idx::v2 + i));
  }
  mode.push_back(static_cast<std::int32_t>(s.contact.mode));
  T1.push_back(s.dyn.T1);
  T2.push_back(s.dyn.T2);
  contact.push_back(s.dyn.contact);
  L1.push_back(s.dyn.g.L1);
  psi.push_back(s.dyn.g.psi);
  omega_m.push_back(s.top.motor_omega);
  double motor_phi, omega, omega_dot;
  schedule.phase(s.t, motor_phi, omega, omega_dot);
  phi.push_back(motor_phi);
  chi.push_back(s.top.phi);
  energy.push_back(physics::mechanical_energy(p, s.y));
  tie_energy.push_back(physics::tie_energy(p, s.y));
  const bool ledger = physics::has_ledger(s.y);
  motor_work.push_back(s.y(ledger ? physics::idx::rod_work : physics::idx::motor_work));
  string_work.push_back(s.y(physics::idx::motor_work));
  clutch_loss.push_back(ledger ? s.y(physics::idx::clutch_loss) : 0.0);
  drag_loss.push_back(s.y(physics::idx::drag_loss));
  friction_loss.push_back(s.y(physics::idx::friction_loss));
  impact_loss.push_back(s.impact_loss);
}

void Trajectory::write(io::Group& g) const {
  const std::size_t n = t.size();
  // One dataset per quantity, n rows of `width` columns, with units and a description.
  auto put = [&](const char* name, const std::vector<double>& v, std::size_t width, const char* unit,
                 const char* what) {
    auto d = g.write_dataset(name, std::span<const double>(v), width == 1 ? io::Dims{n} : io::Dims{n, width});
    d.set_attribute("units", unit);
    d.set_attribute("description", what);
  };
  auto col = [&](const char* name, const std::vector<double>& v, const char* unit, const char* what) {
    put(name, v, 1, unit, what);
  };
  auto vec = [&](const char* name, const std::vector<double>& v, const char* unit, const char* what) {
    put(name, v, 3, unit, what);
  };
  col("t", t, "s", "time");
  vec("r1", r1, "m", "bead (middle ball) position, z up, motor axis at x = y = 0");
  vec("r2", r2, "m", "bottom ball position");
  vec("v1", v1, "m/s", "bead velocity");
  vec("v2", v2, "m/s", "bottom ball velocity");
  auto m = g.write_dataset("mode", std::span<const std::int32_t>(mode), io::Dims{n});
  m.set_attribute("units", "1");
  m.set_attribute("description", "contact mode: 0 sliding (taut), 1 bead on the bottom ball, 2 bead stuck on the string, 3 bead at the top stop, 4 slack string");
  col("T1", T1, "N", "tension above the bead");
  col("T2", T2, "N", "tension below the bead (at the stop: the one closest to the link force)");
  col("contact", contact, "N", "push of the stop (bottom ball or top) on the bead (0 elsewhere)");
  col("L1", L1, "m", "string length above the bead, s = L1");
  col("psi", psi, "rad", "deflection of the string at the bead, arccos(u1.u2)");
  col("omega_m", omega_m, "rad/s", "motor angular velocity");
  col("phi", phi, "rad", "motor phase φ, the rod's azimuth (dφ/dt = omega_m)");
  col("chi", chi, "rad", "azimuth χ of the string's tie on the motor's circle: φ for a rigid tie, φ + its offset while "
                         "the tie clutch holds, the tie's own angle while it slips");
  col("energy", energy, "J", "kinetic + potential energy of both balls");
  col("tie_energy", tie_energy, "J", "kinetic energy of the tie, ½ I_a χ̇² (0 for a rigid tie)");
  col("motor_work", motor_work, "J", "cumulative work the motor does at its rod, ∫ τ_rod ω_m dt (for a rigid tie: "
                                     "= string_work); motor_work = tie_energy change + clutch_loss + string_work");
  col("string_work", string_work, "J", "cumulative work the top of the string passes into the string, "
                                       "∫ −F1 u1·ȧ dt and the top's impulses (with layers.pair_couple: plus the "
                                       "couple's work on the balls); string_work = energy change + the four losses");
  col("clutch_loss", clutch_loss, "J", "cumulative dissipation of the tie clutch, ∫ τ_c (ω_m − χ̇) dt (0 for a rigid tie)");
  col("drag_loss", drag_loss, "J", "cumulative drag dissipation");
  col("friction_loss", friction_loss, "J", "cumulative friction dissipation");
  col("impact_loss", impact_loss, "J", "cumulative dissipation in impacts");
}

void write_summary_common(io::Group& sg, const sim::RunSummary& sum) {
  sg.set_attribute("status", sum.ok() ? std::string("ok") : sum.failure);
  sg.set_attribute("t_end", sum.t_end);
  sg.set_attribute("motor_work", sum.energy.motor_work);
  sg.set_attribute("string_work", sum.energy.string_work);
  sg.set_attribute("clutch_loss", sum.energy.clutch_loss);
  sg.set_attribute("steps", sum.steps);
  sg.set_attribute("rhs_evaluations", sum.rhs_evals);
  sg.set_attribute("impacts", sum.impacts);
  sg.set_attribute("sticks", sum.sticks);
  sg.set_attribute("slack_phases", sum.slack_phases);
}

// The trajectory, the summary and the provenance into the run's file, then committed.
// `start_projection`: with the paper's scheme, |L1 + L2 - l| of its starting pair before projection.
void write_run(io::File& f, const std::string& command_line, const config::RunConfig& cfg,
               const physics::MotorSchedule& schedule, const Trajectory& traj, const sim::RunSummary& sum,
               const physics::State& state, double wall, std::optional<double> start_projection,
               const std::optional<sim::PairStart>& raw_pair) {
  write_format(f, "run");
  write_provenance(f, command_line, cfg);
  io::Group tg = f.create_group("trajectory");
  traj.write(tg);
  io::Group sg = f.create_group("summary");
  write_summary_common(sg, sum);
  sg.set_attribute("final_mode", std::string(physics::to_string(state.contact.mode)));
  sg.set_attribute("omega_ball", sum.omega_ball);
  sg.set_attribute("omega_window", cfg.run.omega_window);
  sg.set_attribute("energy_residual_relative", sum.energy.relative());
  sg.set_attribute("max_constraint_drift", sum.max_drift);
  sg.set_attribute("max_sample_drift", sum.max_sample_drift);
  sg.set_attribute("rejected_steps", sum.rejected);
  sg.set_attribute("mode_switches", sum.mode_switches);
  sg.set_attribute("first_stick", sum.first_stick);
  sg.set_attribute("tie_slips", sum.tie_slips);
  sg.set_attribute("first_tie_slip", sum.first_tie_slip);
  sg.set_attribute("chatter_episodes", sum.chatter);
  sg.set_attribute("first_chatter", sum.first_chatter);
  // Assumptions of omitted layers that the run found violated, one group each.
  io::Group vg = sg.create_group("violations");
  for (std::size_t i = 0; i < sum.violations.size(); ++i) {
    const sim::Violation& v = sum.violations[i];
    io::Group g = vg.create_group(fmt::format("{}", i));
    g.set_attribute("what", v.what);
    g.set_attribute("count", v.count);
    g.set_attribute("first_time", v.first_time);
    g.set_attribute("worst", v.worst);
    g.set_attribute("worst_units", v.unit);
  }
  if (start_projection) sg.set_attribute("start_projection", *start_projection);
  if (raw_pair) {
    // The raw pair: its speeds |q^(1) - q^(0)|/h and its L1 + L2 - l at t = 0.
    const sim::PairStart& raw = *raw_pair;
    const double h = cfg.run.integ.h_fixed;
    sg.set_attribute("start_pair_speed_bead", (raw.r1_1 - raw.r1_0).norm() / h);
    sg.set_attribute("start_pair_speed_ball", (raw.r2_1 - raw.r2_0).norm() / h);
    sg.set_attribute("start_pair_length_excess", (raw.r1_0 - schedule.top(0.0).a).norm() +
                                                     (raw.r2_0 - raw.r1_0).norm() - cfg.model.p.string_length);
  }
  sg.set_attribute("wall_time", wall);
  f.commit();
}

RunFile::RunFile(const std::filesystem::path& out) {
  try {
    f_ = create_output(out);
  } catch (const io::Hdf5Error& e) {
    throw OutputError(e.what());
  }
}

void RunFile::write(const std::string& command_line, const config::RunConfig& cfg,
                    const physics::MotorSchedule& schedule, const Trajectory& traj, const sim::RunSummary& sum,
                    const physics::State& state, double wall, std::optional<double> start_projection,
                    const std::optional<sim::PairStart>& raw_pair) {
  try {
    write_run(f_, command_line, cfg, schedule, traj, sum, state, wall, start_projection, raw_pair);
  } catch (const io::Hdf5Error& e) {
    f_ = io::File();  // the uncommitted .part is removed
    throw OutputError(e.what());
  }
}

}  // namespace ajx::results
