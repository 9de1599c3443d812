// The GOM list (common/core/gom_list.h) and the encoder's GOMListFile: every line is checked with a
// message naming the file and line; GOMs of uneven length are coded as one stream that decodes
// bit-exactly, with the GOM headers of the list, keyframes chosen inside each GOM and a texture
// IDR picture at every GOM start and nowhere else.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "bitstream/byte_io.h"
#include "bitstream/syntax.h"
#include "bitstream/units.h"
#include "common/core/error.h"
#include "common/core/gom_list.h"
#include "encoder/encoder_params.h"
#include "roundtrip_check.h"
#include "test_support.h"

namespace tdvo {
namespace {

std::string parseError(const std::string& text, size_t frameCount = 0) {
  try {
    parseGomList(text, "goms.txt", frameCount);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

// The GOM headers of a stream, in stream order.
std::vector<GomHeader> gomHeaders(const std::vector<uint8_t>& stream) {
  std::vector<GomHeader> headers;
  UnitReader reader(stream.data(), stream.size(), "s.3dvo");
  UnitView u;
  while (reader.next(u))
    if (u.type == static_cast<uint8_t>(UnitType::kGomHeader)) {
      ByteReader r(u.payload, u.size, u.describe(), u.payloadOffset);
      headers.emplace_back();
      transfer(r, headers.back());
    }
  return headers;
}

// Whether an H.264 access unit (Annex B) holds an IDR slice (nal_unit_type 5).
bool holdsIdrSlice(const std::vector<uint8_t>& au) {
  for (size_t i = 0; i + 3 < au.size(); ++i)
    if (au[i] == 0 && au[i + 1] == 0 && au[i + 2] == 1 && (au[i + 3] & 0x1F) == 5) return true;
  return false;
}

// The header comment says what the numbers are: counted from the first output frame, not the
// output files' numbers (which are the input's frame numbers, 0200.obj ... with FirstFrame 200).
TEST(GomList, FormatSaysFramesCountFromFirstFrame) {
  const std::string text = formatGomList({{0, 2}});
  EXPECT_EQ(text.rfind("# 3dvo-recon GOM list: ", 0), 0u) << text;
  EXPECT_NE(text.find("counted from the first output frame (0 = FirstFrame)"), std::string::npos)
      << text;
  EXPECT_EQ(text.find("numbered as the output"), std::string::npos) << text;
}

TEST(GomList, FormatAndParseRoundTrip) {
  const GomList goms = {{0, 5}, {5, 16}, {21, 1}};
  EXPECT_EQ(parseGomList(formatGomList(goms), "goms.txt"), goms);
  EXPECT_EQ(parseGomList(formatGomList(goms), "goms.txt", 22), goms);
  // Comments, blank lines, tabs and CR LF line ends.
  EXPECT_EQ(parseGomList("# list\n0 2 # first\n\n  2\t3\r\n", "x", 5), (GomList{{0, 2}, {2, 3}}));
}

TEST(GomList, EveryLineIsChecked) {
  // Not two integers (line 2).
  for (const char* bad : {"1 x", "1", "1 2 3", "1 2.5", "0x2 1", "1e1 1", "one 2"})
    EXPECT_EQ(parseError(std::string("0 1\n") + bad + "\n"),
              "goms.txt:2: expected '<first frame> <frame count>'")
        << bad;
  // Gaps and overlaps.
  EXPECT_EQ(parseError("0 2\n3 1\n"),
            "goms.txt:2: GOM starts at frame 3, expected 2: frame 2 is "
            "in no GOM");
  EXPECT_EQ(parseError("0 2\n5 1\n"),
            "goms.txt:2: GOM starts at frame 5, expected 2: frames 2 .. 4 are in no GOM");
  EXPECT_EQ(parseError("0 2\n# a comment\n1 1\n"),
            "goms.txt:3: GOM starts at frame 1, expected 2: it overlaps the GOM of line 1");
  EXPECT_EQ(parseError("0 2\n2 2\n2 1\n"),
            "goms.txt:3: GOM starts at frame 2, expected 4: it overlaps the GOM of line 2");
  for (const char* first : {"1", "-1"})
    EXPECT_EQ(parseError(std::string(first) + " 2\n"),
              std::string("goms.txt:1: the first GOM starts at frame ") + first +
                  "; it must start at frame 0");
  // Counts.
  for (const char* count : {"0", "-3", "65536"})
    EXPECT_EQ(parseError(std::string("0 ") + count + "\n"),
              "goms.txt:1: frame count must be in 1 .. 65535")
        << count;
  EXPECT_EQ(parseGomList("0 65535\n", "x"), (GomList{{0, 65535}}));
  // Against the coded frames: beyond them, or not all of them.
  EXPECT_EQ(parseError("0 3\n3 4\n", 5),
            "goms.txt:2: GOM of frames 3 .. 6 goes beyond the coded frames 0 .. 4");
  EXPECT_EQ(parseError("0 5\n5 1\n", 5),
            "goms.txt:2: GOM of frame 5 goes beyond the coded frames 0 .. 4");
  EXPECT_EQ(parseError("0 2\n", 5),
            "goms.txt:1: the last GOM ends at frame 1: frames 2 .. 4 of "
            "the coded frames 0 .. 4 are in no GOM");
  EXPECT_EQ(parseError("0 4\n# end\n", 5),
            "goms.txt:1: the last GOM ends at frame 3: frame 4 of "
            "the coded frames 0 .. 4 is in no GOM");
  // Nothing listed.
  EXPECT_EQ(parseError(""), "goms.txt: no GOM listed");
  EXPECT_EQ(parseError("# nothing\n\n"), "goms.txt: no GOM listed");
}

TEST(GomList, ReadFromAFile) {
  test::TempDir dir("gom-list-file");
  test::writeText(dir.file("goms.txt"), "0 2\n2 1\n");
  EXPECT_EQ(readGomList(dir.file("goms.txt"), 3), (GomList{{0, 2}, {2, 1}}));
  try {
    readGomList(dir.file("goms.txt"), 4);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), dir.file("goms.txt") +
                                         ":2: the last GOM ends at frame 2: frame 3 of the "
                                         "coded frames 0 .. 3 is in no GOM");
  }
  EXPECT_THROW(readGomList(dir.file("missing.txt")), Error);
}

// A UTF-8 byte-order mark at the start, as a cfg file may have one (it was "expected '<first
// frame> <frame count>'" and "'' is not a frame index", the mark invisible).
TEST(GomList, ByteOrderMarkAtTheStartIsSkipped) {
  test::TempDir dir("gom-list-bom");
  test::writeText(dir.file("goms.txt"),
                  "\xEF\xBB\xBF"
                  "0 2\r\n2 1\r\n");
  EXPECT_EQ(readGomList(dir.file("goms.txt"), 3), (GomList{{0, 2}, {2, 1}}));
  test::writeText(dir.file("starts.txt"),
                  "\xEF\xBB\xBF"
                  "0\n4\n");
  EXPECT_EQ(readGomStarts(dir.file("starts.txt")), (std::vector<int>{0, 4}));
}

TEST(GomStarts, ReadFromAFileSortedWithoutRepeats) {
  // gom_starts.txt as 3dvo-dec writes it and 3dvo-metrics --GroupStarts reads it.
  test::TempDir dir("gom-starts");
  test::writeText(dir.file("starts.txt"), formatGomStarts({0, 4}));
  EXPECT_EQ(readGomStarts(dir.file("starts.txt")), (std::vector<int>{0, 4}));
  test::writeText(dir.file("goms.txt"), "5, 1  # two GOMs\n1\n");
  EXPECT_EQ(readGomStarts(dir.file("goms.txt")), (std::vector<int>{1, 5}));
  test::writeText(dir.file("bad.txt"), "0 1\n2 -3\n");
  try {
    readGomStarts(dir.file("bad.txt"));
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              dir.file("bad.txt") + ":2: '-3' is not a frame index (a non-negative integer)");
  }
}

TEST(GomListFile, ReplacesGomSizeAndIsCheckedByValidate) {
  test::TempDir dir("gom-list-params");
  EncoderParams params;
  params.gomSize = 4;
  EXPECT_EQ(params.goms(10), (GomList{{0, 4}, {4, 4}, {8, 2}}));
  EXPECT_EQ(params.goms(8), (GomList{{0, 4}, {4, 4}}));
  test::writeText(dir.file("goms.txt"), "0 1\n1 6\n7 3\n");
  params.gomListFile = dir.file("goms.txt");
  EXPECT_EQ(params.goms(10), (GomList{{0, 1}, {1, 6}, {7, 3}}));
  // validate() checks the list against FrameCount before any frame is read.
  params.inputMeshPattern = "in/%03d.obj";
  params.bitstreamFile = "x.3dvo";
  params.frameCount = 10;
  EXPECT_NO_THROW(params.validate());
  params.frameCount = 11;
  try {
    params.validate();
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("goms.txt:3: the last GOM ends at frame 9"),
              std::string::npos)
        << e.what();
  }
}

TEST(RandomAccessRuns, PeriodGomsEachOneRunForZeroEveryGomWithIntra) {
  using Runs = std::vector<std::pair<size_t, size_t>>;
  EncoderParams params;
  params.randomAccessPeriod = 1;
  EXPECT_EQ(params.randomAccessRuns(3), (Runs{{0, 1}, {1, 1}, {2, 1}}));
  params.randomAccessPeriod = 2;
  EXPECT_EQ(params.randomAccessRuns(5), (Runs{{0, 2}, {2, 2}, {4, 1}}));
  params.randomAccessPeriod = 0;
  EXPECT_EQ(params.randomAccessRuns(5), (Runs{{0, 5}}));
  params.pmeshMode = PMeshMode::kIntra;
  EXPECT_EQ(params.randomAccessRuns(2), (Runs{{0, 1}, {1, 1}}));
  EXPECT_EQ(params.randomAccessRuns(0), Runs{});
}

TEST(GomListFile, UnevenGomsEncodeAndDecodeBitExactly) {
  test::TempDir dir("gom-list-encode");
  const std::vector<Mesh> frames = test::wobblingSphere(2, 12);
  const GomList list = {{0, 3}, {3, 1}, {4, 6}, {10, 2}};
  test::writeText(dir.file("goms.txt"), formatGomList(list));
  for (const PMeshMode mode : {PMeshMode::kD3dmc, PMeshMode::kAfxic, PMeshMode::kIntra}) {
    SCOPED_TRACE(static_cast<int>(mode));
    EncoderParams params;
    params.gridBits = 10;
    params.gomSize = 5;  // overridden by the list
    params.gomListFile = dir.file("goms.txt");
    params.pmeshMode = mode;
    params.keyframeCount = mode == PMeshMode::kIntra ? 0 : 3;
    params.threads = 2;
    const test::RoundTrip r = test::encodeAndDecode(frames, params);
    ASSERT_EQ(r.encoderLines.size(), frames.size());
    EXPECT_EQ(r.decoderLines, r.encoderLines);
    // One GOM header per listed GOM; keyframes (first and last frame of the GOM, 3 at most)
    // inside it.
    const std::vector<GomHeader> headers = gomHeaders(r.coded.stream);
    ASSERT_EQ(headers.size(), list.size());
    for (size_t g = 0; g < list.size(); ++g) {
      EXPECT_EQ(headers[g].gh_first_frame, static_cast<uint32_t>(list[g].first)) << g;
      EXPECT_EQ(headers[g].gh_frame_count, list[g].second) << g;
      if (mode == PMeshMode::kIntra) continue;
      const size_t expected = static_cast<size_t>(std::min(3, list[g].second));
      ASSERT_EQ(headers[g].keyframes.size(), expected) << g;
      EXPECT_EQ(headers[g].keyframes.front(), 0) << g;
      EXPECT_EQ(headers[g].keyframes.back(), list[g].second - 1) << g;
    }
  }
}

TEST(GomListFile, AListOfEqualGomsCodesTheSameStreamAsGomSize) {
  test::TempDir dir("gom-list-equal");
  const std::vector<Mesh> frames = test::wobblingSphere(1, 12);
  test::writeText(dir.file("goms.txt"), "0 5\n5 5\n10 2\n");
  EncoderParams fixed;
  fixed.gridBits = 10;
  fixed.gomSize = 5;
  EncoderParams listed = fixed;
  listed.gomSize = 16;
  listed.gomListFile = dir.file("goms.txt");
  EXPECT_EQ(test::encodeAndDecode(frames, listed).coded.stream,
            test::encodeAndDecode(frames, fixed).coded.stream);
}

TEST(GomListFile, TexturesHaveAnIdrPictureAtEveryGomStartAndNowhereElse) {
  test::TempDir dir("gom-list-texture");
  const std::string rig = std::string(TDVO_SOURCE_DIR) + "/conformance/inputs/rig";
  test::writeText(dir.file("goms.txt"), "0 1\n1 3\n4 2\n");
  const test::CommandResult enc =
      test::run(dir, std::string(TDVO_BIN_DIR) + "/3dvo-enc",
                {"--Dataset=" + rig, "--FrameCount=6", "--GOMListFile=goms.txt",
                 "--TexturePreset=fast", "--BitstreamFile=s.3dvo"});
  ASSERT_EQ(enc.exitCode, 0) << enc.err;
  test::writeText(dir.file("enc.log"), enc.out);
  const test::CommandResult dec = test::run(dir, std::string(TDVO_BIN_DIR) + "/3dvo-dec",
                                            {"-i", "s.3dvo", "--verify", "enc.log"});
  EXPECT_EQ(dec.exitCode, 0) << dec.out << dec.err;
  const std::vector<std::string> lines = test::linesStartingWith(enc.out, "MD5 ");
  EXPECT_EQ(lines.size(), 6u + 6u * 3u + 1u);  // geometry and 3 cameras per frame, the header
  EXPECT_EQ(test::linesStartingWith(dec.out, "MD5 "), lines);

  const std::vector<uint8_t> stream = test::readBytes(dir.file("s.3dvo"));
  const std::vector<GomHeader> headers = gomHeaders(stream);
  ASSERT_EQ(headers.size(), 3u);
  EXPECT_EQ(headers[1].gh_first_frame, 1u);
  EXPECT_EQ(headers[2].gh_first_frame, 4u);
  UnitReader reader(stream.data(), stream.size(), "s.3dvo");
  UnitView u;
  int pictures = 0;
  while (reader.next(u)) {
    if (u.type != static_cast<uint8_t>(UnitType::kTexture)) continue;
    ByteReader r(u.payload, u.size, u.describe(), u.payloadOffset);
    TextureUnit tx;
    transfer(r, tx);
    const bool gomStart = tx.tx_frame == 0 || tx.tx_frame == 1 || tx.tx_frame == 4;
    EXPECT_EQ(holdsIdrSlice(tx.tx_access_unit), gomStart)
        << "frame " << tx.tx_frame << " camera " << tx.tx_camera;
    ++pictures;
  }
  EXPECT_EQ(pictures, 6 * 3);
}

}  // namespace
}  // namespace tdvo
