#include "sweep/protocol.hpp"

#include <cmath>
#include <stdexcept>

namespace ajx::sweep {

namespace {

struct Builder {
  CompiledProtocol out;
  double t = 0.0, omega = 0.0;

  // ω_m from the current value to `to` at |rate|; returns the time it took.
  double ramp_to(double to, double rate) {
    if (to == omega) return 0.0;
    const double T = std::abs(to - omega) / rate;
    out.schedule.push_back({omega, to, T});
    t += T;
    omega = to;
    return T;
  }
  void hold(double T) {
    if (T <= 0.0) return;
    out.schedule.push_back({omega, omega, T});
    t += T;
  }
};

void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(what);
}

}  // namespace

constexpr double kMaxWindows = 1e6;

CompiledProtocol compile(const std::vector<Segment>& segments, double omega_start) {
  require(!segments.empty(), "protocol: no segments");
  Builder b;
  b.omega = omega_start;
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const Segment& s = segments[k];
    if (s.kind == Segment::Kind::Ramp) {
      const Ramp& r = s.ramp;
      require(r.rate > 0.0 && r.window > 0.0 && r.from >= 0.0 && r.to >= 0.0 && r.from != r.to,
              "protocol: a ramp needs rate > 0, window > 0, from != to, both >= 0");
      b.ramp_to(r.from, r.rate);  // unmeasured approach
      // Windows of `window` seconds; the last one takes what is left (at least half a window,
      // else it is merged into the previous one).
      const double T = std::abs(r.to - r.from) / r.rate;
      // A bound on the windows (each is stored with its samples): also keeps n an int.
      require(T / r.window + double(b.out.windows.size()) <= kMaxWindows,
              "protocol: more than 1e6 windows (a ramp's |to - from| / rate / window is too large)");
      const int n = std::max(1, int(std::floor(T / r.window + 0.5)));
      const double w = T / n, dir = r.to > r.from ? 1.0 : -1.0;
      for (int i = 0; i < n; ++i) {
        const double t0 = b.t + i * w, t1 = b.t + (i + 1) * w;
        b.out.windows.push_back({t0, t1, r.from + dir * r.rate * i * w, r.from + dir * r.rate * (i + 1) * w, int(k),
                                 int(dir)});
      }
      b.out.windows.back().omega_end = r.to;
      b.ramp_to(r.to, r.rate);
      b.out.windows.back().t_end = b.t;
    } else {
      const Steps& st = s.steps;
      require(st.num >= 1 && st.measure > 0.0 && st.settle >= 0.0 && st.step_rate > 0.0 && st.from >= 0.0 &&
                  st.to >= 0.0,
              "protocol: steps need num >= 1, measure > 0, settle >= 0, step_rate > 0, from/to >= 0");
      // A staircase has the direction of its levels (thresholds need it); a single level none.
      const int dir = st.to > st.from ? 1 : (st.to < st.from ? -1 : 0);
      require(double(st.num) + double(b.out.windows.size()) <= kMaxWindows, "protocol: more than 1e6 windows");
      for (int i = 0; i < st.num; ++i) {
        const double level = st.num == 1 ? st.from : st.from + (st.to - st.from) * i / (st.num - 1);
        b.ramp_to(level, st.step_rate);
        const double t_settle = b.t;
        b.hold(st.settle);
        const double t0 = b.t;
        b.hold(st.measure);
        b.out.windows.push_back({t0, b.t, level, level, int(k), st.num > 1 ? dir : 0, t_settle});
      }
    }
  }
  b.out.duration = b.t;
  return b.out;
}

std::vector<TaskSpan> split(const CompiledProtocol& p, int windows_per_task) {
  require(windows_per_task >= 1, "protocol: windows_per_task must be >= 1");
  std::vector<TaskSpan> tasks;
  const int n = int(p.windows.size());
  double t = 0.0;
  for (int first = 0; first < n; first += windows_per_task) {
    const int num = std::min(windows_per_task, n - first);
    const double t_end = p.windows[std::size_t(first + num - 1)].t_end;
    tasks.push_back({t, t_end, first, num});
    t = t_end;
  }
  return tasks;
}

}  // namespace ajx::sweep
