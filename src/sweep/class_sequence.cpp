#include "sweep/class_sequence.hpp"

#include <cmath>
#include <stdexcept>

namespace ajx::sweep {

namespace {

// Least-squares slope of y over x, NaN with fewer than two points or no spread in x.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  if (n < 2) return ClassRun::nan;
  double mx = 0.0, my = 0.0;
  for (std::size_t i = 0; i < n; ++i) mx += x[i] / double(n), my += y[i] / double(n);
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t i = 0; i < n; ++i) sxx += (x[i] - mx) * (x[i] - mx), sxy += (x[i] - mx) * (y[i] - my);
  return sxx > 0.0 ? sxy / sxx : ClassRun::nan;
}
}  // namespace

std::vector<ClassRun> class_runs(const std::vector<ClassedWindow>& w, const std::vector<double>& omega_ball,
                                 bool absorb_blips) {
  if (w.size() != omega_ball.size())
    throw std::invalid_argument("class sequence: one omega_ball per window is needed");
  const std::size_t n = w.size();
  std::vector<int> leg(n, 0);
  for (std::size_t i = 1; i < n; ++i) leg[i] = leg[i - 1] + (w[i].direction != w[i - 1].direction);
  // Blips: one not-settled window between two windows of the same other class, on one leg.
  std::vector<OrbitClass> cls(n);
  std::vector<bool> blip(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    cls[i] = w[i].cls;
    if (absorb_blips && i > 0 && i + 1 < n && w[i].cls == OrbitClass::NotSettled && w[i - 1].cls == w[i + 1].cls &&
        w[i - 1].cls != OrbitClass::NotSettled && leg[i - 1] == leg[i + 1]) {
      cls[i] = w[i - 1].cls;
      blip[i] = true;
    }
  }
  std::vector<ClassRun> runs;
  std::vector<double> x, y;
  const auto close = [&] {
    if (runs.empty()) return;
    ClassRun& r = runs.back();
    r.omega_ball_slope = slope(x, y);
    if (!y.empty()) {
      double s = 0.0;
      for (double v : y) s += v;
      r.omega_ball_mean = s / double(y.size());
    }
    x.clear();
    y.clear();
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (runs.empty() || runs.back().leg != leg[i] || runs.back().cls != cls[i]) {
      close();
      ClassRun r;
      r.leg = leg[i];
      r.direction = w[i].direction;
      r.cls = cls[i];
      r.omega_from = w[i].omega_begin;
      r.first = int(i);
      runs.push_back(r);
    }
    ClassRun& r = runs.back();
    r.omega_to = w[i].omega_end;
    r.last = int(i);
    ++r.windows;
    r.blips += blip[i];
    if (std::isfinite(omega_ball[i]) && !blip[i]) {
      x.push_back(w[i].omega_mean());
      y.push_back(omega_ball[i]);
    }
  }
  close();
  return runs;
}

std::string_view to_string(PaperStep s) {
  switch (s) {
    case PaperStep::Rise: return "rise";
    case PaperStep::Circular: return "circular";
    case PaperStep::Fall: return "fall";
    case PaperStep::Locked: return "locked";
    case PaperStep::Omega1: return "omega_1";
    case PaperStep::Omega2: return "omega_2";
  }
  return "?";
}

std::string_view describe(PaperStep s) {
  switch (s) {
    case PaperStep::Rise: return "up: fallen -> climb (omega_rise)";
    case PaperStep::Circular: return "a circular orbit after the climb";
    case PaperStep::Fall: return "down: circular -> fallen (omega_fall)";
    case PaperStep::Locked: return "up: locked-circular";
    case PaperStep::Omega1: return "up: locked -> lagging, omega_ball nearly constant (omega_1)";
    case PaperStep::Omega2: return "up: circular -> flower (omega_2)";
  }
  return "?";
}

std::string_view to_string(StepStatus s) {
  switch (s) {
    case StepStatus::Present: return "present";
    case StepStatus::OutOfOrder: return "out of order";
    case StepStatus::Missing: return "missing";
  }
  return "?";
}

namespace {

// Whether step s happens at run j: for a transition, run j is the run entered.
bool happens(PaperStep s, const std::vector<ClassRun>& runs, std::size_t j) {
  const ClassRun& r = runs[j];
  // The nearest earlier run of the same leg that is not not-settled (for s's "from" class).
  const auto before = [&](bool skip_not_settled) -> const ClassRun* {
    for (std::size_t i = j; i-- > 0;) {
      if (runs[i].leg != r.leg) return nullptr;
      if (!skip_not_settled || runs[i].cls != OrbitClass::NotSettled) return &runs[i];
    }
    return nullptr;
  };
  switch (s) {
    case PaperStep::Rise: {
      const ClassRun* a = before(false);
      return r.direction > 0 && a && a->cls == OrbitClass::Fallen && r.cls != OrbitClass::Fallen &&
             r.cls != OrbitClass::Failed;
    }
    case PaperStep::Circular: return circular(r.cls);
    case PaperStep::Fall: {
      const ClassRun* a = before(true);
      return r.direction < 0 && r.cls == OrbitClass::Fallen && a && circular(a->cls);
    }
    case PaperStep::Locked: return r.direction > 0 && r.cls == OrbitClass::LockedCircular;
    case PaperStep::Omega1: {
      const ClassRun* a = before(true);
      return r.direction > 0 && r.cls == OrbitClass::LaggingCircular && a && a->cls == OrbitClass::LockedCircular;
    }
    case PaperStep::Omega2: {
      const ClassRun* a = before(true);
      return r.direction > 0 && r.cls == OrbitClass::Flower && a && circular(a->cls);
    }
  }
  return false;
}

}  // namespace

std::vector<StepMatch> compare_with_paper(const std::vector<ClassRun>& runs) {
  std::vector<StepMatch> out;
  std::size_t pos = 0;  // steps are looked for from the run of the last step found
  for (PaperStep s : kPaperSteps) {
    StepMatch m{s};
    for (std::size_t j = pos; j < runs.size() && m.run < 0; ++j)
      if (happens(s, runs, j)) m = {s, StepStatus::Present, int(j), runs[j].omega_from};
    for (std::size_t j = 0; j < pos && m.run < 0; ++j)
      if (happens(s, runs, j)) m = {s, StepStatus::OutOfOrder, int(j), runs[j].omega_from};
    if (m.status == StepStatus::Present) pos = std::size_t(m.run);
    out.push_back(m);
  }
  return out;
}

}  // namespace ajx::sweep
