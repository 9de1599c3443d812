// Texture coding end to end, through the apps: encoder and decoder agree on every texture
// picture, two encodes are byte-identical, the extracted H.264 decodes with the ffmpeg tool to
// the same pictures, the decoder writes a dataset, and bad camera input gives clear errors.
#include <gtest/gtest.h>

#include <filesystem>

#include "common/dataset.h"
#include "common/image.h"
#include "common/md5.h"
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
  // Too few dataset frames for FrameCount is an error also with a pattern.
  const auto c =
      encode({"--InputMeshPattern=" + kRig + "/meshes/%04d.obj", "--FirstFrame=1"}, "c.3dvo");
  EXPECT_EQ(c.exitCode, 1);
  EXPECT_NE(c.err.find("but the dataset has 6 frames"), std::string::npos) << c.err;
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

}  // namespace
}  // namespace tdvo
