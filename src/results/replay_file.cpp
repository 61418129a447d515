#include "results/replay_file.hpp"

#include <string_view>

#include "io/hdf5_file.hpp"
#include "results/reclassify.hpp"

#include "results/provenance.hpp"
#include "sweep/orbit_classifier.hpp"

namespace ajx::results {

namespace {

std::string_view class_name(std::int32_t cls) {
  return cls < 0 ? std::string_view("not computed") : sweep::to_string(static_cast<sweep::OrbitClass>(cls));
}

// One window's class and statistics as attributes of g, each statistic under its kStats name.
void put_row(io::Group g, const WindowRow& row) {
  g.set_attribute("class", std::int64_t(row.cls));
  g.set_attribute("class_name", class_name(row.cls));
  for (std::size_t k = 0; k < kNumStats; ++k) g.set_attribute(kStats[k].name, row.stats[k]);
}

}  // namespace

void write_replay(const std::filesystem::path& path, const std::string& command_line, const config::CommonConfig& cfg,
                  const Trajectory& traj, const ReplayInfo& info, const sim::RunSummary& sum) {
  io::File f = create_output(path);
  write_format(f, "run");
  write_provenance(f, command_line, cfg);
  io::Group tg = f.create_group("trajectory");
  traj.write(tg);

  io::Group sg = f.create_group("summary");
  write_summary_common(sg, sum);
  sg.set_attribute("omega_ball", row_stat(info.replayed, "omega_ball"));
  sg.set_attribute("omega_window", info.t_end - info.t_begin);

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
