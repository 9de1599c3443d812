// Reconstruction on the real data sets of ../shared/data (skipped when it is absent): the
// Middlebury dino (still, thresholded silhouettes), uu-4cam (video with background video, into
// GOMs that the codec encodes and decodes bit-exactly) and tvmc-varying (tracking meshes whose
// connectivity changes every frame into constant-connectivity GOMs).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "common/core/config.h"
#include "common/core/obj_io.h"
#include "common/core/sequence.h"
#include "common/media/dataset.h"
#include "common/views/rasteriser.h"
#include "tests/test_support.h"
#include "tools/eval/metrics.h"
#include "tools/multiview/importers.h"
#include "tools/recon/recon_params.h"
#include "tools/recon/recon_pipeline.h"
#include "tools/recon/silhouettes.h"

using namespace tdvo;
namespace fs = std::filesystem;

namespace {

const std::string kData = TDVO_SHARED_DATA_DIR;

#define REQUIRE_DATA(path)                                          \
  if (!fs::exists(kData + "/" + path))                              \
  GTEST_SKIP() << "shared data not found: " << kData << "/" << path \
               << " (tests on real data need ../shared/data beside the repository)"

// The parameters of a shipped cfg file (cfg/recon/NAME), then `overrides` (Key=value).
ReconParams paramsFromCfg(const std::string& name, const std::vector<std::string>& overrides) {
  ReconParams params;
  OptionTable table("recon_data_test", "");
  addReconOptions(table, params);
  // Paths in the shipped cfg files are relative to the repository root.
  {
    const test::WorkingDirectory cwd(TDVO_SOURCE_DIR);
    table.parseFile(std::string("cfg/recon/") + name);
  }
  if (!params.input.empty() && fs::path(params.input).is_relative())
    params.input = (fs::path(TDVO_SOURCE_DIR) / params.input).string();
  for (const std::string& o : overrides) {
    const size_t eq = o.find('=');
    table.set(o.substr(0, eq), o.substr(eq + 1), "test");
  }
  return params;
}

std::string app(const char* name) {
  return std::string(TDVO_BIN_DIR) + "/" + name;
}

}  // namespace

TEST(ReconDino, HullInsideTheBoundingBoxAndReprojectsOntoTheGoodViews) {
  REQUIRE_DATA("multiview/middlebury-dinoSparseRing");
  test::TempDir dir("recon-dino");
  ReconParams params = paramsFromCfg("dino.cfg", {"WriteHull=true"});
  params.output = dir.file("out");
  const ReconResult result = runReconstruction(params, stdout);
  ASSERT_EQ(result.frames.size(), 1u);
  ASSERT_EQ(result.cameras.size(), 15u);  // the README's good views: all but dinoSR0006

  // The README's tight bounding box, enlarged by 5 % (2.5 % of each extent on every side).
  const Vec3d tightLo = {-0.061897, -0.018874, -0.057845};
  const Vec3d tightHi = {0.010897, 0.068227, 0.015495};
  for (const std::string file : {"0000.obj", "hull/0000.obj"}) {
    const Mesh mesh = readObj(params.output + "/" + file);
    BoundingBox box;
    box.extend(mesh.positions);
    for (int k = 0; k < 3; ++k) {
      const double margin = 0.025 * (tightHi[k] - tightLo[k]);
      EXPECT_GE(box.lo[k], tightLo[k] - margin) << file << " axis " << k;
      EXPECT_LE(box.hi[k], tightHi[k] + margin) << file << " axis " << k;
    }
    std::printf("%s: bounds (%.5f %.5f %.5f) (%.5f %.5f %.5f)\n", file.c_str(), box.lo[0],
                box.lo[1], box.lo[2], box.hi[0], box.hi[1], box.hi[2]);
  }

  // The reprojection matches the thresholded silhouettes (recomputed here with the data set's
  // recipe) with IoU >= 0.95 on every good view.
  const Dataset dataset = importAny(params.input, ImportOptions());
  const Mesh mesh = readObj(params.output + "/0000.obj");
  for (size_t u = 0; u < result.cameras.size(); ++u) {
    const size_t c = dataset.cameraIndex(result.cameras[u]);
    CameraFrames frames(dataset, c);
    const Image silhouette = thresholdSilhouette(frames.frame(0), ThresholdRecipe());
    const double iou = maskIoU(renderMask(mesh, dataset.cameras[c].camera), silhouette);
    EXPECT_GE(iou, 0.95) << result.cameras[u];
    EXPECT_NEAR(iou, result.iou[0][u], 1e-12);
    std::printf("%s: IoU %.4f\n", result.cameras[u].c_str(), iou);
  }
}

TEST(ReconUu4cam, VideoToTrackedGomsThatTheCodecDecodesBitExactly) {
  REQUIRE_DATA("multiview/uu-4cam");
  // The shipped cfg on the first 50 frames at depth 7 with lighter I meshes, to keep the test
  // short; `3dvo-recon -c cfg/recon/uu-4cam.cfg` runs the whole video at depth 8.
  test::TempDir dir("recon-uu");
  ReconParams params =
      paramsFromCfg("uu-4cam.cfg", {"FrameCount=50", "OctreeDepth=7", "DecimationFaces=4000"});
  params.output = dir.file("out");
  const ReconResult result = runReconstruction(params, stdout);
  ASSERT_EQ(result.frames.size(), 50u);
  size_t tracked = 0;
  for (const FrameRecord& r : result.frames) {
    tracked += !r.iMesh;
    // The README: the approximate calibration reprojects with IoU of about 0.8.
    EXPECT_GE(r.iouMean, 0.8) << "frame " << r.frame;
  }
  EXPECT_GT(tracked, 25u) << "most frames should be tracked (P meshes)";

  // Every GOM encodes (D3DMC, lossless on the grid) and decodes to the encoder's MD5s.
  const auto goms = parseGomList(test::readText(params.output + "/goms.txt"), "goms.txt");
  EXPECT_EQ(goms, result.goms);
  const std::string codingCfg = std::string(TDVO_SOURCE_DIR) + "/cfg/d3dmc-lossless.cfg";
  for (size_t g = 0; g < goms.size(); ++g) {
    const std::string cfg = params.output + "/encode/" + framePath("gom_%04d.cfg", int(g));
    const std::string stream = dir.file("gom.3dvo");
    const test::CommandResult enc =
        test::run(dir, app("3dvo-enc"), {"-c", codingCfg, "-c", cfg, "--BitstreamFile=" + stream});
    ASSERT_EQ(enc.exitCode, 0) << "GOM " << g << ": " << enc.err;
    test::writeText(dir.file("enc.log"), enc.out);
    const test::CommandResult dec =
        test::run(dir, app("3dvo-dec"), {"-i", stream, "--verify", dir.file("enc.log")});
    ASSERT_EQ(dec.exitCode, 0) << "GOM " << g << ": " << dec.out << dec.err;
    EXPECT_EQ(test::linesStartingWith(dec.out, "MD5 frame=").size(),
              static_cast<size_t>(goms[g].second));
  }
}

TEST(ReconTvmc, TrackingGivesConstantConnectivityGomsWithinOnePercent) {
  REQUIRE_DATA("meshseq/tvmc-varying");
  struct Sequence {
    const char* name;
    int first;
  };
  size_t frames = 0, goms = 0;
  for (const Sequence& s : {Sequence{"basketball_player", 11}, Sequence{"dancer", 5},
                            Sequence{"mitch", 1}, Sequence{"thomas", 1}}) {
    test::TempDir dir("recon-tvmc");
    const std::string pattern =
        kData + "/meshseq/tvmc-varying/" + std::string(s.name) + "_fr%04d.obj.gz";
    ReconParams params = paramsFromCfg(
        "tvmc.cfg", {"InputMeshPattern=" + pattern, "FirstFrame=" + std::to_string(s.first)});
    params.output = dir.file("out");
    const ReconResult result = runReconstruction(params, nullptr);
    ASSERT_EQ(result.frames.size(), 10u);
    frames += result.frames.size();
    goms += result.goms.size();
    // The output files carry the input files' numbers (from s.first).
    for (const auto& [first, count] : result.goms) {
      const Mesh i = readObj(params.output + "/" + framePath("%04d.obj", s.first + first));
      for (int f = first; f < first + count; ++f) {
        const Mesh out = readObj(params.output + "/" + framePath("%04d.obj", s.first + f));
        EXPECT_EQ(out.triangles, i.triangles) << s.name << " frame " << f;
        // Against the input frame as published (before welding its seams).
        const Mesh input = readObj(framePath(pattern, s.first + f));
        BoundingBox box;
        box.extend(input.positions);
        const double hausdorff = surfaceDistance(input, out).hausdorff();
        EXPECT_LT(hausdorff, 0.01 * box.diagonal()) << s.name << " frame " << f;
        std::printf("%s frame %d (GOM of %d): Hausdorff %.4f %% of the diagonal\n", s.name, f,
                    count, 100 * hausdorff / box.diagonal());
      }
    }
  }
  EXPECT_LT(goms, frames / 2) << "tracking should keep GOMs longer than two frames on average";
}
