// The real apps (3dvo-enc, 3dvo-dec in TDVO_BIN_DIR) run as child processes in a temporary
// folder: encode → decode of a generated OBJ sequence, --verify, --help, and bad input of every
// kind, each of which must give exit code 1, exactly one "<app>: error: ..." line on stderr that
// names the file and line (or the stream unit), and no output file.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/sysmacros.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "bitstream/header_hash.h"
#include "common/core/gom_list.h"
#include "common/core/grid.h"
#include "common/core/md5.h"
#include "common/core/mesh_io.h"
#include "common/core/obj_io.h"
#include "encoder/sequence_encoder.h"
#include "tests/test_support.h"

namespace tdvo {
namespace {

using test::CommandResult;
using test::TempDir;

const std::string kEncoder = std::string(TDVO_BIN_DIR) + "/3dvo-enc";
const std::string kDecoder = std::string(TDVO_BIN_DIR) + "/3dvo-dec";
const std::string kBin = TDVO_BIN_DIR;

// A folder holding a generated sequence as OBJ files in/001.obj ... (first frame 1).
class AppsTest : public testing::Test {
 protected:
  static constexpr int kFrames = 6;

  void SetUp() override {
    frames_ = test::wobblingSphere(2, kFrames, 1.5, {0, 2, -1});  // 162 vertices
    std::filesystem::create_directories(dir_.path() / "in");
    for (int f = 0; f < kFrames; ++f)
      writeObj(inputPath(f + 1), frames_[f]);
  }

  std::string inputPath(int number) const {
    char name[32];
    std::snprintf(name, sizeof name, "in/%03d.obj", number);
    return dir_.file(name);
  }

  // Encoder arguments for the generated sequence; `extra` come last (and win). Intra coding by
  // default, so that the app plumbing is tested apart from the P-mesh coder; the tests that
  // need P meshes ask for them.
  std::vector<std::string> encoderArgs(std::vector<std::string> extra = {}) const {
    std::vector<std::string> args = {"--InputMeshPattern=in/%03d.obj",
                                     "--FirstFrame=1",
                                     "--FrameCount=" + std::to_string(kFrames),
                                     "--GridBits=11",
                                     "--PMeshMode=intra",
                                     "-o",
                                     "seq.3dvo"};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  }

  CommandResult encode(std::vector<std::string> extra = {}) const {
    return test::run(dir_, kEncoder, encoderArgs(std::move(extra)));
  }
  CommandResult decode(std::vector<std::string> args) const {
    return test::run(dir_, kDecoder, args);
  }

  // Every file and folder under the temporary folder, as relative paths.
  std::vector<std::string> tree() const {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(dir_.path()))
      names.push_back(std::filesystem::relative(entry.path(), dir_.path()).string());
    std::sort(names.begin(), names.end());
    return names;
  }

  // Runs `program` and checks the standard failure: exit 1, one error line from the app
  // containing every `part`, and nothing new anywhere (no output, no staged or temporary file,
  // no output folder).
  CommandResult expectFailure(const std::string& program, const std::vector<std::string>& args,
                              const std::vector<std::string>& parts) const {
    const std::vector<std::string> before = tree();
    const CommandResult r = test::run(dir_, program, args);
    const std::string app = std::filesystem::path(program).filename().string();
    EXPECT_EQ(r.exitCode, 1) << r.err;
    const std::vector<std::string> errLines = test::lines(r.err);
    EXPECT_EQ(errLines.size(), 1u) << r.err;
    if (errLines.size() == 1) {
      EXPECT_EQ(errLines[0].rfind(app + ": error: ", 0), 0u) << errLines[0];
      for (const std::string& part : parts)
        EXPECT_NE(errLines[0].find(part), std::string::npos)
            << "'" << part << "' missing from: " << errLines[0];
    }
    EXPECT_EQ(tree(), before) << "something was left behind";
    return r;
  }

  // A correct stream seq.3dvo and the encoder's stdout.
  CommandResult encodeGood() const {
    CommandResult r = encode();
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err, "");
    return r;
  }

  TempDir dir_{"apps"};
  std::vector<Mesh> frames_;
};

TEST_F(AppsTest, EncodeDecodeMd5LinesMatch) {
  const CommandResult enc =
      test::run(dir_, kEncoder, encoderArgs({"--ReconMeshPattern=recon-%d.obj"}));
  ASSERT_EQ(enc.exitCode, 0) << enc.err;
  EXPECT_EQ(enc.err, "");
  const std::vector<std::string> encLines = test::linesStartingWith(enc.out, "MD5 ");
  ASSERT_EQ(encLines.size(), static_cast<size_t>(kFrames) + 1u);
  // The lines and files carry the input's frame numbers (1 .. 6), recorded in the stream.
  for (int f = 0; f < kFrames; ++f)
    EXPECT_EQ(encLines[f].rfind("MD5 frame=" + std::to_string(f + 1) + " geometry=", 0), 0u);
  EXPECT_EQ(encLines.back().rfind("MD5 header=", 0), 0u);  // after the frames
  EXPECT_NE(enc.out.find("frames              : 6 (frame numbers 1 .. 6)\n"), std::string::npos)
      << enc.out;

  const CommandResult dec = decode({"-i", "seq.3dvo", "-o", "out"});
  ASSERT_EQ(dec.exitCode, 0) << dec.err;
  EXPECT_EQ(dec.err, "");
  EXPECT_EQ(test::linesStartingWith(dec.out, "MD5 "), encLines);
  EXPECT_NE(dec.out.find("frames              : 6"), std::string::npos) << dec.out;

  // One OBJ per frame, identical to the encoder's reconstruction, and the MD5 lines are those
  // of the library's encoder on the same input.
  std::vector<std::string> expectedNames;
  for (int f = 0; f < kFrames; ++f) {
    char name[16];
    std::snprintf(name, sizeof name, "%04d.obj", f + 1);
    expectedNames.push_back(name);
  }
  expectedNames.push_back("gom_starts.txt");  // beside the frames: where each GOM starts
  EXPECT_EQ(test::listFolder(dir_.path() / "out"), expectedNames);
  std::vector<Mesh> input;
  for (int f = 0; f < kFrames; ++f)
    input.push_back(readObj(inputPath(f + 1)));
  EncoderParams params;
  params.gridBits = 11;
  params.gomSize = 16;
  params.pmeshMode = PMeshMode::kIntra;
  params.firstFrame = 1;  // as the apps' FirstFrame: the header records it
  const Grid grid = gridForSequence(input, 11);
  std::vector<std::string> libraryLines;
  const EncodedSequence library =
      encodeSequence(params, grid, input, {}, [&](int frame, const IntMesh& mesh) {
        libraryLines.push_back(geometryHashLine(frame + 1, mesh));
      });
  libraryLines.push_back(sequenceHeaderHashLine(library.stream, "library"));
  EXPECT_EQ(libraryLines, encLines);
  for (int f = 0; f < kFrames; ++f) {
    const std::string decoded = test::readText(dir_.file("out/" + expectedNames[f]));
    EXPECT_EQ(decoded, test::readText(dir_.file("recon-" + std::to_string(f + 1) + ".obj")));
    // Decoded vertices are grid points: quantising them again changes nothing.
    const Mesh m = parseObj(decoded, expectedNames[f]);
    EXPECT_EQ(m.positions.size(), frames_[f].positions.size());
    EXPECT_EQ(m.triangles.size(), frames_[f].triangles.size());
    EXPECT_EQ(formatObj(grid.dequantise(grid.quantise(m))), decoded);
  }
  // Nothing else was written.
  std::vector<std::string> expectedTop = {"in", "out", "seq.3dvo"};
  for (int f = 0; f < kFrames; ++f)
    expectedTop.push_back("recon-" + std::to_string(f + 1) + ".obj");
  std::sort(expectedTop.begin(), expectedTop.end());
  EXPECT_EQ(test::listFolder(dir_.path()), expectedTop);
}

// The effective configuration 3dvo-enc prints, read back as a cfg file, gives the same run:
// the keys Quality chooses stay unset (printed as comments), so it chooses them again, rather
// than GridBits 12 and MotionQuantStep 1 being read as coding by hand.
TEST_F(AppsTest, TheEffectiveConfigurationReproducesTheRun) {
  const CommandResult first = test::run(
      dir_, kEncoder, {"--InputMeshPattern=in/%03d.obj", "--FirstFrame=1", "-o", "a.3dvo"});
  ASSERT_EQ(first.exitCode, 0) << first.err;
  // The block: from its title line to the first empty line ("" when there is none).
  const auto blockOf = [](const std::string& out) {
    const std::string title = "# 3dvo-enc effective configuration\n";
    const size_t from = out.find(title);
    const size_t to = out.find("\n\n", from);
    return from == std::string::npos || to == std::string::npos
               ? std::string()
               : out.substr(from + title.size(), to + 1 - from - title.size());
  };
  const std::string block = blockOf(first.out);
  ASSERT_FALSE(block.empty()) << first.out;
  EXPECT_NE(block.find("\n# GridBits                 : 12  (not set: chosen by Quality"),
            std::string::npos)
      << block;
  EXPECT_NE(block.find("\nFirstFrame               : 1\n"), std::string::npos) << block;
  test::writeText(dir_.file("effective.cfg"), block);
  const CommandResult second = test::run(dir_, kEncoder, {"-c", "effective.cfg", "-o", "b.3dvo"});
  ASSERT_EQ(second.exitCode, 0) << second.err;
  const auto qualityLine = [](const std::string& out) {
    return test::linesStartingWith(out, "quality ");
  };
  ASSERT_EQ(qualityLine(first.out).size(), 1u) << first.out;
  EXPECT_EQ(qualityLine(second.out), qualityLine(first.out));
  EXPECT_EQ(test::readBytes(dir_.file("b.3dvo")), test::readBytes(dir_.file("a.3dvo")));
  // The default Quality codes B meshes; the summary says so, with the step it derived from the
  // quantiser Quality chose (2 x MotionQuantStep), not from the keys' defaults.
  const std::vector<std::string> quality = test::linesStartingWith(first.out, "quality ");
  ASSERT_EQ(quality.size(), 1u) << first.out;
  const size_t at = quality[0].find("MotionQuantStep ");
  ASSERT_NE(at, std::string::npos) << quality[0];
  const int step = std::stoi(quality[0].substr(at + 16));
  const std::vector<std::string> keyframes = test::linesStartingWith(first.out, "keyframes ");
  ASSERT_EQ(keyframes.size(), 1u) << first.out;
  EXPECT_NE(keyframes[0].find("the others are B meshes (BMeshGap 8, BMeshQuantStep " +
                              std::to_string(2 * step) + ", BMeshLambdaGrowth 2)"),
            std::string::npos)
      << keyframes[0];
  // The summary gives the frame rate used, exactly (FrameRate is printed only when set).
  EXPECT_EQ(test::linesStartingWith(first.out, "frame rate "),
            std::vector<std::string>{"frame rate          : 25"});
  const CommandResult ntsc = encode({"--FrameRate=29.97002997002997"});
  EXPECT_EQ(test::linesStartingWith(ntsc.out, "frame rate "),
            std::vector<std::string>{"frame rate          : 29.97002997002997"});
  // Without B meshes (coding by hand) the B-mesh keys stay unset too: set, they would be an
  // error (C55). The growth is printed as given, every digit.
  const CommandResult byHand = test::run(
      dir_, kEncoder,
      {"--InputMeshPattern=in/%03d.obj", "--FirstFrame=1", "--Quality=-1", "-o", "c.3dvo"});
  ASSERT_EQ(byHand.exitCode, 0) << byHand.err;
  test::writeText(dir_.file("by-hand.cfg"), blockOf(byHand.out));
  const CommandResult again = test::run(dir_, kEncoder, {"-c", "by-hand.cfg", "-o", "d.3dvo"});
  ASSERT_EQ(again.exitCode, 0) << again.err;
  EXPECT_EQ(test::readBytes(dir_.file("d.3dvo")), test::readBytes(dir_.file("c.3dvo")));
  const CommandResult growth = test::run(dir_, kEncoder,
                                         {"--InputMeshPattern=in/%03d.obj", "--FirstFrame=1",
                                          "--BMeshLambdaGrowth=1.23456789", "-o", "e.3dvo"});
  ASSERT_EQ(growth.exitCode, 0) << growth.err;
  EXPECT_NE(growth.out.find(", BMeshLambdaGrowth 1.23456789)"), std::string::npos) << growth.out;
  EXPECT_NE(blockOf(growth.out).find("\nBMeshLambdaGrowth        : 1.23456789\n"),
            std::string::npos)
      << growth.out;
}

TEST_F(AppsTest, PMeshesAndGzipInput) {
  for (int f = 0; f < kFrames; ++f) {
    test::writeGz(inputPath(f + 1) + ".gz", formatObj(frames_[f]));
    std::filesystem::remove(inputPath(f + 1));
  }
  const CommandResult enc =
      encode({"--InputMeshPattern=in/%03d.obj.gz", "--GOMSize=4", "--PMeshMode=d3dmc"});
  ASSERT_EQ(enc.exitCode, 0) << enc.err;
  const CommandResult dec = decode({"-i", "seq.3dvo"});
  ASSERT_EQ(dec.exitCode, 0) << dec.err;
  const std::vector<std::string> lines = test::linesStartingWith(enc.out, "MD5 ");
  EXPECT_EQ(lines.size(), static_cast<size_t>(kFrames) + 1u);  // and the header line
  EXPECT_EQ(test::linesStartingWith(dec.out, "MD5 "), lines);
}

TEST_F(AppsTest, VerifyPassesAndFailsOnAnEditedLog) {
  const CommandResult enc = encodeGood();
  test::writeText(dir_.file("enc.log"), enc.out);
  const CommandResult ok = decode({"-i", "seq.3dvo", "-o", "out", "--verify", "enc.log"});
  EXPECT_EQ(ok.exitCode, 0) << ok.err;
  EXPECT_NE(ok.out.find("verify              : all 6 frames match"), std::string::npos) << ok.out;
  EXPECT_EQ(test::listFolder(dir_.path() / "out").size(), static_cast<size_t>(kFrames) + 1u);
  std::filesystem::remove_all(dir_.path() / "out");

  // One hex digit of frame 3 changed.
  std::string edited = enc.out;
  const size_t at = edited.find("MD5 frame=4 geometry=");
  ASSERT_NE(at, std::string::npos);
  char& digit = edited[at + std::string("MD5 frame=4 geometry=").size() + 5];
  digit = digit == '0' ? '1' : '0';
  test::writeText(dir_.file("edited.log"), edited);
  expectFailure(kDecoder, {"-i", "seq.3dvo", "-o", "out", "--verify", "edited.log"},
                {"edited.log: line 4 of its MD5 lines differs: expected 'MD5 frame=4 geometry="});

  // A log with a frame missing.
  std::string shorter = enc.out;
  shorter.erase(shorter.find("MD5 frame=5"));
  test::writeText(dir_.file("short.log"), shorter);
  expectFailure(kDecoder, {"-i", "seq.3dvo", "-o", "out", "--verify", "short.log"},
                {"short.log: has no line for 'MD5 frame=5 geometry="});

  // A log with one frame too many.
  test::writeText(dir_.file("long.log"),
                  enc.out + "MD5 frame=7 geometry=00000000000000000000000000000000\n");
  expectFailure(kDecoder, {"-i", "seq.3dvo", "-o", "out", "--verify", "long.log"},
                {"long.log: has 8 MD5 lines, the stream gives 7"});
}

// Issue 17.2: the output carries the input's frame numbers (FirstFrame 1 here, recorded in the
// stream); RenumberFrames names the files from 0 and keeps the MD5 lines' numbers.
TEST_F(AppsTest, DecodedFilesCarryTheInputFrameNumbersUnlessRenumbered) {
  const CommandResult enc = encode({"--PMeshMode=d3dmc", "--GOMSize=4"});
  ASSERT_EQ(enc.exitCode, 0) << enc.err;
  const CommandResult dec = decode({"-i", "seq.3dvo", "-o", "out"});
  ASSERT_EQ(dec.exitCode, 0) << dec.err;
  EXPECT_EQ(test::listFolder(dir_.path() / "out"),
            (std::vector<std::string>{"0001.obj", "0002.obj", "0003.obj", "0004.obj", "0005.obj",
                                      "0006.obj", "gom_starts.txt"}));
  EXPECT_EQ(readGomStarts(dir_.file("out/gom_starts.txt")), (std::vector<int>{1, 5}));
  // The decoded files are read back by 3dvo-metrics with the input's numbers on both sides.
  const CommandResult metrics = test::run(
      dir_, std::string(TDVO_BIN_DIR) + "/3dvo-metrics",
      {"-r", "in/%03d.obj", "--ReferenceFirstFrame=1", "-t", "out/%04d.obj", "--TestFirstFrame=1",
       "--GroupStarts=out/gom_starts.txt", "--Correspondence=nearest"});
  EXPECT_EQ(metrics.exitCode, 0) << metrics.err;
  EXPECT_NE(metrics.out.find("frames"), std::string::npos);

  const CommandResult renumbered = decode({"-i", "seq.3dvo", "-o", "zero", "--RenumberFrames"});
  ASSERT_EQ(renumbered.exitCode, 0) << renumbered.err;
  EXPECT_EQ(test::listFolder(dir_.path() / "zero"),
            (std::vector<std::string>{"0000.obj", "0001.obj", "0002.obj", "0003.obj", "0004.obj",
                                      "0005.obj", "gom_starts.txt"}));
  EXPECT_EQ(readGomStarts(dir_.file("zero/gom_starts.txt")), (std::vector<int>{0, 4}));
  EXPECT_EQ(test::readText(dir_.file("zero/0000.obj")), test::readText(dir_.file("out/0001.obj")));
  EXPECT_EQ(test::linesStartingWith(renumbered.out, "MD5 "),
            test::linesStartingWith(enc.out, "MD5 "));
}

// Issue 17.4: without FrameCount the encoder codes every frame from FirstFrame until the first
// missing file and says how many it found; an explicit FrameCount past the files stays an error
// naming the missing file.
TEST_F(AppsTest, FrameCountDefaultsToEveryFrameUntilAFileIsMissing) {
  const CommandResult all = test::run(
      dir_, kEncoder,
      {"--InputMeshPattern=in/%03d.obj", "--FirstFrame=2", "--GridBits=11", "-o", "all.3dvo"});
  ASSERT_EQ(all.exitCode, 0) << all.err;
  EXPECT_NE(all.out.find("# input frames: 5 frames, 2 .. 6"), std::string::npos) << all.out;
  EXPECT_NE(all.out.find("in/007.obj, which does not exist"), std::string::npos) << all.out;
  EXPECT_NE(all.out.find("frames              : 5"), std::string::npos) << all.out;
  EXPECT_EQ(test::linesStartingWith(all.out, "MD5 frame=").size(), 5u);
  EXPECT_EQ(all.err.find("warning"), std::string::npos) << all.err;  // no file after the end
  expectFailure(kEncoder,
                {"--InputMeshPattern=in/%03d.obj", "--FirstFrame=2", "--FrameCount=6",
                 "--GridBits=11", "-o", "more.3dvo"},
                {"in/007.obj: cannot open"});
  // A gap in the numbering ends the frames too, and the files after it are named.
  std::filesystem::rename(inputPath(4), dir_.file("in/010.obj"));
  const CommandResult gap = test::run(
      dir_, kEncoder,
      {"--InputMeshPattern=in/%03d.obj", "--FirstFrame=2", "--GridBits=11", "-o", "gap.3dvo"});
  ASSERT_EQ(gap.exitCode, 0) << gap.err;
  EXPECT_NE(gap.out.find("# input frames: 2 frames, 2 .. 3"), std::string::npos) << gap.out;
  EXPECT_NE(gap.err.find("3dvo-enc: warning: in/005.obj exists, after in/004.obj, which does not "
                         "exist: the frames after that gap are not coded"),
            std::string::npos)
      << gap.err;
}

// Issue 17.8: a frame range, in input frame numbers: decoding starts at the GOM holding
// FirstFrame, only the range is output, and its lines are the encoder's for those frames.
TEST_F(AppsTest, DecoderFrameRangeStartsAtTheGomHoldingItsFirstFrame) {
  const CommandResult enc = encode({"--PMeshMode=d3dmc", "--GOMSize=2"});  // GOMs at 1, 3, 5
  ASSERT_EQ(enc.exitCode, 0) << enc.err;
  test::writeText(dir_.file("enc.log"), enc.out);
  const CommandResult dec = decode(
      {"-i", "seq.3dvo", "-o", "out", "--FirstFrame=4", "--FrameCount=2", "--verify", "enc.log"});
  ASSERT_EQ(dec.exitCode, 0) << dec.err;
  const std::vector<std::string> all = test::linesStartingWith(enc.out, "MD5 ");
  EXPECT_EQ(test::linesStartingWith(dec.out, "MD5 "),
            (std::vector<std::string>{all[3], all[4], all.back()}));  // frames 4, 5; header
  EXPECT_EQ(test::listFolder(dir_.path() / "out"),
            (std::vector<std::string>{"0004.obj", "0005.obj", "gom_starts.txt"}));
  EXPECT_EQ(readGomStarts(dir_.file("out/gom_starts.txt")), (std::vector<int>{5}));
  // The same frames as a whole decode gives, also renumbered; FrameCount 0 runs to the end.
  ASSERT_EQ(decode({"-i", "seq.3dvo", "-o", "whole"}).exitCode, 0);
  EXPECT_EQ(test::readText(dir_.file("out/0004.obj")), test::readText(dir_.file("whole/0004.obj")));
  const CommandResult tail =
      decode({"-i", "seq.3dvo", "-o", "tail", "--FirstFrame=6", "--RenumberFrames"});
  ASSERT_EQ(tail.exitCode, 0) << tail.err;
  EXPECT_EQ(test::listFolder(dir_.path() / "tail"),
            (std::vector<std::string>{"0000.obj", "gom_starts.txt"}));
  EXPECT_EQ(test::readText(dir_.file("tail/0000.obj")),
            test::readText(dir_.file("whole/0006.obj")));
  expectFailure(kDecoder, {"-i", "seq.3dvo", "--FirstFrame=0"},
                {"FirstFrame 0 is not in the stream (the stream's frames are 1 .. 6)"});
}

TEST_F(AppsTest, HelpListsTheKeys) {
  const CommandResult enc = test::run(dir_, kEncoder, {"--help"});
  EXPECT_EQ(enc.exitCode, 0);
  EXPECT_EQ(enc.err, "");
  for (const char* key : {"InputMeshPattern", "FirstFrame", "FrameCount", "FrameRate", "GridBits",
                          "GOMSize", "BitstreamFile", "ReconMeshPattern"})
    EXPECT_NE(enc.out.find(std::string("\n  ") + key + " "), std::string::npos) << key;
  EXPECT_NE(enc.out.find("default: not set (chosen by Quality unless Quality is -1; setting it "
                         "codes by hand; else 12)"),
            std::string::npos);  // GridBits
  const CommandResult dec = test::run(dir_, kDecoder, {"-h"});
  EXPECT_EQ(dec.exitCode, 0);
  EXPECT_EQ(dec.err, "");
  for (const char* key : {"BitstreamFile (-i)", "OutputDir (-o)", "VerifyMd5 (--verify)"})
    EXPECT_NE(dec.out.find(key), std::string::npos) << key;
  EXPECT_EQ(test::listFolder(dir_.path()), std::vector<std::string>{"in"});
}

// Every app answers --version with the 3DVO release and the libraries it links (exit 0, no
// other output, no file).
TEST_F(AppsTest, VersionOnEveryApp) {
  const std::vector<std::string> core = {
      "(3DVO ",           "zlib ", "libpng ", "FFmpeg libavcodec ", "FFmpeg libavformat ",
      "FFmpeg libavutil "};
  const std::vector<std::pair<std::string, std::vector<std::string>>> apps = {
      {"3dvo-enc", {"stream syntax version ", "Draco ", "x264 "}},
      {"3dvo-dec", {"stream syntax version ", "Draco "}},
      {"3dvo-metrics", {"stream syntax version "}},
      {"3dvo-recon", {"OpenMesh ", "OpenCV "}},
      {"3dvo-render", {}},
      {"3dvo-import", {}},
      {"3dvo-synth", {}},
      {"3dvo-sample", {}}};
  for (const auto& [app, own] : apps) {
    const CommandResult r = test::run(dir_, std::string(TDVO_BIN_DIR) + "/" + app, {"--version"});
    EXPECT_EQ(r.exitCode, 0) << app << ": " << r.err;
    EXPECT_EQ(r.err, "") << app;
    EXPECT_EQ(r.out.rfind(app + " (3DVO ", 0), 0u) << r.out;
    for (const std::vector<std::string>* list : {&core, &own})
      for (const std::string& line : *list)
        EXPECT_NE(r.out.find(line), std::string::npos) << app << " lacks '" << line << "':\n"
                                                       << r.out;
  }
  // 3dvo-rd (Python) names the release, Python and its packages, importing none of them.
  const CommandResult rd = test::run(dir_, std::string(TDVO_BIN_DIR) + "/3dvo-rd", {"--version"});
  EXPECT_EQ(rd.exitCode, 0) << rd.err;
  EXPECT_EQ(rd.out.rfind("3dvo-rd (3DVO ", 0), 0u) << rd.out;
  for (const char* line : {"Python ", "distributed", "numpy"})
    EXPECT_NE(rd.out.find(line), std::string::npos) << line << " missing in:\n" << rd.out;
  EXPECT_EQ(test::listFolder(dir_.path()), std::vector<std::string>{"in"});
}

// Real captures with degenerate triangles (thomas, frames 1..4 of tvmc-varying: 10 to 14 each)
// encode in intra mode, one warning per frame counting them, decode to the encoder's MD5 lines
// (--verify), and the decoded files have the input's triangle list, degenerate ones included.
TEST_F(AppsTest, RealMeshesWithDegenerateTrianglesEncode) {
  const std::string folder = std::string(TDVO_SHARED_DATA_DIR) + "/meshseq/tvmc-varying";
  if (!std::filesystem::exists(folder + "/thomas_fr0001.obj.gz"))
    GTEST_SKIP() << "../shared/data/meshseq/tvmc-varying is absent";
  const CommandResult enc =
      test::run(dir_, kEncoder,
                {"--InputMeshPattern=" + folder + "/thomas_fr%04d.obj.gz", "--FirstFrame=1",
                 "--FrameCount=4", "--PMeshMode=intra", "--GOMSize=1", "--BitstreamFile=t.3dvo"});
  ASSERT_EQ(enc.exitCode, 0) << enc.err;
  std::vector<std::string> warnings;
  for (const std::string& line : test::lines(enc.err))
    if (line.find("triangles have a repeated vertex (degenerate); kept") != std::string::npos)
      warnings.push_back(line);
  EXPECT_EQ(warnings.size(), 4u) << enc.err;
  std::string log;
  for (const std::string& line : test::linesStartingWith(enc.out, "MD5 "))
    log += line + "\n";
  test::writeText(dir_.file("t.md5"), log);
  const CommandResult dec =
      test::run(dir_, kDecoder, {"-i", "t.3dvo", "--verify", "t.md5", "-o", "out"});
  ASSERT_EQ(dec.exitCode, 0) << dec.err;
  for (int f = 1; f <= 4; ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "/thomas_fr%04d.obj.gz", f);
    const Mesh in = readObj(folder + name);
    std::snprintf(name, sizeof name, "out/%04d.obj", f);
    EXPECT_EQ(readObj(dir_.file(name)).triangles, in.triangles) << "frame " << f;
  }
}

// 3dvo-sample writes the format its pattern names (it wrote OBJ text into .ply and .glb files,
// which no reader took): the same frame in each format reads back to the same mesh.
TEST_F(AppsTest, SampleWritesTheFormatItsPatternNames) {
  Mesh reference;
  for (const char* extension : {"obj", "ply", "glb", "gltf"}) {
    const std::string folder = std::string("sample-") + extension;
    const test::CommandResult r = test::run(dir_, kBin + "/3dvo-sample",
                                            {"-o", folder, "--FrameCount=1", "--Subdivisions=1",
                                             std::string("--OutputMeshPattern=%04d.") + extension});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const Mesh m = readMesh(dir_.file(folder + "/0000." + extension));
    if (reference.positions.empty()) reference = m;
    ASSERT_EQ(m.positions.size(), reference.positions.size()) << extension;
    EXPECT_EQ(m.triangles, reference.triangles) << extension;
    for (size_t v = 0; v < m.positions.size(); ++v)
      for (int c = 0; c < 3; ++c)  // glTF holds float32
        EXPECT_NEAR(m.positions[v][c], reference.positions[v][c], 1e-6) << extension;
  }
}

// ---- Encoder: bad input ----

TEST_F(AppsTest, NoArguments) {
  expectFailure(kEncoder, {}, {"InputMeshPattern is not set"});
  expectFailure(kDecoder, {}, {"no stream given"});
  expectFailure(kEncoder, {"--NoSuchKey=1"}, {"unknown key 'NoSuchKey'"});
  expectFailure(kDecoder, {"stray"}, {"unknown argument 'stray'"});
}

TEST_F(AppsTest, MissingInputFile) {
  std::filesystem::remove(inputPath(4));
  expectFailure(kEncoder, encoderArgs(), {"in/004.obj", "cannot open"});
}

TEST_F(AppsTest, MalformedObjNamesTheLine) {
  std::string text = formatObj(frames_[2]);
  const size_t line7 = [&] {
    size_t pos = 0;
    for (int i = 0; i < 6; ++i)
      pos = text.find('\n', pos) + 1;
    return pos;
  }();
  text.insert(line7, "v 1 2 three\n");
  test::writeText(inputPath(3), text);
  expectFailure(kEncoder, encoderArgs(), {"in/003.obj:7: bad number 'three'"});
}

// A run that fails after readers warned: the warnings of the frames read, their closing count,
// then the error, last (runApp closes the warnings' scope before it says the error).
TEST_F(AppsTest, WarningCountsComeBeforeTheError) {
  for (int f = 0; f < kFrames; ++f)
    test::writeText(inputPath(f + 1), "mtllib skin.mtl\n" + formatObj(frames_[f]) +
                                          (f == kFrames - 1 ? "v 1 2 three\n" : ""));
  const CommandResult r = test::run(dir_, kEncoder, encoderArgs());
  EXPECT_EQ(r.exitCode, 1) << r.err;
  const std::vector<std::string> lines = test::lines(r.err);
  ASSERT_GE(lines.size(), 3u) << r.err;
  EXPECT_NE(lines[0].find("3dvo-enc: warning: in/001.obj:1: statements 3DVO does not code"),
            std::string::npos)
      << r.err;
  EXPECT_NE(lines[lines.size() - 2].find("the same in"), std::string::npos) << r.err;
  EXPECT_EQ(lines.back().rfind("3dvo-enc: error: ", 0), 0u) << r.err;
  EXPECT_NE(lines.back().find("in/006.obj:"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir_.file("seq.3dvo")));
}

TEST_F(AppsTest, VertexCountDiffersInsideAGom) {
  // The last frame (number 6) gets one more vertex, unreferenced, in front.
  Mesh shifted = frames_[5];
  shifted.positions.insert(shifted.positions.begin(), Vec3d{0, 0, 0});
  for (Triangle& t : shifted.triangles)
    for (uint32_t& v : t)
      ++v;
  writeObj(inputPath(6), shifted);
  // P meshes need the GOM's vertices: an error naming both frames.
  expectFailure(kEncoder, encoderArgs({"--PMeshMode=d3dmc", "--GOMSize=6"}),
                {"in/006.obj: 163 vertices, but the GOM's first frame (in/001.obj) has 162"});
  // Intra coding, or a GOM starting at that frame, takes it.
  const CommandResult intra = encode({"--PMeshMode=intra", "--GOMSize=6"});
  EXPECT_EQ(intra.exitCode, 0) << intra.err;
  const CommandResult split = encode({"--PMeshMode=d3dmc", "--GOMSize=5"});
  EXPECT_EQ(split.exitCode, 0) << split.err;
}

TEST_F(AppsTest, ConnectivityDiffersInsideAGom) {
  Mesh flipped = frames_[1];
  std::swap(flipped.triangles[10][1], flipped.triangles[10][2]);
  writeObj(inputPath(2), flipped);
  expectFailure(kEncoder, encoderArgs({"--PMeshMode=d3dmc", "--GOMSize=6"}),
                {"in/002.obj", "connectivity differs"});
}

TEST_F(AppsTest, EmptyMesh) {
  test::writeText(inputPath(2), "");
  expectFailure(kEncoder, encoderArgs(), {"in/002.obj: no vertices"});
  test::writeText(inputPath(2), "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  expectFailure(kEncoder, encoderArgs(), {"in/002.obj: no faces"});
}

TEST_F(AppsTest, OutOfRangeCfgValue) {
  test::writeText(dir_.file("bad.cfg"), "# grid\nGridBits : 30\n");
  expectFailure(kEncoder, encoderArgs({"-c", "bad.cfg"}),
                {"bad.cfg:2: GridBits: value 30 out of range [8, 20]"});
  expectFailure(kEncoder, encoderArgs({"--GOMSize=0"}),
                {"--GOMSize=0", "GOMSize: value 0 out of range"});
  expectFailure(kEncoder, encoderArgs({"--FrameRate=-3"}), {"FrameRate: value -3 out of range"});
}

TEST_F(AppsTest, UnknownCfgKey) {
  test::writeText(dir_.file("bad.cfg"), "GridBits : 10\n\nGridBitz : 10\n");
  expectFailure(kEncoder, encoderArgs({"-c", "bad.cfg"}), {"bad.cfg:3: unknown key 'GridBitz'"});
}

TEST_F(AppsTest, BadFramePattern) {
  expectFailure(kEncoder, encoderArgs({"--InputMeshPattern=in/frame.obj"}),
                {"InputMeshPattern", "in/frame.obj"});
}

TEST_F(AppsTest, UnwritableStreamLeavesNoReconstruction) {
  expectFailure(kEncoder,
                encoderArgs({"-o", "no-such-folder/seq.3dvo", "--ReconMeshPattern=recon-%d.obj"}),
                {"no-such-folder/seq.3dvo"});
}

// ---- Decoder: bad streams ----

TEST_F(AppsTest, MissingStream) {
  expectFailure(kDecoder, {"-i", "nothing.3dvo", "-o", "out"}, {"nothing.3dvo", "cannot open"});
}

TEST_F(AppsTest, NotA3dvoStream) {
  test::writeText(dir_.file("seq.3dvo"), test::readText(inputPath(1)));
  expectFailure(kDecoder, {"-i", "seq.3dvo", "-o", "out"}, {"seq.3dvo: not a 3DVO stream"});
}

TEST_F(AppsTest, TruncatedStream) {
  encodeGood();
  const std::vector<uint8_t> stream = test::readBytes(dir_.file("seq.3dvo"));
  for (size_t length : {size_t{0}, size_t{3}, size_t{10}, stream.size() / 2, stream.size() - 1}) {
    SCOPED_TRACE(length);
    test::writeBytes(dir_.file("cut.3dvo"),
                     std::vector<uint8_t>(stream.begin(), stream.begin() + length));
    const CommandResult r =
        expectFailure(kDecoder, {"-i", "cut.3dvo", "-o", "out"},
                      {"cut.3dvo: ", length < 4 ? "not a 3DVO stream" : "truncated"});
    if (length >= 10) {
      EXPECT_NE(r.err.find("unit "), std::string::npos) << r.err;
    }
    // The frames decoded before the cut were printed, but none was written.
    std::filesystem::remove(dir_.file("cut.3dvo"));
  }
}

TEST_F(AppsTest, FlippedByteNamesTheUnit) {
  encodeGood();
  const std::vector<uint8_t> stream = test::readBytes(dir_.file("seq.3dvo"));
  for (size_t position : {size_t{4}, size_t{9}, size_t{20}, stream.size() / 3, stream.size() / 2,
                          stream.size() - 1}) {
    SCOPED_TRACE(position);
    std::vector<uint8_t> bad = stream;
    bad[position] ^= 0x20;
    test::writeBytes(dir_.file("bad.3dvo"), bad);
    expectFailure(kDecoder, {"-i", "bad.3dvo", "-o", "out"}, {"bad.3dvo: unit "});
    std::filesystem::remove(dir_.file("bad.3dvo"));
  }
}

// ---- Output folders and files (docs/user-guide.md, "Output folders"; docs/robustness.md) ----

// Everything under `folder` (relative paths, hidden entries included), sorted.
std::vector<std::string> listTree(const std::filesystem::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder))
    names.push_back(std::filesystem::relative(entry.path(), folder).string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST_F(AppsTest, DecoderRefusesANonEmptyFolderAndOverwriteReplacesIt) {
  encodeGood();
  ASSERT_EQ(decode({"-i", "seq.3dvo", "-o", "out"}).exitCode, 0);
  const std::vector<std::string> decoded = listTree(dir_.path() / "out");
  // Files from another run: a frame this run does not write and a camera folder.
  std::filesystem::create_directories(dir_.path() / "out" / "cam3");
  test::writeText(dir_.file("out/0099.obj"), "another run");
  test::writeText(dir_.file("out/cam3/0000.png"), "another run");
  expectFailure(kDecoder, {"-i", "seq.3dvo", "-o", "out"},
                {"out: the output folder is not empty", "--Overwrite"});
  EXPECT_EQ(test::readText(dir_.file("out/0099.obj")), "another run");
  const CommandResult r = decode({"-i", "seq.3dvo", "-o", "out", "--Overwrite"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  // Exactly this run's output: nothing of the other run, nothing staged or set aside.
  EXPECT_EQ(listTree(dir_.path() / "out"), decoded);
}

TEST_F(AppsTest, DecoderOverwriteKeepsItsInputs) {
  encodeGood();
  std::filesystem::create_directories(dir_.path() / "out");
  std::filesystem::rename(dir_.file("seq.3dvo"), dir_.file("out/seq.3dvo"));
  expectFailure(kDecoder, {"-i", "out/seq.3dvo", "-o", "out", "--Overwrite"},
                {"--Overwrite would delete the input out/seq.3dvo"});
  EXPECT_TRUE(std::filesystem::exists(dir_.file("out/seq.3dvo")));
}

// A cfg file (3dvo-dec, 3dvo-sample) or an input frame (3dvo-synth) inside the output folder
// is an input --Overwrite keeps: the run is refused before it starts, the files stay.
TEST_F(AppsTest, OverwriteKeepsCfgFilesAndFramesInsideTheFolder) {
  encodeGood();
  std::filesystem::create_directories(dir_.path() / "o");
  test::writeText(dir_.file("o/dec.cfg"), "OutputDir : o\n");
  expectFailure(kDecoder, {"-c", "o/dec.cfg", "-i", "seq.3dvo", "--Overwrite"},
                {"o: --Overwrite would delete the input o/dec.cfg"});
  std::filesystem::create_directories(dir_.path() / "so");
  test::writeText(dir_.file("so/s.cfg"), "FrameCount : 2\n");
  expectFailure(kBin + "/3dvo-sample", {"-c", "so/s.cfg", "-o", "so", "--Overwrite"},
                {"so: --Overwrite would delete the input so/s.cfg"});
  ASSERT_EQ(test::run(dir_, kBin + "/3dvo-sample", {"-o", "smp", "--FrameCount=2"}).exitCode, 0);
  for (int f = 0; f < 2; ++f) {
    std::filesystem::create_directories(dir_.path() / ("m" + std::to_string(f)));
    std::filesystem::copy_file(dir_.file("smp/000" + std::to_string(f) + ".obj"),
                               dir_.file("m" + std::to_string(f) + "/f.obj"));
  }
  expectFailure(kBin + "/3dvo-synth",
                {"-o", "m1", "--InputMeshPattern=m%d/f.obj", "--FrameCount=2", "--Overwrite"},
                {"m1: --Overwrite would delete the input m1/f.obj"});
  for (const char* kept : {"o/dec.cfg", "so/s.cfg", "m1/f.obj"})
    EXPECT_TRUE(std::filesystem::exists(dir_.file(kept))) << kept;
}

TEST_F(AppsTest, FailedTexturedDecodeLeavesNoFolderTree) {
  // A textured stream cut inside its last GOM: frames and camera PNGs of the first GOMs were
  // decoded (and staged) before the error.
  const std::vector<uint8_t> stream = test::readBytes(
      std::string(TDVO_SOURCE_DIR) + "/conformance/streams/texture_bbox_mb128_g3.3dvo");
  test::writeBytes(dir_.file("cut.3dvo"),
                   std::vector<uint8_t>(stream.begin(), stream.begin() + stream.size() * 9 / 10));
  for (const char* out : {"out", "new/deeper/out"}) {
    SCOPED_TRACE(out);
    const CommandResult r = expectFailure(kDecoder, {"-i", "cut.3dvo", "-o", out}, {"cut.3dvo"});
    EXPECT_NE(r.out.find("MD5 frame=3 texture cam=0"), std::string::npos) << "decoded too little";
  }
}

TEST_F(AppsTest, EncoderRefusesToOverwriteItsInputs) {
  // Other spellings and links of an input are caught too: files are compared by identity.
  std::filesystem::create_symlink("in/003.obj", dir_.file("link.obj"));
  test::writeText(dir_.file("x.cfg"), "GridBits : 11\n");
  const std::string input = test::readText(inputPath(3));
  for (const std::vector<std::string>& extra :
       {std::vector<std::string>{"-o", "./in/../in/003.obj"},
        {"-o", "link.obj"},
        {"-c", "x.cfg", "-o", "x.cfg"},
        {"--ReconMeshPattern=in/%03d.obj"}}) {
    SCOPED_TRACE(extra.back());
    expectFailure(kEncoder, encoderArgs(extra), {"is the input", "refusing to overwrite it"});
  }
  EXPECT_EQ(test::readText(inputPath(3)), input);
  EXPECT_EQ(test::readText(dir_.file("x.cfg")), "GridBits : 11\n");
}

TEST_F(AppsTest, EncoderWritesIntoACharacterDeviceAndThroughASymlink) {
  // A private null device (what /dev/null is): written to, never replaced by a regular file.
  const std::string device = dir_.file("null");
  if (mknod(device.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0)
    GTEST_SKIP() << "cannot make a device node here";
  CommandResult r = encode({"-o", "null"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(std::filesystem::is_character_file(device));
  // Through a symbolic link: the link stays, its target gets the stream.
  std::filesystem::create_directories(dir_.path() / "streams");
  std::filesystem::create_symlink("streams/seq.3dvo", dir_.file("link.3dvo"));
  r = encode({"-o", "link.3dvo"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(std::filesystem::is_symlink(dir_.file("link.3dvo")));
  EXPECT_GT(std::filesystem::file_size(dir_.file("streams/seq.3dvo")), 100u);
}

TEST_F(AppsTest, ImportRefusesToOverwriteTheDatasetItReads) {
  CommandResult r = test::run(dir_, kBin + "/3dvo-synth",
                              {"-o", "rig", "--Cameras=2", "--FrameCount=1", "--Width=32",
                               "--Height=24", "--BlobSubdivisions=1"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::string json = test::readText(dir_.file("rig/dataset.json"));
  std::filesystem::create_symlink("rig", dir_.file("same"));
  expectFailure(kBin + "/3dvo-import", {"-i", "rig", "-o", "same", "--Up=0,0,1"},
                {"same/dataset.json: is the input rig/dataset.json (the same file)"});
  EXPECT_EQ(test::readText(dir_.file("rig/dataset.json")), json);
}

TEST_F(AppsTest, EveryFolderAppRefusesANonEmptyFolder) {
  // The same rule for every app that writes an output folder: refused when not empty, replaced
  // with --Overwrite, and afterwards the folder holds exactly the run's output.
  struct App {
    std::string name;
    std::vector<std::string> args;
  };
  const std::vector<App> apps = {
      {"3dvo-sample", {"-o", "sample", "--FrameCount=2", "--Subdivisions=1"}},
      {"3dvo-synth",
       {"-o", "rig", "--Cameras=2", "--FrameCount=2", "--Width=32", "--Height=24",
        "--BlobSubdivisions=1"}},
      {"3dvo-render", {"-i", "rig", "-o", "views", "--OrbitSteps=2", "--Width=24", "--Height=16"}},
      {"3dvo-render", {"-i", "rig", "-o", "held-out", "--Mode=leave-one-out", "--SaveRenders"}},
      {"3dvo-recon", {"--InputMeshPattern=rig/meshes/%04d.obj", "--FrameCount=2", "-o", "recon"}},
  };
  for (const App& app : apps) {
    SCOPED_TRACE(app.name + " " + app.args[1] + " " + app.args[3]);
    const std::string program = kBin + "/" + app.name;
    CommandResult r = test::run(dir_, program, app.args);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string folder =
        app.args[std::find(app.args.begin(), app.args.end(), "-o") - app.args.begin() + 1];
    const std::vector<std::string> written = listTree(dir_.path() / folder);
    test::writeText(dir_.file(folder + "/stray.txt"), "another run");
    expectFailure(program, app.args, {folder + ": the output folder is not empty"});
    std::vector<std::string> args = app.args;
    args.push_back("--Overwrite");
    r = test::run(dir_, program, args);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(listTree(dir_.path() / folder), written);
  }
}

}  // namespace
}  // namespace tdvo
