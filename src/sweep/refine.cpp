#include "sweep/refine.hpp"

#include <stdexcept>

namespace ajx::sweep {

std::vector<physics::DriveSegment> schedule_until(const std::vector<physics::DriveSegment>& schedule, double t_cut,
                                                  double omega_cut) {
  std::vector<physics::DriveSegment> out;
  double t = 0.0;
  for (physics::DriveSegment s : schedule) {
    if (t >= t_cut) break;
    if (t + s.duration >= t_cut) {
      s.duration = t_cut - t;
      s.omega_end = omega_cut;
      if (s.duration > 0.0) out.push_back(s);
      break;
    }
    out.push_back(s);
    t += s.duration;
  }
  return out;
}

ChainSetup refined_chain(const ChainSetup& chain, const std::vector<Segment>& segments, const Bracket& bracket,
                         int factor) {
  const auto& windows = chain.protocol.windows;
  if (factor < 1) throw std::invalid_argument("refinement: the factor must be >= 1");
  if (bracket.window_before < 0 || bracket.window_after <= bracket.window_before ||
      std::size_t(bracket.window_after) >= windows.size())
    throw std::invalid_argument("refinement: the bracket's windows are not in the chain");
  const Window &a = windows[std::size_t(bracket.window_before)], &b = windows[std::size_t(bracket.window_after)];
  if (a.direction == 0 || a.direction != b.direction)
    throw std::invalid_argument("refinement: the bracket's windows are not of one ramp or staircase direction");

  const Segment& seg = segments.at(std::size_t(a.segment));
  Segment slow = seg;
  if (seg.kind == Segment::Kind::Ramp) {
    // From the start of the window before to the end of the window after, rate/factor.
    slow.ramp = {a.omega_begin, b.omega_end, seg.ramp.rate / factor, seg.ramp.window};
  } else {
    // The levels of the two windows and factor − 1 new ones between each pair of old ones.
    const int gaps = bracket.window_after - bracket.window_before;
    slow.steps.from = a.omega_begin;
    slow.steps.to = b.omega_begin;
    slow.steps.num = factor * gaps + 1;
  }
  const CompiledProtocol tail = compile({slow}, a.omega_begin);

  ChainSetup out = chain;
  out.protocol.schedule = schedule_until(chain.protocol.schedule, a.t_begin, a.omega_begin);
  out.protocol.schedule.insert(out.protocol.schedule.end(), tail.schedule.begin(), tail.schedule.end());
  out.protocol.windows = tail.windows;
  for (Window& w : out.protocol.windows) {
    w.t_begin += a.t_begin;
    w.t_end += a.t_begin;
    w.segment = a.segment;
  }
  out.protocol.duration = a.t_begin + tail.duration;
  return out;
}

Refinement refine_threshold(Threshold t, const ChainSetup& chain, const std::vector<Segment>& segments,
                            const Bracket& bracket, int factor, const physics::State& start,
                            const ClassifierSettings& settings) {
  const ChainSetup fine = refined_chain(chain, segments, bracket, factor);
  if (start.t > fine.protocol.windows.front().t_begin)
    throw std::invalid_argument("refinement: the start state is later than the bracket");
  const TaskSpan span{start.t, fine.protocol.duration, 0, int(fine.protocol.windows.size())};
  const TaskOutput out = run_task(fine, span, start);
  const std::vector<OrbitClassification> classes = classify_windows(fine, out, settings);

  Refinement r;
  r.factor = factor;
  r.ok = out.ok;
  r.failure = out.failure;
  r.simulated = out.simulated;
  for (std::size_t i = 0; i < classes.size(); ++i) {
    const Window& w = fine.protocol.windows[std::size_t(out.windows[i].index)];
    r.windows.push_back({w.omega_begin, w.omega_end, w.direction, classes[i].cls, out.windows[i].index});
  }
  r.bracket = find_threshold(t, r.windows);
  return r;
}

}  // namespace ajx::sweep
