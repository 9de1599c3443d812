// Texture coding end to end, through the apps: encoder and decoder agree on every texture
// picture, two encodes are byte-identical, the extracted H.264 decodes with the ffmpeg tool to
// the same pictures, the decoder writes a dataset, and bad camera input gives clear errors.
#include <gtest/gtest.h>

#include <filesystem>

#include "common/core/gom_list.h"
#include "common/core/md5.h"
#include "common/media/dataset.h"
#include "common/media/png_io.h"
#include "common/views/image.h"
#include "test_support.h"

namespace tdvo {
namespace {

namespace fs = std::filesystem;

const std::string kBin = TDVO_BIN_DIR;
const std::string kRig = std::string(TDVO_SOURCE_DIR) + "/conformance/inputs/rig";

std::vector<std::string> textureLines(const std::string& log) {
  std::vector<std::string> out;
  for (const std::string& line : test::linesStartingWith(log, "MD5 "))
    if (line.find(" texture ") != std::string::npos) out.push_back(line);
  return out;
}

class TextureApps : public ::testing::Test {
 protected:
  test::TempDir dir{"texture"};
  test::CommandResult encode(const std::vector<std::string>& extra, const std::string& out) {
    std::vector<std::string> args = {"--Dataset=" + kRig, "--FrameCount=6", "--GOMSize=3",
                                     "--TexturePreset=fast", "--BitstreamFile=" + out};
    args.insert(args.end(), extra.begin(), extra.end());
    return test::run(dir, kBin + "/3dvo-enc", args);
  }
};

TEST_F(TextureApps, EncoderAndDecoderAgreeAndEncodingIsDeterministic) {
  for (const std::string padding : {"none", "mb128", "extrapolate"}) {
    const auto a = encode({"--TexturePadding=" + padding}, "a.3dvo");
    ASSERT_EQ(a.exitCode, 0) << a.err;
    const auto b = encode({"--TexturePadding=" + padding}, "b.3dvo");
    ASSERT_EQ(b.exitCode, 0) << b.err;
    EXPECT_EQ(test::readBytes(dir.file("a.3dvo")), test::readBytes(dir.file("b.3dvo")))
        << padding << ": two encodes differ";
    const std::vector<std::string> encoded = textureLines(a.out);
    EXPECT_EQ(encoded.size(), 6u * 3u);  // 6 frames x 3 cameras
    const auto d = test::run(dir, kBin + "/3dvo-dec", {"-i", "a.3dvo", "-o", "out", "--Overwrite"});
    ASSERT_EQ(d.exitCode, 0) << d.err;
    EXPECT_EQ(textureLines(d.out), encoded) << padding;
    EXPECT_EQ(test::linesStartingWith(d.out, "MD5 "), test::linesStartingWith(a.out, "MD5 "));
  }
  // The decoded folder is a dataset: cameras, RGBA frames with the shape as alpha, meshes.
  const Dataset decoded = readDataset(dir.file("out"));
  ASSERT_EQ(decoded.cameras.size(), 3u);
  EXPECT_EQ(decoded.frameCount, 6);
  EXPECT_NO_THROW(validateDatasetFiles(decoded));
  const Image frame = readPng(decoded.framePath(decoded.cameras[1].images, 2));
  ASSERT_EQ(frame.channels, 4);
  int opaque = 0;
  for (int y = 0; y < frame.height; ++y)
    for (int x = 0; x < frame.width; ++x)
      opaque += frame.at(x, y, 3) == 255;
  EXPECT_GT(opaque, 100);
}

// InputMeshPattern replaces the dataset's meshes as the geometry, also for the texture boxes:
// named as the dataset's own meshes, it gives the same stream (and boxes that see the object,
// not the one-macroblock fallback of a camera that never sees it).
TEST_F(TextureApps, InputMeshPatternGivesTheTextureBoxesTheirFrames) {
  const auto a = encode({"--TexturePadding=mb128"}, "a.3dvo");
  ASSERT_EQ(a.exitCode, 0) << a.err;
  const auto b = encode(
      {"--TexturePadding=mb128", "--InputMeshPattern=" + kRig + "/meshes/%04d.obj"}, "b.3dvo");
  ASSERT_EQ(b.exitCode, 0) << b.err;
  EXPECT_EQ(test::readBytes(dir.file("a.3dvo")), test::readBytes(dir.file("b.3dvo")));
  EXPECT_EQ(test::linesStartingWith(b.out, "MD5 "), test::linesStartingWith(a.out, "MD5 "));
  // A geometry frame without a dataset frame is an error also with a pattern, naming both.
  const auto c =
      encode({"--InputMeshPattern=" + kRig + "/meshes/%04d.obj", "--FirstFrame=1"}, "c.3dvo");
  EXPECT_EQ(c.exitCode, 1);
  EXPECT_NE(c.err.find("meshes/0006.obj: geometry frame 6 has no texture frame in " + kRig +
                       "/dataset.json (its frames are 0 .. 5"),
            std::string::npos)
      << c.err;
  EXPECT_FALSE(fs::exists(dir.file("c.3dvo")));
}
TEST_F(TextureApps, ExtractedAnnexBDecodesWithTheFfmpegToolToTheSamePictures) {
  if (std::system("ffmpeg -version > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "the ffmpeg command-line tool is not installed";
  const auto e = encode({}, "s.3dvo");
  ASSERT_EQ(e.exitCode, 0) << e.err;
  const auto d = test::run(dir, kBin + "/3dvo-dec", {"-i", "s.3dvo", "--extract-textures", "h264"});
  ASSERT_EQ(d.exitCode, 0) << d.err;
  for (int camera = 0; camera < 3; ++camera) {
    const std::string raw = dir.file("cam" + std::to_string(camera) + ".yuv");
    const std::string command = "ffmpeg -v error -y -i " +
                                dir.file("h264/cam" + std::to_string(camera) + ".264") +
                                " -f rawvideo -pix_fmt yuv420p " + raw;
    ASSERT_EQ(std::system(command.c_str()), 0);
    const std::vector<uint8_t> bytes = test::readBytes(raw);
    std::vector<std::string> expected;
    for (const std::string& line : textureLines(e.out))
      if (line.find(" cam=" + std::to_string(camera) + " ") != std::string::npos)
        expected.push_back(line.substr(line.rfind(' ') + 1));
    ASSERT_EQ(expected.size(), 6u);
    ASSERT_EQ(bytes.size() % 6, 0u);
    const size_t size = bytes.size() / 6;
    for (size_t f = 0; f < 6; ++f) {
      Md5 md5;
      md5.update(bytes.data() + f * size, size);
      EXPECT_EQ(toHex(md5.finish()), expected[f]) << "camera " << camera << " frame " << f;
    }
  }
}

// A copy of the rig dataset that a test may damage.
std::string copyRig(const test::TempDir& dir) {
  const std::string copy = dir.file("rig");
  fs::copy(kRig, copy, fs::copy_options::recursive);
  return copy;
}

TEST_F(TextureApps, BadCameraInputGivesOneClearError) {
  const std::string rig = copyRig(dir);
  struct Case {
    std::string what, expected;
    std::function<void()> damage;
  };
  const std::vector<Case> cases = {
      {"missing frame", "cam01/0004.png", [&] { fs::remove(rig + "/cam01/0004.png"); }},
      {"size mismatch", "cam02/0001.png",
       [&] { writePng(rig + "/cam02/0001.png", Image(64, 48, 3, 10)); }},
      {"unreadable image", "cam00/0003.png",
       [&] { test::writeText(rig + "/cam00/0003.png", "not a png"); }},
  };
  for (const Case& c : cases) {
    fs::remove_all(rig);
    copyRig(dir);
    c.damage();
    fs::remove(dir.file("x.3dvo"));
    const auto r = test::run(dir, kBin + "/3dvo-enc",
                             {"--Dataset=" + rig, "--FrameCount=6", "--BitstreamFile=x.3dvo"});
    EXPECT_EQ(r.exitCode, 1) << c.what;
    EXPECT_EQ(r.err.rfind("3dvo-enc: error: ", 0), 0u) << c.what << ": " << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << c.what << ": " << r.err;
    EXPECT_EQ(test::lines(r.err).size(), 1u) << c.what << ": " << r.err;
    EXPECT_FALSE(fs::exists(dir.file("x.3dvo"))) << c.what;
  }
  // An unreadable video instead of the image sequence.
  fs::remove_all(rig);
  copyRig(dir);
  Dataset d = readDataset(rig);
  d.cameras[0].images.clear();
  d.cameras[0].video = "broken.avi";
  test::writeText(rig + "/broken.avi", "this is not a video");
  writeDataset(d, rig);
  const auto r = test::run(dir, kBin + "/3dvo-enc",
                           {"--Dataset=" + rig, "--FrameCount=6", "--BitstreamFile=x.3dvo"});
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("broken.avi"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir.file("x.3dvo")));
}

// Issue 17.3: every field of the input dataset.json comes back, except what the stream changes
// by design: the file names (decoded meshes and RGBA images whose alpha is the shape, so no
// masks, no backgrounds and no videos) and the texture boxes, which are added.
TEST_F(TextureApps, DecodedDatasetIsTheInputDatasetWithTheDecodedFiles) {
  const std::string rig = copyRig(dir);
  Dataset input = readDataset(rig);
  input.description = "a \"quoted\" description, caf\xC3\xA9";
  input.cameras[1].camera.name = "left camera";
  input.up = Vec3d{0.0, 0.0, -1.0};
  input.frameRate = 29.97;  // FrameRate not set: the dataset's
  writeDataset(input, rig);
  input = readDataset(rig);
  const auto e = encode({"--Dataset=" + rig, "--FrameCount=4", "--FirstFrame=1"}, "s.3dvo");
  ASSERT_EQ(e.exitCode, 0) << e.err;
  const auto d = test::run(dir, kBin + "/3dvo-dec", {"-i", "s.3dvo", "-o", "out"});
  ASSERT_EQ(d.exitCode, 0) << d.err;
  const Dataset decoded = readDataset(dir.file("out"));
  EXPECT_NO_THROW(validateDatasetFiles(decoded));

  Dataset expected = input;
  expected.folder = dir.file("out");
  expected.firstFrame = 1;  // the coded frames: 1 .. 4
  expected.frameCount = 4;
  expected.meshes = "%04d.obj";
  ASSERT_EQ(decoded.cameras.size(), expected.cameras.size());
  for (size_t c = 0; c < expected.cameras.size(); ++c) {
    DatasetCamera& dc = expected.cameras[c];
    dc.images = "cam" + std::to_string(c) + "/%04d.png";
    dc.masks.clear();
    dc.background.clear();
    dc.alphaMask = true;
    ASSERT_TRUE(decoded.cameras[c].textureBox.has_value()) << c;
    dc.textureBox = decoded.cameras[c].textureBox;
    const std::array<int, 4> box = *dc.textureBox;
    EXPECT_EQ(box[0] % 16 + box[1] % 16 + box[2] % 16 + box[3] % 16, 0) << c;
  }
  EXPECT_EQ(test::readText(dir.file("out/dataset.json")), formatDataset(expected, dir.file("out")));
  EXPECT_EQ(decoded.cameras[1].camera.name, "left camera");
  EXPECT_EQ(decoded.description, input.description);
  // The decoded files carry the input's frame numbers, as the dataset says.
  EXPECT_TRUE(fs::exists(dir.file("out/0001.obj")));
  EXPECT_TRUE(fs::exists(dir.file("out/cam2/0004.png")));
  EXPECT_FALSE(fs::exists(dir.file("out/0000.obj")));
}

// Tools that read decoded folders follow the frame numbers: a stream coded from frame 1 (GOMs
// at frames 1 and 3) decodes to gom_starts.txt listing frames 1 and 3, and 3dvo-render renders
// each of the decoded frames 1 .. 4 from a camera's pose.
TEST_F(TextureApps, DecodedGomStartsAndFramesKeepTheFrameNumbers) {
  const auto e = encode({"--FirstFrame=1", "--FrameCount=4", "--GOMSize=2"}, "s.3dvo");
  ASSERT_EQ(e.exitCode, 0) << e.err;
  ASSERT_EQ(test::run(dir, kBin + "/3dvo-dec", {"-i", "s.3dvo", "-o", "out"}).exitCode, 0);
  EXPECT_EQ(readGomStarts(dir.file("out/gom_starts.txt")), (std::vector<int>{1, 3}));
  const Dataset decoded = readDataset(dir.file("out"));
  const auto r = test::run(
      dir, kBin + "/3dvo-render",
      {"-i", "out", "--Path=camera", "--Camera=" + decoded.cameras[0].camera.name, "-o", "views"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(test::listFolder(dir.path() / "views"),
            (std::vector<std::string>{"0000.png", "0001.png", "0002.png", "0003.png"}));
}

// Issue 17.8: a decoder frame range with textures starts at the GOM's IDR pictures (GOMs at
// 0, 2, 4: frames 3 .. 4 decode from the GOM at 2) and gives the encoder's pictures.
TEST_F(TextureApps, DecoderFrameRangeDecodesTexturesFromTheGomStart) {
  const auto e = encode({"--GOMSize=2"}, "s.3dvo");
  ASSERT_EQ(e.exitCode, 0) << e.err;
  test::writeText(dir.file("enc.log"), e.out);
  const auto d = test::run(dir, kBin + "/3dvo-dec",
                           {"-i", "s.3dvo", "-o", "out", "--FirstFrame=3", "--FrameCount=2",
                            "--verify", "enc.log", "--Threads=2"});
  ASSERT_EQ(d.exitCode, 0) << d.err;
  EXPECT_EQ(textureLines(d.out).size(), 2u * 3u);
  EXPECT_TRUE(fs::exists(dir.file("out/cam2/0004.png")));
  EXPECT_FALSE(fs::exists(dir.file("out/cam2/0002.png")));
  const Dataset decoded = readDataset(dir.file("out"));
  EXPECT_EQ(decoded.firstFrame, 3);
  EXPECT_EQ(decoded.frameCount, 2);
  EXPECT_NO_THROW(validateDatasetFiles(decoded));
}

// Issue 17.5: geometry and texture frames are tied by frame number. A dataset holding the rig's
// frames 2 .. 4 under their own numbers (frames.first 2, the same files) codes to the same stream
// as the rig's frames 2 .. 4 picked by FirstFrame, and with no FirstFrame or FrameCount it
// starts at its first frame and takes all three.
TEST_F(TextureApps, GeometryAndTexturesAreTiedByFrameNumber) {
  const std::string part = copyRig(dir);
  std::string json = test::readText(part + "/dataset.json");
  const std::string frames = "\"frames\": {\"first\": 0, \"count\": 6";
  ASSERT_NE(json.find(frames), std::string::npos);
  json.replace(json.find(frames), frames.size(), "\"frames\": {\"first\": 2, \"count\": 3");
  test::writeText(part + "/dataset.json", json);
  const auto whole = test::run(dir, kBin + "/3dvo-enc",
                               {"--Dataset=" + kRig, "--FirstFrame=2", "--FrameCount=3",
                                "--GOMSize=3", "--TexturePreset=fast", "-o", "whole.3dvo"});
  ASSERT_EQ(whole.exitCode, 0) << whole.err;
  const auto numbered =
      test::run(dir, kBin + "/3dvo-enc",
                {"--Dataset=" + part, "--GOMSize=3", "--TexturePreset=fast", "-o", "part.3dvo"});
  ASSERT_EQ(numbered.exitCode, 0) << numbered.err;
  EXPECT_EQ(test::readBytes(dir.file("part.3dvo")), test::readBytes(dir.file("whole.3dvo")));
  EXPECT_EQ(test::linesStartingWith(numbered.out, "MD5 "),
            test::linesStartingWith(whole.out, "MD5 "));
  EXPECT_EQ(test::linesStartingWith(numbered.out, "MD5 ").front().rfind("MD5 frame=2 ", 0), 0u);
  // A geometry frame outside the dataset's frames is an error naming both.
  const auto outside =
      test::run(dir, kBin + "/3dvo-enc",
                {"--Dataset=" + part, "--FirstFrame=0", "--FrameCount=3",
                 "--InputMeshPattern=" + kRig + "/meshes/%04d.obj", "-o", "x.3dvo"});
  EXPECT_EQ(outside.exitCode, 1);
  EXPECT_NE(outside.err.find("meshes/0000.obj: geometry frame 0 has no texture frame in " + part +
                             "/dataset.json (its frames are 2 .. 4"),
            std::string::npos)
      << outside.err;
  EXPECT_FALSE(fs::exists(dir.file("x.3dvo")));
}

// Issue 17.5, as a user met it: 3dvo-recon from frame 2, then its encode.cfg with the dataset.
// The reconstruction's files and encode.cfg carry the dataset's frame numbers, so the encoder
// codes the camera images of frame 2 with the geometry of frame 2.
TEST_F(TextureApps, ReconstructionFromALaterFrameEncodesWithItsOwnTextures) {
  const auto recon = test::run(dir, kBin + "/3dvo-recon",
                               {"-i", kRig, "--FirstFrame=2", "--FrameCount=1", "-o", "rec"});
  ASSERT_EQ(recon.exitCode, 0) << recon.err;
  EXPECT_TRUE(fs::exists(dir.file("rec/0002.obj")));
  EXPECT_NE(test::readText(dir.file("rec/encode.cfg")).find("FirstFrame       : 2\n"),
            std::string::npos);
  const auto e = test::run(dir, kBin + "/3dvo-enc",
                           {"-c", dir.file("rec/encode.cfg"), "--Dataset=" + kRig,
                            "--TexturePreset=fast", "-o", "r.3dvo"});
  ASSERT_EQ(e.exitCode, 0) << e.err;
  const std::vector<std::string> lines = textureLines(e.out);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0].rfind("MD5 frame=2 texture cam=0 ", 0), 0u) << lines[0];
}

}  // namespace
}  // namespace tdvo
