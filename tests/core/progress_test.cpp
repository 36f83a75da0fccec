// Progress when stderr is not a terminal (logs, CI): a closing line with the count and the unit, and
// nothing at all when quiet.
#include <gtest/gtest.h>

#include "core/progress.h"

namespace isoatlas {
namespace {

TEST(Progress, PlainClosingLineWhenNotATerminal) {
  ::testing::internal::CaptureStderr();
  {
    Progress p("reading", 1000, "slices");
    for (int i = 0; i <= 1000; ++i) p.update(std::uint64_t(i));
  }
  const std::string out = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(out.rfind("reading: done, 1000 slices in ", 0), 0u) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
}

TEST(Progress, QuietPrintsNothing) {
  Progress::setQuiet(true);
  ::testing::internal::CaptureStderr();
  {
    Progress p("reading", 10);
    p.update(10);
    logInfo("hello");
  }
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  Progress::setQuiet(false);
}

}  // namespace
}  // namespace isoatlas
