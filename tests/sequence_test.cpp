// Frame-numbered file patterns (common/core/sequence.h).
#include <gtest/gtest.h>

#include <string>

#include "common/core/error.h"
#include "common/core/sequence.h"

namespace tdvo {
namespace {

std::string patternError(const std::string& pattern) {
  try {
    checkFramePattern(pattern, "InputMeshPattern");
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for '" << pattern << "'";
  return "";
}

TEST(Sequence, Conversions) {
  EXPECT_EQ(framePath("seq/%d.obj", 7), "seq/7.obj");
  EXPECT_EQ(framePath("seq/%d.obj", 12345), "seq/12345.obj");
  EXPECT_EQ(framePath("seq/%4d.obj", 7), "seq/   7.obj");
  EXPECT_EQ(framePath("seq/%04d.obj.gz", 7), "seq/0007.obj.gz");
  EXPECT_EQ(framePath("seq/%04d.obj.gz", 0), "seq/0000.obj.gz");
  EXPECT_EQ(framePath("seq/%04d.obj", 123456), "seq/123456.obj");  // wider numbers are not cut
  EXPECT_EQ(framePath("%03d", 5), "005");
  EXPECT_EQ(framePath("f%0d.obj", 5), "f5.obj");
  EXPECT_EQ(framePath("mesh_%d_%%.obj", 3), "mesh_3_%.obj");
}

TEST(Sequence, PercentEscapes) {
  EXPECT_EQ(framePath("100%%/f%03d.obj", 9), "100%/f009.obj");
  EXPECT_EQ(framePath("%%%d%%%%", 1), "%1%%");
  EXPECT_EQ(framePath("a%%d/%d", 2), "a%d/2");
  checkFramePattern("100%%/f%03d.obj", "X");
}

TEST(Sequence, OutputPatternsAreRelative) {
  checkOutputFramePattern("sub/f%04d.obj", "OutputMeshPattern");
  try {
    checkOutputFramePattern("/tmp/f%04d.obj", "OutputMeshPattern");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "OutputMeshPattern: '/tmp/f%04d.obj' is an absolute path; it names files inside "
              "the output folder (give a relative path)");
  }
}

TEST(Sequence, NoConversion) {
  EXPECT_EQ(patternError("frame.obj"),
            "InputMeshPattern: 'frame.obj' needs one frame-number conversion such as %04d");
  EXPECT_EQ(patternError(""),
            "InputMeshPattern: '' needs one frame-number conversion such as %04d");
  EXPECT_EQ(patternError("100%%d.obj"),
            "InputMeshPattern: '100%%d.obj' needs one frame-number conversion such as %04d");
}

TEST(Sequence, TwoConversions) {
  EXPECT_EQ(patternError("%d/%04d.obj"),
            "InputMeshPattern: '%d/%04d.obj' has more than one frame-number conversion");
}

TEST(Sequence, BadConversions) {
  for (const std::string pattern : {"%s.obj", "%x.obj", "%5.obj", "%-4d.obj", "frame%", "%ld.obj",
                                    "%+d", "%.3d", "%040d", "%d%"})
    EXPECT_EQ(patternError(pattern),
              "InputMeshPattern: '" + pattern + "': only %d, %Nd and %0Nd conversions are allowed")
        << pattern;
}

TEST(Sequence, FramePathChecksThePattern) {
  EXPECT_THROW(framePath("frame.obj", 1), Error);
  EXPECT_THROW(framePath("%d%d", 1), Error);
  try {
    framePath("%s", 1);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "frame pattern: '%s': only %d, %Nd and %0Nd conversions are allowed");
  }
}

}  // namespace
}  // namespace tdvo
