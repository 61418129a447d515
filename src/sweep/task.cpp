#include "sweep/task.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "physics/energy.hpp"
#include "physics/state_row.hpp"
#include "physics/tie.hpp"
#include "sweep/codec.hpp"

namespace ajx::sweep {

void add_settle_spans(const ChainSetup& chain, const TaskSpan& span, sim::RunOptions& run) {
  for (int i = 0; i < span.num_windows; ++i) {
    const Window& win = chain.protocol.windows[std::size_t(span.first_window + i)];
    if (chain.settle_tolerance > 0.0 && win.t_begin > win.t_settle) run.settle_spans.emplace_back(win.t_settle, win.t_begin);
  }
  run.settle_tolerance = chain.settle_tolerance;
}

TaskOutput run_task(const ChainSetup& chain, const TaskSpan& span, physics::State start) {
  const physics::MotorSchedule schedule = chain.motor();
  sim::RunOptions run = chain.run;
  run.run_statistics = false;  // the windows are measured from the samples
  for (int i = 0; i < span.num_windows; ++i) {  // and only the windows' samples are stored
    const Window& win = chain.protocol.windows[std::size_t(span.first_window + i)];
    run.sample_spans.emplace_back(win.t_begin, win.t_end);
  }
  add_settle_spans(chain, span, run);
  sim::Simulation simulation(chain.model, schedule, run);
  TaskOutput out;
  const auto& windows = chain.protocol.windows;
  for (int i = 0; i < span.num_windows; ++i) out.windows.push_back({span.first_window + i, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}});
  // The sample grid is anchored at the chain's t = 0, so a result depends on its task alone and
  // the samples do not depend on how the chain is split.
  std::size_t w = 0;
  const auto on_sample = [&](const sim::Sample& s) {
    while (w < out.windows.size() && s.t >= windows[std::size_t(out.windows[w].index)].t_end) ++w;
    if (w == out.windows.size() || s.t < windows[std::size_t(out.windows[w].index)].t_begin) return;
    WindowRecord& rec = out.windows[w];
    rec.t.push_back(s.t);
    rec.omega_m.push_back(s.top.motor_omega);
    for (int k = 0; k < 3; ++k) {
      rec.r1.push_back(s.y(physics::idx::r1 + k));
      rec.r2.push_back(s.y(physics::idx::r2 + k));
    }
    rec.L1.push_back(s.dyn.g.L1);
    rec.T1.push_back(s.dyn.T1);
    rec.T2.push_back(s.dyn.T2);
    rec.mode.push_back(static_cast<std::int32_t>(s.contact.mode));
    const bool ledger = physics::has_ledger(s.y);
    rec.last = {s.t, s.y(ledger ? physics::idx::rod_work : physics::idx::motor_work), s.y(physics::idx::drag_loss),
                s.y(physics::idx::friction_loss) + s.impact_loss, physics::mechanical_energy(chain.model.p, s.y),
                s.y(physics::idx::motor_work), ledger ? s.y(physics::idx::clutch_loss) : 0.0,
                physics::tie_energy(chain.model.p, s.y)};
    if (rec.size() == 1) rec.first = rec.last;
  };
  start.t = span.t_begin;
  const sim::RunSummary r = simulation.run(start, span.t_end, 1.0 / chain.sample_rate, on_sample, 0.0);
  out.ok = r.ok();
  out.failure = r.failure;
  out.final_state = start;
  add_counts(out, r);
  out.simulated = r.t_end - span.t_begin;
  return out;
}

void add_counts(TaskOutput& out, const sim::RunSummary& r) {
  out.steps += r.steps;
  out.rhs_evals += r.rhs_evals;
  out.impacts += r.impacts;
  out.sticks += r.sticks;
  out.slack_phases += r.slack_phases;
  out.skipped += r.skipped;
}

WindowPowers window_powers(const WindowRecord& rec) {
  const double dt = rec.last.t - rec.first.t;
  if (rec.size() < 2 || !(dt > 0.0)) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan, nan, nan};
  }
  return {(rec.last.motor_work - rec.first.motor_work) / dt, (rec.last.drag_loss - rec.first.drag_loss) / dt,
          (rec.last.other_loss - rec.first.other_loss) / dt, (rec.last.energy - rec.first.energy) / dt,
          (rec.last.string_work - rec.first.string_work) / dt, (rec.last.clutch_loss - rec.first.clutch_loss) / dt};
}

std::vector<OrbitClassification> classify_windows(const ChainSetup& chain, const TaskOutput& out,
                                                  const ClassifierSettings& settings) {
  const OrbitScales scales = orbit_scales(chain.model.p);
  std::vector<OrbitClassification> classes;
  for (const WindowRecord& rec : out.windows) {
    // Finished when its samples reach the window's end (to within the sampling grid).
    const double t_end = chain.protocol.windows[std::size_t(rec.index)].t_end;
    const bool complete = out.ok || (rec.size() > 0 && rec.t.back() >= t_end - 2.0 / chain.sample_rate);
    OrbitWindow w;
    w.t = rec.t;
    w.omega_m = rec.omega_m;
    w.r1 = rec.r1;
    w.r2 = rec.r2;
    w.L1 = rec.L1;
    w.T1 = rec.T1;
    w.T2 = rec.T2;
    w.mode = std::span<const int>(reinterpret_cast<const int*>(rec.mode.data()), rec.mode.size());
    w.failed = !complete;
    w.failure = out.failure;
    classes.push_back(classify_orbit(w, scales, settings));
  }
  return classes;
}

namespace {
// The state travels as its row (physics/state_row.hpp), bit for bit.
void put_state(ByteWriter& w, const physics::State& s) { w.put_vector(physics::state_row(s)); }
physics::State get_state(ByteReader& r) {
  const auto row = r.get_vector<double>();
  if (row.size() != physics::kStateCols) throw std::runtime_error("state: wrong number of columns");
  return physics::state_from_row(row);
}
}  // namespace

std::vector<std::byte> encode(const physics::State& s) {
  ByteWriter w;
  put_state(w, s);
  return w.take();
}

physics::State decode_state(const std::vector<std::byte>& bytes) {
  ByteReader r(bytes.data(), bytes.size());
  return get_state(r);
}

std::vector<std::byte> encode(const TaskOutput& o) {
  ByteWriter w;
  w.put<std::uint8_t>(o.ok);
  w.put_string(o.failure);
  put_state(w, o.final_state);
  for (long v : {o.steps, o.rhs_evals, o.impacts, o.sticks, o.slack_phases}) w.put<std::int64_t>(v);
  w.put(o.simulated);
  w.put(o.skipped);
  w.put<std::uint64_t>(o.windows.size());
  for (const WindowRecord& rec : o.windows) {
    w.put<std::int32_t>(rec.index);
    for (const auto* v : {&rec.t, &rec.omega_m, &rec.r1, &rec.r2, &rec.L1, &rec.T1, &rec.T2}) w.put_vector(*v);
    w.put_vector(rec.mode);
    w.put(rec.first);
    w.put(rec.last);
  }
  return w.take();
}

TaskOutput decode_output(const std::vector<std::byte>& bytes) {
  ByteReader r(bytes.data(), bytes.size());
  TaskOutput o;
  o.ok = r.get<std::uint8_t>() != 0;
  o.failure = r.get_string();
  o.final_state = get_state(r);
  for (long* v : {&o.steps, &o.rhs_evals, &o.impacts, &o.sticks, &o.slack_phases}) *v = long(r.get<std::int64_t>());
  o.simulated = r.get<double>();
  o.skipped = r.get<double>();
  o.windows.resize(r.get<std::uint64_t>());
  for (WindowRecord& rec : o.windows) {
    rec.index = r.get<std::int32_t>();
    for (auto* v : {&rec.t, &rec.omega_m, &rec.r1, &rec.r2, &rec.L1, &rec.T1, &rec.T2}) *v = r.get_vector<double>();
    rec.mode = r.get_vector<std::int32_t>();
    rec.first = r.get<EnergyLedger>();
    rec.last = r.get<EnergyLedger>();
  }
  if (!r.done()) throw std::runtime_error("sweep codec: trailing bytes in a task output");
  return o;
}

}  // namespace ajx::sweep
