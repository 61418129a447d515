#include "results/replay_file.hpp"

#include <cmath>
#include <string_view>

#include "physics/state.hpp"
#include "results/provenance.hpp"
#include "sweep/orbit_classifier.hpp"

namespace ajx::results {

void ReplayColumns::add(const sim::Sample& s, const physics::Model& m, const physics::MotorSchedule& schedule) {
  double phi = 0.0, omega = 0.0, omega_dot = 0.0;
  schedule.phase(s.t, phi, omega, omega_dot);
  motor_phi.push_back(phi);
  const bool slip = m.layers.tie_clutch && s.contact.tie.slip;
  tie_slip.push_back(slip ? 1 : 0);
  // While slipping the top turns at χ̇ = top.omega; the clutch passes σ τ_k + c_a (ω_m − χ̇).
  const double rate = s.top.motor_omega - s.top.omega;
  clutch_power.push_back(slip ? (s.contact.tie.sigma * m.p.tie_kinetic_torque + m.p.tie_damping * rate) * rate : 0.0);
}

namespace {

std::string_view class_name(std::int32_t cls) {
  return cls < 0 ? std::string_view("not computed") : sweep::to_string(static_cast<sweep::OrbitClass>(cls));
}

// One window's class and statistics as attributes of g, each statistic under its kStats name.
void put_row(io::Group g, const WindowRow& row) {
  g.set_attribute("class", std::int64_t(row.cls));
  g.set_attribute("class_name", class_name(row.cls));
  for (std::size_t k = 0; k < kNumStats; ++k) g.set_attribute(kStats[k][0], row.stats[k]);
}

}  // namespace

void write_replay(io::File& f, const std::string& command_line, const config::CommonConfig& cfg,
                  const Trajectory& traj, const ReplayColumns& extra, const ReplayInfo& info,
                  const sim::RunSummary& sum) {
  write_format(f, "run");
  write_provenance(f, command_line, cfg);
  io::Group tg = f.create_group("trajectory");
  traj.write(tg);
  const io::Dims n{extra.motor_phi.size()};
  auto phi = tg.write_dataset("motor_phi", std::span<const double>(extra.motor_phi), n);
  phi.set_attribute("units", "rad");
  phi.set_attribute("description", "phase φ of the motor's rod (the string's top is at /trajectory/phi, the tie's "
                                   "azimuth χ, equal to φ unless the clutch slips)");
  auto slip = tg.write_dataset("tie_slip", std::span<const std::int32_t>(extra.tie_slip), n);
  slip.set_attribute("units", "1");
  slip.set_attribute("description", "1 while the tie slips round the rod (tie-clutch layer), else 0");
  auto clutch = tg.write_dataset("clutch_power", std::span<const double>(extra.clutch_power), n);
  clutch.set_attribute("units", "W");
  clutch.set_attribute("description", "power the clutch dissipates, (σ τ_k + c_a (ω_m − χ̇)) (ω_m − χ̇) while the tie "
                                      "slips, 0 while held; not part of motor_work, which counts what reaches the string");

  io::Group sg = f.create_group("summary");
  sg.set_attribute("status", sum.ok() ? std::string("ok") : sum.failure);
  sg.set_attribute("t_end", sum.t_end);
  sg.set_attribute("omega_ball", info.replayed.stats[1]);
  sg.set_attribute("omega_window", info.t_end - info.t_begin);
  sg.set_attribute("steps", sum.steps);
  sg.set_attribute("rhs_evaluations", sum.rhs_evals);
  sg.set_attribute("impacts", sum.impacts);
  sg.set_attribute("sticks", sum.sticks);
  sg.set_attribute("slack_phases", sum.slack_phases);

  io::Group rg = f.create_group("replay");
  rg.set_attribute("description", "one window of a sweep file re-run from its task's stored start state with the "
                                  "file's own model, variant and integrator (astrojax replay)");
  rg.set_attribute("source", info.source);
  rg.set_attribute("source_git_commit", info.source_commit);
  rg.set_attribute("chain", info.chain);
  rg.set_attribute("window", info.window);
  rg.set_attribute("task", info.task);
  rg.set_attribute("group", info.group);
  rg.set_attribute("variant", info.variant);
  rg.set_attribute("variant_label", info.variant_label);
  rg.set_attribute("task_t_begin", info.task_begin);
  rg.set_attribute("t_begin", info.t_begin);
  rg.set_attribute("t_end", info.t_end);
  rg.set_attribute("omega_m_begin", info.omega_begin);
  rg.set_attribute("omega_m_end", info.omega_end);
  rg.set_attribute("direction", info.direction);
  rg.set_attribute("sweep_sample_rate", info.sweep_sample_rate);
  rg.set_attribute("sample_rate", info.sample_rate);
  rg.set_attribute("reason", info.reason);
  rg.set_attribute("reproduced", std::int64_t(info.reproduced ? 1 : 0));
  rg.set_attribute("omega_ball_difference", info.omega_ball_difference);
  put_row(rg.create_group("stored"), info.stored);
  put_row(rg.create_group("replayed"), info.replayed);
  f.commit();
}

}  // namespace ajx::results
