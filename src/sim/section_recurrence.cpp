#include "sim/section_recurrence.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ajx::sim {

std::optional<Period> SectionRecurrence::add(SectionPoint point, double time_left) {
  points_.push_back(std::move(point));
  if (points_.size() > kMaxPoints) points_.pop_front();
  for (int k = 1; k <= kMaxCrossings; ++k)  // the shortest period that recurs
    if (auto period = test(k, time_left)) return period;
  return std::nullopt;
}

// Every crossing i of the last `history` seconds against the one a period before: the same
// direction, n max_i |p_i − p_{i−k}| ≤ ε l, and the newest shift no larger than the oldest (a
// deviation growing as e^{γ t}, γ > 0, as a lag just past its Hopf point, outruns the linear
// bound n s: it is never taken for a periodic orbit).
std::optional<Period> SectionRecurrence::test(int k, double time_left) const {
  const int j = int(points_.size()) - 1;
  if (j < k) return std::nullopt;
  const SectionPoint &now = points_[std::size_t(j)], &before = points_[std::size_t(j - k)];
  Period per;
  per.crossings = k;
  per.T = now.t - before.t;
  const double n = std::floor(time_left / per.T);  // whole periods that fit
  if (!(per.T > 0.0) || n < 1.0) return std::nullopt;
  double s_max = 0.0, s_new = 0.0, s_old = 0.0;
  int i = j;
  for (; i >= k; --i) {
    const SectionPoint &a = points_[std::size_t(i)], &b = points_[std::size_t(i - k)];
    if (a.direction != b.direction || a.p.size() != b.p.size()) return std::nullopt;
    s_old = (a.p - b.p).norm();
    if (i == j) s_new = s_old;
    s_max = std::max(s_max, s_old);
    if (n * s_max > tol_) return std::nullopt;
    if (b.t <= now.t - std::max(history_, 2.0 * per.T)) break;  // the pairs cover the history, two periods at least
  }
  if (i < k) return std::nullopt;  // not yet a history's worth of crossings
  if (s_new > s_old) return std::nullopt;  // the drift grows over the history
  per.distance = n * s_max;
  per.turn = now.psi - before.psi;
  for (std::size_t w = 0; w < per.works.size(); ++w) per.works[w] = now.works[w] - before.works[w];
  return per;
}

}  // namespace ajx::sim
