// Reconstruction speed, stage by stage, on a synthetic capture: the built-in deforming blob
// (2,562 vertices) seen by 8 ring cameras at 640 × 480, carved at octree depth 8.
//
//   build/bin/recon_bench                      every stage
//   build/bin/recon_bench --benchmark_filter=Carving
//
// Stages: silhouettes (background subtraction, thresholding), carving-view preparation (mask
// resampling, integral image, distance transforms), octree carving, surface extraction (corner
// distances + marching cubes), smoothing, decimation, tracking (one frame). Carving and surface
// extraction are timed from inside carveVisualHull (manual time), so each is reported alone.
#include <benchmark/benchmark.h>

#include "common/views/rasteriser.h"
#include "tools/eval/metrics.h"
#include "tools/eval/sample_mesh.h"
#include "tools/multiview/synth_rig.h"
#include "tools/recon/carving_view.h"
#include "tools/recon/silhouettes.h"
#include "tools/recon/surface_processing.h"
#include "tools/recon/tracking.h"
#include "tools/recon/visual_hull.h"

using namespace tdvo;

namespace {

struct Scene {
  std::vector<Camera> cameras;
  std::vector<CanvasMap> maps;
  std::vector<std::vector<Image>> masks;  // [frame][camera]
  std::vector<std::vector<CarvingView>> views;
  HullOptions options;
  CaptureCube cube;
  std::vector<Mesh> surfaces;  // smoothed hull per frame
};

const Scene& scene() {
  static const Scene s = [] {
    Scene s;
    const std::vector<Mesh> blob = deformingBlob(4, 2);
    SynthParams rig;
    rig.width = 640;
    rig.height = 480;
    rig.cameras = 8;
    BoundingBox box;
    box.extend(blob[0].positions);
    const Vec3d centre = 0.5 * (box.lo + box.hi);
    s.cameras = makeRigCameras(rig, centre, 0.5 * box.diagonal());
    for (const Camera& c : s.cameras)
      s.maps.push_back(CanvasMap::build(c));
    s.options.depth = 8;
    s.options.minViews = 6;
    for (const Mesh& m : blob) {
      std::vector<Image> masks;
      std::vector<CarvingView> views;
      for (size_t c = 0; c < s.cameras.size(); ++c) {
        masks.push_back(renderMask(m, s.cameras[c]));
        views.emplace_back(s.maps[c], masks.back());
      }
      s.masks.push_back(std::move(masks));
      s.views.push_back(std::move(views));
    }
    s.cube = estimateCaptureCube(s.views[0], s.options, 0.1);
    for (const auto& views : s.views) {
      Mesh surface = carveVisualHull(views, s.cube, s.options).surface;
      keepLargestComponent(surface);
      smoothMesh(surface, {3, 0});
      s.surfaces.push_back(std::move(surface));
    }
    return s;
  }();
  return s;
}

void BM_SilhouetteBackground(benchmark::State& state) {
  // One 640 × 480 frame per iteration: model comparison, clean-up, Kalman, selective update.
  Image background(640, 480, 3, 60), frame = background;
  for (int y = 150; y < 350; ++y)
    for (int x = 250; x < 400; ++x)
      frame.at(x, y, 0) = 220;
  BackgroundSegmenter segmenter{BackgroundOptions()};
  for (int k = 0; k < 20; ++k)
    segmenter.learnBackground(background);
  for (auto _ : state)
    benchmark::DoNotOptimize(segmenter.segment(frame));
}
BENCHMARK(BM_SilhouetteBackground)->Unit(benchmark::kMillisecond);

void BM_SilhouetteThreshold(benchmark::State& state) {
  Image image(640, 480, 3, 10);
  for (int y = 100; y < 380; ++y)
    for (int x = 200; x < 440; ++x)
      image.at(x, y, 1) = 200;
  for (auto _ : state)
    benchmark::DoNotOptimize(thresholdSilhouette(image, ThresholdRecipe()));
}
BENCHMARK(BM_SilhouetteThreshold)->Unit(benchmark::kMillisecond);

void BM_CarvingViews(benchmark::State& state) {
  // The 8 views of one frame: integral images and signed distance fields.
  const Scene& s = scene();
  for (auto _ : state) {
    std::vector<CarvingView> views;
    for (size_t c = 0; c < s.cameras.size(); ++c)
      views.emplace_back(s.maps[c], s.masks[0][c]);
    benchmark::DoNotOptimize(views.data());
  }
}
BENCHMARK(BM_CarvingViews)->Unit(benchmark::kMillisecond);

void BM_Carving(benchmark::State& state) {
  // Octree carving per frame: 8 cameras, 640 × 480, depth 8.
  const Scene& s = scene();
  size_t cells = 0, voxels = 0;
  for (auto _ : state) {
    const HullResult r = carveVisualHull(s.views[0], s.cube, s.options);
    state.SetIterationTime(r.carvingSeconds);
    cells = r.cellsJudged;
    voxels = r.surfaceVoxels;
  }
  state.counters["octree_cells"] = double(cells);
  state.counters["surface_voxels"] = double(voxels);
}
BENCHMARK(BM_Carving)->UseManualTime()->Unit(benchmark::kMillisecond);

void BM_SurfaceExtraction(benchmark::State& state) {
  // Corner signed distances and marching cubes on the same carving.
  const Scene& s = scene();
  size_t triangles = 0;
  for (auto _ : state) {
    const HullResult r = carveVisualHull(s.views[0], s.cube, s.options);
    state.SetIterationTime(r.surfaceSeconds);
    triangles = r.surface.triangles.size();
  }
  state.counters["triangles"] = double(triangles);
}
BENCHMARK(BM_SurfaceExtraction)->UseManualTime()->Unit(benchmark::kMillisecond);

void BM_CaptureCubeEstimate(benchmark::State& state) {
  const Scene& s = scene();
  for (auto _ : state)
    benchmark::DoNotOptimize(estimateCaptureCube(s.views[0], s.options, 0.1));
}
BENCHMARK(BM_CaptureCubeEstimate)->Unit(benchmark::kMillisecond);

void BM_Smoothing(benchmark::State& state) {
  // Three umbrella iterations on the raw marching cubes mesh.
  const Scene& s = scene();
  Mesh raw = carveVisualHull(s.views[0], s.cube, s.options).surface;
  keepLargestComponent(raw);
  for (auto _ : state) {
    Mesh m = raw;
    smoothMesh(m, {3, 0});
    benchmark::DoNotOptimize(m.positions.data());
  }
  state.counters["triangles"] = double(raw.triangles.size());
}
BENCHMARK(BM_Smoothing)->Unit(benchmark::kMillisecond);

void BM_Decimation(benchmark::State& state) {
  // To 10,000 triangles, normal deviation at most 30 degrees.
  const Scene& s = scene();
  DecimationOptions options;
  options.targetFaces = 10000;
  options.maxNormalDeviation = 30;
  for (auto _ : state) {
    Mesh m = s.surfaces[0];
    decimateMesh(m, options);
    benchmark::DoNotOptimize(m.positions.data());
  }
  state.counters["input_triangles"] = double(s.surfaces[0].triangles.size());
}
BENCHMARK(BM_Decimation)->Unit(benchmark::kMillisecond);

void BM_Tracking(benchmark::State& state) {
  // One frame: the decimated first frame fitted to the second frame's surface.
  const Scene& s = scene();
  Mesh rest = s.surfaces[0];
  DecimationOptions options;
  options.targetFaces = 10000;
  options.maxNormalDeviation = 30;
  decimateMesh(rest, options);
  for (auto _ : state) {
    MeshTracker tracker(rest, TrackingOptions());
    benchmark::DoNotOptimize(tracker.fit(s.surfaces[1]));
  }
  state.counters["vertices"] = double(rest.positions.size());
}
BENCHMARK(BM_Tracking)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
