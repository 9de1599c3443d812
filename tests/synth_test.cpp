// The synthetic capture rig: exact masks, determinism, the app itself.
#include "common/media/png_io.h"
#include "tools/multiview/synth_rig.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/obj_io.h"
#include "common/core/sequence.h"
#include "common/views/rasteriser.h"
#include "tools/eval/sample_mesh.h"

using namespace tdvo;
namespace fs = std::filesystem;

namespace {

fs::path tempPath(const std::string& tag) {
  return fs::temp_directory_path() / ("tdvo_synth_" + tag + "_" + std::to_string(::getpid()));
}

// Every regular file under `root`, as relative paths, sorted.
std::vector<std::string> listFiles(const fs::path& root) {
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file()) files.push_back(fs::relative(e.path(), root).generic_string());
  std::sort(files.begin(), files.end());
  return files;
}

void expectIdenticalTrees(const fs::path& a, const fs::path& b) {
  const std::vector<std::string> fa = listFiles(a), fb = listFiles(b);
  ASSERT_EQ(fa, fb);
  for (const std::string& f : fa)
    EXPECT_TRUE(readFileBytes((a / f).string()) == readFileBytes((b / f).string()))
        << f << " differs between the two runs";
}

// The default rig, written once for all tests of this file.
class SynthDefault : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    folder_ = tempPath("default");
    fs::remove_all(folder_);
    SynthParams p;
    p.output = folder_.string();
    writeSyntheticDataset(p);
  }
  static void TearDownTestSuite() { fs::remove_all(folder_); }
  static fs::path folder_;
};
fs::path SynthDefault::folder_;

}  // namespace

TEST(Blob, IcosphereIsClosedAndOutwardFacing) {
  const Mesh m = icosphere(3);
  EXPECT_EQ(m.positions.size(), 642u);
  EXPECT_EQ(m.triangles.size(), 1280u);
  for (const Triangle& t : m.triangles) {
    const Vec3d n =
        cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
    EXPECT_GT(dot(n, m.positions[t[0]]), 0) << "triangle wound clockwise seen from outside";
  }
  // Closed: every directed edge appears once and its reverse once.
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (const Triangle& t : m.triangles)
    for (int k = 0; k < 3; ++k)
      ++edges[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, n] : edges) {
    EXPECT_EQ(n, 1);
    EXPECT_EQ(edges.count({e.second, e.first}), 1u);
  }
  // The blob deforms: frames differ, connectivity stays.
  const std::vector<Mesh> blob = deformingBlob(3, 10);
  EXPECT_EQ(blob[0].triangles, blob[5].triangles);
  EXPECT_EQ(blob[0].triangles, m.triangles);
  EXPECT_NE(blob[0].positions, blob[5].positions);
}

TEST_F(SynthDefault, WritesAValidDatasetOf8CamerasAt320x240) {
  const Dataset d = readDataset(folder_.string());
  EXPECT_EQ(d.cameras.size(), 8u);
  EXPECT_EQ(d.frameCount, 10);
  for (const DatasetCamera& dc : d.cameras) {
    EXPECT_EQ(dc.camera.width, 320);
    EXPECT_EQ(dc.camera.height, 240);
  }
  EXPECT_NO_THROW(validateDatasetFiles(d));
}

TEST_F(SynthDefault, MasksEqualTheRasterisedGroundTruth) {
  const Dataset d = readDataset(folder_.string());
  size_t objectPixels = 0, total = 0, differentFromBackground = 0;
  for (int f = 0; f < d.frameCount; ++f) {
    const Mesh mesh = readDatasetMesh(d, f);  // through the OBJ files and dataset.json
    for (size_t k = 0; k < d.cameras.size(); ++k) {
      CameraFrames frames(d, k);
      const Image mask = frames.mask(f);
      const Image expected = renderMask(mesh, d.cameras[k].camera);
      ASSERT_EQ(mask, expected) << "camera " << k << " frame " << f;
      // The object is seen in every view and the image shows it where the mask says.
      const Image image = frames.frame(f);
      const Image background = readPng(d.framePath(d.cameras[k].background, f));
      size_t inMask = 0;
      for (int y = 0; y < mask.height; ++y)
        for (int x = 0; x < mask.width; ++x) {
          bool differs = false;
          for (int c = 0; c < 3; ++c)
            differs = differs || image.at(x, y, c) != background.at(x, y, c);
          if (mask.at(x, y)) {
            ++inMask;
            differentFromBackground += differs;
          } else {
            EXPECT_FALSE(differs) << "object colour outside the mask at " << x << "," << y;
          }
        }
      EXPECT_GT(inMask, 320u * 240u / 10) << "object too small in camera " << k;
      EXPECT_LT(inMask, 320u * 240u * 9 / 10) << "object too large in camera " << k;
      objectPixels += inMask;
      total += mask.pixels.size();
    }
  }
  EXPECT_GT(differentFromBackground, objectPixels * 99 / 100);
  std::printf("default rig: object covers %.1f%% of the pixels over all views\n",
              100.0 * double(objectPixels) / double(total));
}

TEST_F(SynthDefault, SameInputsGiveByteIdenticalOutput) {
  const fs::path again = tempPath("again");
  fs::remove_all(again);
  SynthParams p;
  p.output = again.string();
  writeSyntheticDataset(p);
  expectIdenticalTrees(folder_, again);
  fs::remove_all(again);
}

TEST_F(SynthDefault, TheAppWritesTheSameDataset) {
  const fs::path app = fs::path(TDVO_BIN_DIR) / "3dvo-synth";
  ASSERT_TRUE(fs::exists(app)) << app << " not built";
  const fs::path out = tempPath("app");
  fs::remove_all(out);
  const std::string command = app.string() + " -o " + out.string() + " 2>/dev/null >/dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  expectIdenticalTrees(folder_, out);
  fs::remove_all(out);
  // Bad options are one clear error, exit code 1, and nothing written.
  const std::string bad = app.string() + " -o " + out.string() + " --Cameras=0 2>/dev/null";
  EXPECT_EQ(WEXITSTATUS(std::system(bad.c_str())), 1);
  EXPECT_FALSE(fs::exists(out / "dataset.json"));
}

TEST(Synth, NoiseIsSeededAndOptionsApply) {
  SynthParams p;
  p.frameCount = 2;
  p.cameras = 3;
  p.width = 64;
  p.height = 48;
  p.blobSubdivisions = 2;
  p.noiseSigma = 4;
  p.layout = RigLayout::dome;
  const fs::path a = tempPath("noiseA"), b = tempPath("noiseB"), c = tempPath("noiseC");
  for (const fs::path& f : {a, b, c})
    fs::remove_all(f);
  p.output = a.string();
  writeSyntheticDataset(p);
  p.output = b.string();
  writeSyntheticDataset(p);
  expectIdenticalTrees(a, b);
  p.seed = 2;
  p.output = c.string();
  writeSyntheticDataset(p);
  EXPECT_FALSE(readFileBytes((a / "cam01/0001.png").string()) ==
               readFileBytes((c / "cam01/0001.png").string()));
  // Masks do not depend on noise.
  EXPECT_TRUE(readFileBytes((a / "cam01/mask_0001.png").string()) ==
              readFileBytes((c / "cam01/mask_0001.png").string()));
  const Dataset d = readDataset(a.string());
  ASSERT_EQ(d.cameras.size(), 3u);
  EXPECT_EQ(d.cameras[0].camera.width, 64);
  // Dome cameras sit at different heights.
  const Vec3d up = *d.up;
  EXPECT_NE(dot(d.cameras[0].camera.centre(), up), dot(d.cameras[2].camera.centre(), up));
  for (const fs::path& f : {a, b, c})
    fs::remove_all(f);
}

TEST(Synth, InputMeshSequenceFromSharedData) {
  const std::string samba = std::string(TDVO_SHARED_DATA_DIR) + "/meshseq/samba/mesh_%04d.obj.gz";
  if (!fs::exists(std::string(TDVO_SHARED_DATA_DIR) + "/meshseq/samba/mesh_0000.obj.gz"))
    GTEST_SKIP() << "real data not found: " << samba << " (../shared/data absent)";
  SynthParams p;
  p.inputMeshPattern = samba;
  p.frameCount = 2;
  p.cameras = 4;
  p.width = 160;
  p.height = 120;
  const fs::path out = tempPath("samba");
  fs::remove_all(out);
  p.output = out.string();
  writeSyntheticDataset(p);
  const Dataset d = readDataset(out.string());
  for (int f = 0; f < 2; ++f) {
    const Mesh original = readObj(framePath(samba, f));
    const Mesh written = readDatasetMesh(d, f);
    EXPECT_EQ(written.positions, original.positions);
    for (size_t k = 0; k < d.cameras.size(); ++k)
      EXPECT_EQ(CameraFrames(d, k).mask(f), renderMask(original, d.cameras[k].camera));
  }
  fs::remove_all(out);
}

TEST(Synth, BadInputIsAClearError) {
  SynthParams p;
  p.output = tempPath("bad").string();
  p.inputMeshPattern = "/nonexistent/mesh_%04d.obj";
  EXPECT_THROW(writeSyntheticDataset(p), Error);
  p.inputMeshPattern = "";
  p.backgroundColour = "1,2";
  EXPECT_THROW(writeSyntheticDataset(p), Error);
  EXPECT_FALSE(fs::exists(fs::path(p.output) / "dataset.json"));
  fs::remove_all(p.output);
}
