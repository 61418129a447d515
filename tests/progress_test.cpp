// The sweep's progress line: h:mm:ss, the share, and the bar on a terminal.
#include <gtest/gtest.h>

#include <limits>

#include "app/progress.hpp"

using ajx::app::clock_text;
using ajx::app::progress_line;

TEST(Progress, ClockText) {
  EXPECT_EQ(clock_text(0.4), "0:00:00");
  EXPECT_EQ(clock_text(83), "0:01:23");
  EXPECT_EQ(clock_text(3 * 3600 + 61), "3:01:01");
  EXPECT_EQ(clock_text(std::numeric_limits<double>::quiet_NaN()), "--:--:--");
}

TEST(Progress, PlainLineForLogsAndABarForTerminals) {
  EXPECT_EQ(progress_line(17, 39, 0, 0.5, 1830.4, 83, false),
            "50 % (17/39 tasks), 1830 simulated s per wall s, ETA 0:01:23");
  EXPECT_EQ(progress_line(17, 39, 2, 0.25, 10, std::numeric_limits<double>::quiet_NaN(), true),
            "[######..................]  25 %  17/39 tasks, 2 failed  10 sim s/s  ETA --:--:--");
  EXPECT_EQ(progress_line(39, 39, 0, 1.0, 5, 0, true).substr(0, 26), "[########################]");
}
