// The progress line: ETAs from the stage's own rate (a long preparation does not inflate
// the pull's estimate), no ETA before the rate can be measured, none negative, stages
// that end on a criterion show it instead of a percentage, values with 4 digits.
#include <gtest/gtest.h>

#include <algorithm>

#include "io/progress.hpp"

namespace geodem {
namespace {

TEST(Progress, EtaFromTheStagesOwnRate) {
  Progress p(true);
  // 60 s of preparation, then a pull that does 10 % in 5 s: 45 s left, not 600.
  p.line("foundation layer 1 of about 4", 100, 0.1, -1.0, "unbalanced 0.2", -1.0, 0.0);
  const std::string start = p.line("pull", 1000, 1.0, 0.0, "T 0 N/m", -1.0, 60.0);
  EXPECT_EQ(start.find("ETA"), std::string::npos) << start;  // no rate yet
  const std::string later = p.line("pull", 2000, 2.0, 0.1, "T 1.234e+04 N/m", -1.0, 65.0);
  EXPECT_NE(later.find("pull: 10.0 %, ETA 45 s, T 1.234e+04 N/m"), std::string::npos) << later;
  EXPECT_NE(later.find("elapsed 65 s"), std::string::npos) << later;
  const std::string done = p.line("pull", 3000, 3.0, 1.0, "", -1.0, 110.0);
  EXPECT_NE(done.find("100.0 %, ETA 0 s"), std::string::npos) << done;
  EXPECT_EQ(done.find("-"), std::string::npos) << done;
  EXPECT_NE(done.find("elapsed 1 min 50 s"), std::string::npos) << done;
}

TEST(Progress, CriterionStagesAndTheWholeRun) {
  Progress p(true);
  const std::string settle =
      p.line("consolidation", 10, 0.5, -1.0, "unbalanced 0.03 (at rest below 0.01)", 0.2, 3.0);
  EXPECT_EQ(std::count(settle.begin(), settle.end(), '%'), 1) << settle;  // the run's only
  EXPECT_NE(settle.find("run 20 %"), std::string::npos) << settle;
  EXPECT_NE(settle.find("(at rest below 0.01)"), std::string::npos);
  // A test of 2: the run's ETA from its progress since the test began.
  p.line("compression 2/2", 10, 0.5, 0.0, "q 1e+05 Pa", 0.5, 100.0);
  const std::string c = p.line("compression 2/2", 10, 0.5, 0.5, "q 1.403e+05 Pa", 0.75, 120.0);
  EXPECT_NE(c.find("50.0 %, ETA 20 s"), std::string::npos) << c;
  EXPECT_NE(c.find("run 75 %, ETA 20 s"), std::string::npos) << c;
}

TEST(Progress, Formats) {
  EXPECT_EQ(format_sig(140286.33590078744), "1.403e+05");
  EXPECT_EQ(format_sig(0.0123456), "0.01235");
  EXPECT_EQ(format_duration(-0.2), "0 s");
  EXPECT_EQ(format_duration(192.0), "3 min 12 s");
  EXPECT_EQ(format_duration(7500.0), "2 h 05 min");
}

}  // namespace
}  // namespace geodem
