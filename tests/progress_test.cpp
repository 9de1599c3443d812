// Progress lines: the count and the estimate of the time left, and the decoder showing them
// when (and only when) stderr is a terminal.
#include <gtest/gtest.h>

#include <cstdlib>

#include "common/core/progress.h"
#include "tests/test_support.h"

namespace tdvo {
namespace {

TEST(Progress, LineCountsAndEstimatesTheTimeLeft) {
  EXPECT_EQ(Progress::line("frame", 0, 10, 0.0), "frame 0/10");
  EXPECT_EQ(Progress::line("frame", 5, 10, 2.0), "frame 5/10, about 2 s left");
  EXPECT_EQ(Progress::line("frame", 1, 100, 3.0), "frame 1/100, about 4 min 57 s left");
  EXPECT_EQ(Progress::line("frame", 1, 1000, 10.0), "frame 1/1000, about 2 h 46 min left");
  EXPECT_EQ(Progress::line("frame", 10, 10, 7.0), "frame 10/10");
}

// The decoder's progress reaches a terminal (a pseudo-terminal made by script(1)), not a file.
TEST(Progress, DecoderShowsItOnATerminalOnly) {
  if (std::system("command -v script > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "script(1) is not installed";
  test::TempDir dir("progress");
  const std::string bin = TDVO_BIN_DIR;
  const test::CommandResult sample = test::run(dir, bin + "/3dvo-sample", {"-o", "in"});
  ASSERT_EQ(sample.exitCode, 0) << sample.err;
  const test::CommandResult enc =
      test::run(dir, bin + "/3dvo-enc",
                {"--InputMeshPattern=in/%04d.obj", "--FrameCount=4", "--BitstreamFile=x.3dvo"});
  ASSERT_EQ(enc.exitCode, 0) << enc.err;
  const test::CommandResult plain = test::run(dir, bin + "/3dvo-dec", {"-i", "x.3dvo"});
  ASSERT_EQ(plain.exitCode, 0) << plain.err;
  EXPECT_EQ(plain.err, "");
  const test::CommandResult tty = test::run(
      dir, "script", {"-qec", test::shellQuote(bin + "/3dvo-dec") + " -i x.3dvo", "/dev/null"});
  ASSERT_EQ(tty.exitCode, 0) << tty.out;
  EXPECT_NE(tty.out.find("3dvo-dec: frame 4/4"), std::string::npos) << tty.out;
}

}  // namespace
}  // namespace tdvo
