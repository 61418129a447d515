// The sweep's progress line: on a terminal a bar redrawn in place, elsewhere (a batch log) a
// plain line every few seconds; both with the share done, the rate and an h:mm:ss ETA.
#pragma once
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <string>

namespace ajx::app {

// h:mm:ss, or "--:--:--" when unknown.
inline std::string clock_text(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--:--";
  const long s = std::lround(seconds);
  return fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60);
}

// `share` in [0, 1] of the simulated seconds; `rate` simulated s per wall s; `eta` [s].
inline std::string progress_line(long long done, long long total, long long failed, double share, double rate,
                                 double eta, bool terminal) {
  const double pct = 100.0 * std::clamp(share, 0.0, 1.0);
  const std::string failures = failed > 0 ? fmt::format(", {} failed", failed) : "";
  if (!terminal)
    return fmt::format("{:.0f} % ({}/{} tasks{}), {:.0f} simulated s per wall s, ETA {}", pct, done, total, failures,
                       rate, clock_text(eta));
  constexpr int kWidth = 24;
  const int filled = int(std::lround(pct / 100.0 * kWidth));
  return fmt::format("[{}{}] {:3.0f} %  {}/{} tasks{}  {:.0f} sim s/s  ETA {}", std::string(std::size_t(filled), '#'),
                     std::string(std::size_t(kWidth - filled), '.'), pct, done, total, failures, rate, clock_text(eta));
}

}  // namespace ajx::app
