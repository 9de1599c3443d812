// Acceptance 2 of issue 2 on real data: horse-gallop frames 1..48 at GridBits 12, with one GOM
// of 48 frames and with GOMs of one frame. The encoder's and the decoder's MD5 lines are
// identical for all 48 frames and every decoded vertex lies within half a grid step of its input
// vertex. Checked at library level (every vertex) and through the real apps (MD5 lines,
// --verify). Skipped when ../shared/data is absent.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "common/core/gom_list.h"
#include "common/core/md5.h"
#include "common/core/obj_io.h"
#include "common/core/sequence.h"
#include "tests/roundtrip_check.h"
#include "tests/test_support.h"

namespace tdvo {
namespace {

constexpr int kFirstFrame = 1;
constexpr int kFrames = 48;
const std::string kPattern =
    std::string(TDVO_SHARED_DATA_DIR) + "/meshseq/horse-gallop/%04d.obj.gz";

// The 48 frames, read once for all tests; empty when the data is absent.
const std::vector<Mesh>& horse() {
  static const std::vector<Mesh> frames = [] {
    std::vector<Mesh> out;
    for (int k = 0; k < kFrames; ++k)
      if (!std::filesystem::exists(framePath(kPattern, kFirstFrame + k))) return out;
    for (int k = 0; k < kFrames; ++k)
      out.push_back(readObj(framePath(kPattern, kFirstFrame + k)));
    return out;
  }();
  return frames;
}

struct Case {
  int gomSize;
  PMeshMode mode;
};

const char* modeName(PMeshMode mode) {
  return mode == PMeshMode::kIntra ? "intra" : "d3dmc";
}

class HorseTest : public testing::TestWithParam<Case> {};

// Library level: every vertex of every frame is checked. Apps: the same settings through
// 3dvo-enc and 3dvo-dec give the same MD5 lines as the library, and --verify passes.
TEST_P(HorseTest, EncoderAndDecoderAgree) {
  if (horse().empty())
    GTEST_SKIP() << "horse-gallop data not found (" << kPattern
                 << ", frames 1..48); see the README of the shared data folder";
  const std::vector<Mesh>& frames = horse();
  ASSERT_EQ(frames[0].positions.size(), 8431u);
  ASSERT_EQ(frames[0].triangles.size(), 16843u);
  EncoderParams params;
  params.gridBits = 12;
  params.gomSize = GetParam().gomSize;
  params.pmeshMode = GetParam().mode;
  const test::RoundTrip r = test::encodeAndDecode(frames, params);
  test::checkRoundTrip(frames, r);
  ASSERT_EQ(r.decoderLines.size(), static_cast<size_t>(kFrames));

  test::TempDir dir("horse");
  const test::CommandResult enc =
      test::run(dir, std::string(TDVO_BIN_DIR) + "/3dvo-enc",
                {"--InputMeshPattern=" + kPattern, "--FirstFrame=1", "--FrameCount=48",
                 "--GridBits=12", "--GOMSize=" + std::to_string(params.gomSize),
                 std::string("--PMeshMode=") + modeName(params.pmeshMode), "-o", "horse.3dvo"});
  ASSERT_EQ(enc.exitCode, 0) << enc.err;
  const std::vector<std::string> encLines = test::linesStartingWith(enc.out, "MD5 frame=");
  // The apps' frame lines (the header line follows them) carry the input's frame numbers
  // (FirstFrame 1), the library's count from 0.
  std::vector<std::string> numbered;
  for (size_t k = 0; k < r.decoderFrames.size(); ++k)
    numbered.push_back(geometryHashLine(static_cast<int>(k) + 1, r.decoderFrames[k]));
  EXPECT_EQ(encLines, numbered);
  test::writeText(dir.file("enc.log"), enc.out);
  const test::CommandResult dec =
      test::run(dir, std::string(TDVO_BIN_DIR) + "/3dvo-dec",
                {"-i", "horse.3dvo", "-o", "out", "--verify", "enc.log"});
  ASSERT_EQ(dec.exitCode, 0) << dec.err;
  EXPECT_EQ(test::linesStartingWith(dec.out, "MD5 frame="), encLines);
  EXPECT_EQ(test::linesStartingWith(dec.out, "MD5 header="),
            test::linesStartingWith(enc.out, "MD5 header="));
  EXPECT_EQ(test::listFolder(dir.path() / "out").size(), static_cast<size_t>(kFrames) + 1u);
  // gom_starts.txt lists the GOMs' first frames (input frame numbers, from 1).
  std::vector<int> starts;
  for (int f = 0; f < kFrames; f += params.gomSize)
    starts.push_back(f + 1);
  EXPECT_EQ(readGomStarts(dir.file("out/gom_starts.txt")), starts);
  // The decoder's last OBJ (input frame 48) is the library's last decoded frame, dequantised.
  EXPECT_EQ(test::readText(dir.file("out/0048.obj")),
            formatObj(r.decodedGrid.dequantise(r.decoderFrames[47])));
}

INSTANTIATE_TEST_SUITE_P(Gom, HorseTest,
                         testing::Values(Case{48, PMeshMode::kD3dmc}, Case{48, PMeshMode::kIntra},
                                         Case{1, PMeshMode::kIntra}),
                         [](const testing::TestParamInfo<Case>& info) {
                           return "gom" + std::to_string(info.param.gomSize) + "_" +
                                  modeName(info.param.mode);
                         });

}  // namespace
}  // namespace tdvo
