// Refinements of 3dvo-recon (issue 22 points 1 and 2): photo-consistency refinement of the
// surface and calibration refinement, on the synthetic rig whose ground truth is known.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "common/core/error.h"
#include "common/media/dataset.h"
#include "common/views/rasteriser.h"
#include "tests/test_support.h"
#include "tools/eval/metrics.h"
#include "tools/multiview/synth_rig.h"
#include "tools/recon/calibration_refinement.h"
#include "tools/recon/recon_pipeline.h"
#include "tools/recon/silhouettes.h"

using namespace tdvo;

namespace {

// Mean pixel distance between the projections of `points` by two cameras.
double meanReprojectionGap(const std::vector<Vec3d>& points, const Camera& a, const Camera& b) {
  double sum = 0;
  size_t n = 0;
  for (const Vec3d& p : points) {
    Vec2d pa, pb;
    if (!a.project(p, pa) || !b.project(p, pb)) continue;
    sum += std::hypot(pa[0] - pb[0], pa[1] - pb[1]);
    ++n;
  }
  return n > 0 ? sum / double(n) : 1e9;
}

// Turns `camera` by about 1.5 degrees and moves its centre by 3 % of its distance to `middle`.
void perturb(Camera& camera, const Vec3d& middle) {
  const Vec3d centre = camera.centre();
  camera.R = rotationFromRodrigues({0.015, -0.02, 0.01}) * camera.R;
  const Vec3d shifted = centre + 0.03 * norm(centre - middle) * normalized(Vec3d{1, 0.5, -0.3});
  const Vec3d rc = camera.R * shifted;
  camera.t = {-rc[0], -rc[1], -rc[2]};
}

Vec3d boxCentre(const Mesh& mesh) {
  BoundingBox box;
  box.extend(mesh.positions);
  return 0.5 * (box.lo + box.hi);
}

}  // namespace

TEST(ReconRefine, NelderMeadFindsTheMinimumOfAQuadratic) {
  auto f = [](const std::vector<double>& x) {
    return (x[0] - 1) * (x[0] - 1) + 4 * (x[1] + 2) * (x[1] + 2) + (x[2] - 0.5) * (x[2] - 0.5);
  };
  double best = 0;
  const std::vector<double> x = nelderMead(f, {0, 0, 0}, {0.5, 0.5, 0.5}, 400, best);
  EXPECT_NEAR(x[0], 1, 1e-3);
  EXPECT_NEAR(x[1], -2, 1e-3);
  EXPECT_NEAR(x[2], 0.5, 1e-3);
  EXPECT_LT(best, 1e-5);
}

// Photo-consistency moves the hull toward the true surface: the mean distance to the ground
// truth falls (the rig's textured blob, 8 ring cameras).
TEST(ReconRefine, PhotoRefineBringsTheSynthRigCloserToTheTruth) {
  test::TempDir dir("recon-photo");
  SynthParams rig;
  rig.output = dir.file("synth");
  rig.frameCount = 1;
  writeSyntheticDataset(rig);
  ReconParams params;
  params.input = rig.output;
  params.tracking = false;
  params.decimationFaces = 0;
  params.output = dir.file("hull");
  const ReconResult hull = runReconstruction(params, nullptr);
  params.photoRefine = true;
  params.output = dir.file("photo");
  const ReconResult photo = runReconstruction(params, nullptr);
  const FrameRecord& a = hull.frames.at(0);
  const FrameRecord& b = photo.frames.at(0);
  std::printf(
      "truth mean distance: hull %.5f, photo-refined %.5f (%zu targets, %.3f voxels, "
      "%.2f s); IoU %.4f -> %.4f\n",
      a.truthMean, b.truthMean, b.photoTargets, b.photoDisplacement, b.photoSeconds, a.iouMean,
      b.iouMean);
  EXPECT_LT(b.truthMean, 0.85 * a.truthMean);
  EXPECT_GT(b.photoTargets, 0u);
  EXPECT_GT(b.iouMin, 0.97);  // still close to every silhouette
}

// A camera turned by 1.5 degrees and moved by 3 % of its distance is pulled back: its
// projection of the true surface comes much closer to the true camera's.
TEST(ReconRefine, PerturbedCameraIsPulledBackTowardItsTruePose) {
  test::TempDir dir("recon-calib");
  SynthParams rig;
  rig.output = dir.file("synth");
  rig.frameCount = 1;
  const Dataset dataset = writeSyntheticDataset(rig);
  const Mesh truth = readDatasetMesh(dataset, 0);
  std::vector<Camera> cameras;
  std::vector<Image> masks;
  for (const DatasetCamera& c : dataset.cameras) {
    cameras.push_back(c.camera);
    masks.push_back(renderMask(truth, c.camera));
  }
  const std::vector<Camera> trueCameras = cameras;
  BoundingBox box;
  box.extend(truth.positions);
  const Vec3d middle = boxCentre(truth);
  const size_t moved = 2;
  perturb(cameras[moved], middle);
  const double before = meanReprojectionGap(truth.positions, cameras[moved], trueCameras[moved]);

  CalibrationRefinementOptions options;
  options.hull.minViews = 6;
  CaptureCube cube;
  const double size = 1.4 * box.diagonal();
  for (int k = 0; k < 3; ++k)
    cube.origin[k] = middle[k] - size / 2;
  cube.size = size;
  const CalibrationRefinementResult r = refineCalibration(cameras, masks, cube, options);
  const double after = meanReprojectionGap(truth.positions, cameras[moved], trueCameras[moved]);
  std::printf("camera %zu: reprojection gap %.2f px -> %.2f px; hull IoU %.4f -> %.4f\n", moved,
              before, after, r.meanIouBefore, r.meanIouAfter);
  EXPECT_LT(after, 0.4 * before);
  EXPECT_GT(r.meanIouAfter, r.meanIouBefore);
  // The other cameras stay close to their (true) poses.
  for (size_t k = 0; k < cameras.size(); ++k) {
    if (k == moved) continue;
    EXPECT_LT(meanReprojectionGap(truth.positions, cameras[k], trueCameras[k]), 0.5 * before);
  }
}

// The app's path: a dataset whose camera 2 is off; Output/dataset.json holds it corrected, and
// the reported IoU rises against a run without the refinement.
TEST(ReconRefine, RefinedCamerasAreWrittenToTheOutputDataset) {
  test::TempDir dir("recon-calib-app");
  SynthParams rig;
  rig.output = dir.file("synth");
  rig.frameCount = 1;
  Dataset dataset = writeSyntheticDataset(rig);
  const Mesh truth = readDatasetMesh(dataset, 0);
  const Camera trueCamera = dataset.cameras[2].camera;
  perturb(dataset.cameras[2].camera, boxCentre(truth));
  writeDataset(dataset, rig.output);
  ReconParams params;
  params.input = rig.output;
  params.octreeDepth = 6;
  params.decimationFaces = 0;
  params.output = dir.file("plain");
  const ReconResult plain = runReconstruction(params, nullptr);
  params.refineCalibration = true;
  params.calibration.rounds = 1;
  params.output = dir.file("refined");
  const ReconResult refined = runReconstruction(params, nullptr);
  const Dataset written = readDataset(params.output);
  ASSERT_EQ(written.cameras.size(), dataset.cameras.size());
  const double before = meanReprojectionGap(truth.positions, dataset.cameras[2].camera, trueCamera);
  const double after = meanReprojectionGap(truth.positions, written.cameras[2].camera, trueCamera);
  std::printf(
      "written camera 2: gap %.2f px -> %.2f px; IoU mean %.4f -> %.4f, worst %.4f -> "
      "%.4f\n",
      before, after, plain.frames[0].iouMean, refined.frames[0].iouMean, plain.frames[0].iouMin,
      refined.frames[0].iouMin);
  EXPECT_LT(after, 0.4 * before);
  EXPECT_GT(refined.frames[0].iouMin, plain.frames[0].iouMin);
  // The images and masks are still found from the new place of dataset.json.
  CameraFrames frames(written, 2);
  EXPECT_FALSE(frames.frame(0).empty());
  // The cfg files name the refined cameras for the textures (their shapes are the mesh projected
  // into them), in a comment: they code the geometry alone, as without the refinement.
  auto text = [](const std::string& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string datasetLine =
      "\n# Dataset          : " +
      std::filesystem::absolute(std::filesystem::path(params.output) / "dataset.json").string();
  EXPECT_NE(text(params.output + "/encode.cfg").find(datasetLine), std::string::npos);
  EXPECT_NE(text(params.output + "/encode/gom_0000.cfg").find(datasetLine), std::string::npos);
  EXPECT_EQ(text(dir.file("plain") + "/encode.cfg").find("Dataset"), std::string::npos);
}

TEST(ReconRefine, RefineCalibrationNeedsTwoCameras) {
  std::vector<Camera> one(1);
  std::vector<Image> masks(1);
  EXPECT_THROW(refineCalibration(one, masks, CaptureCube(), CalibrationRefinementOptions()), Error);
}
