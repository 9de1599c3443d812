#include "tools/recon/reconstruction.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "common/core/error.h"
#include "common/media/png_io.h"
#include "common/media/video_reader.h"
#include "tools/multiview/importers.h"
#include "tools/recon/silhouettes.h"
#include "tools/recon/surface_processing.h"

namespace tdvo {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const size_t a = item.find_first_not_of(" \t"), b = item.find_last_not_of(" \t");
    if (a != std::string::npos) out.push_back(item.substr(a, b - a + 1));
  }
  return out;
}

// True when a surface vertex lies within one voxel of the cube's faces: the hull may have been
// cut by the cube.
bool touchesCube(const Mesh& mesh, const CaptureCube& cube, double voxel) {
  for (const Vec3d& p : mesh.positions)
    for (int k = 0; k < 3; ++k)
      if (p[k] < cube.origin[k] + 1.5 * voxel || p[k] > cube.origin[k] + cube.size - 1.5 * voxel)
        return true;
  return false;
}

}  // namespace

std::vector<size_t> selectCameras(const Dataset& dataset, const std::string& names,
                                  const std::string& exclude) {
  std::vector<size_t> used;
  if (names.empty()) {
    for (size_t c = 0; c < dataset.cameras.size(); ++c)
      used.push_back(c);
  } else {
    for (const std::string& name : splitList(names)) {
      const size_t c = dataset.cameraIndex(name);
      if (std::find(used.begin(), used.end(), c) == used.end()) used.push_back(c);
    }
    std::sort(used.begin(), used.end());
  }
  for (const std::string& name : splitList(exclude)) {
    const size_t c = dataset.cameraIndex(name);
    used.erase(std::remove(used.begin(), used.end(), c), used.end());
  }
  check(!used.empty(), "no camera left to reconstruct from (Cameras / ExcludeCameras)");
  return used;
}

struct FrameReconstructor::CameraState {
  CameraState(const Dataset& d, size_t camera) : frames(d, camera) {}
  CameraFrames frames;
  CanvasMap canvas;
  SilhouetteMethod method = SilhouetteMethod::threshold;
  std::unique_ptr<BackgroundSegmenter> segmenter;
};

FrameReconstructor::FrameReconstructor(const Dataset& dataset, const ReconParams& params)
    : dataset_(dataset), params_(params) {
  cameras_ = selectCameras(dataset, params.cameras, params.excludeCameras);
  minViews_ = params.minViews > 0
                  ? params.minViews
                  : std::max(1, static_cast<int>(std::ceil(0.75 * double(cameras_.size()))));
  check(minViews_ <= static_cast<int>(cameras_.size()),
        "MinViews " + std::to_string(minViews_) + " exceeds the " +
            std::to_string(cameras_.size()) + " cameras used");
  for (size_t c : cameras_) {
    const DatasetCamera& dc = dataset.cameras[c];
    auto state = std::make_unique<CameraState>(dataset, c);
    state->canvas = CanvasMap::build(dc.camera);
    SilhouetteMethod m = params.silhouetteMethod;
    const bool hasBackground = !dc.background.empty() || !dc.backgroundVideo.empty();
    if (m == SilhouetteMethod::automatic) {
      m = !dc.masks.empty() ? SilhouetteMethod::masks
          : dc.alphaMask    ? SilhouetteMethod::alpha
          : hasBackground   ? SilhouetteMethod::background
                            : SilhouetteMethod::threshold;
    }
    const std::string name = "camera '" + dc.camera.name + "'";
    check(m != SilhouetteMethod::masks || !dc.masks.empty(),
          name + ": SilhouetteMethod masks, but the dataset gives no masks");
    check(m != SilhouetteMethod::alpha || dc.alphaMask,
          name + ": SilhouetteMethod alpha, but the images have no alpha mask");
    check(m != SilhouetteMethod::background || hasBackground,
          name + ": SilhouetteMethod background, but the dataset gives no background");
    state->method = m;
    if (m == SilhouetteMethod::background) {
      state->segmenter = std::make_unique<BackgroundSegmenter>(params.background);
      const int limit =
          params.backgroundFrames > 0 ? params.backgroundFrames : params.background.history;
      if (!dc.backgroundVideo.empty()) {
        VideoReader video(dataset.resolve(dc.backgroundVideo));
        Image image;
        int learned = 0;
        while (learned < limit && video.read(image)) {
          check(image.width == dc.camera.width && image.height == dc.camera.height,
                dataset.resolve(dc.backgroundVideo) + ": frames are not the camera's size");
          state->segmenter->learnBackground(image);
          ++learned;
        }
        check(learned > 0, dataset.resolve(dc.backgroundVideo) + ": no frames");
      } else {
        // A still background (the first frame's, for a pattern), learned as a short video.
        const Image image = readPng(dataset.framePath(dc.background, params.firstFrame));
        check(image.width == dc.camera.width && image.height == dc.camera.height,
              dataset.framePath(dc.background, params.firstFrame) +
                  ": background is not the camera's size");
        for (int k = 0; k < std::min(limit, 10); ++k)
          state->segmenter->learnBackground(image);
      }
    }
    states_.push_back(std::move(state));
  }
  if (!params.volumeMin.empty()) {
    const Vec3d lo = parseVector3(params.volumeMin, "VolumeMin");
    const Vec3d hi = parseVector3(params.volumeMax, "VolumeMax");
    for (int k = 0; k < 3; ++k)
      check(hi[k] > lo[k], "VolumeMax must exceed VolumeMin in every coordinate");
    clipLo_ = lo;
    clipHi_ = hi;
    clipBox_ = true;
  }
}

FrameReconstructor::~FrameReconstructor() = default;

std::string FrameReconstructor::silhouetteMethodName(size_t usedCamera) const {
  switch (states_[usedCamera]->method) {
    case SilhouetteMethod::masks:
      return "masks";
    case SilhouetteMethod::alpha:
      return "alpha";
    case SilhouetteMethod::background:
      return "background";
    default:
      return "threshold";
  }
}

Image FrameReconstructor::silhouette(size_t usedCamera, int frame, Image* image) {
  CameraState& s = *states_[usedCamera];
  Image own;
  Image& picture = image ? *image : own;
  switch (s.method) {
    case SilhouetteMethod::masks:
    case SilhouetteMethod::alpha:
      if (image) *image = s.frames.frame(frame);
      return s.frames.mask(frame);
    case SilhouetteMethod::background:
      picture = s.frames.frame(frame);
      return s.segmenter->segment(picture);
    default:
      picture = s.frames.frame(frame);
      return thresholdSilhouette(picture, params_.threshold);
  }
}

std::vector<CarvingView> FrameReconstructor::carvingViews(
    const std::vector<Image>& silhouettes) const {
  std::vector<CarvingView> views;
  views.reserve(cameras_.size());
  for (size_t u = 0; u < cameras_.size(); ++u)
    views.emplace_back(states_[u]->canvas, silhouettes[u]);
  return views;
}

HullOptions FrameReconstructor::hullOptions() const {
  HullOptions options;
  options.depth = params_.octreeDepth;
  options.minViews = minViews_;
  if (clipBox_) {
    options.clip = true;
    options.clipLo = clipLo_;
    options.clipHi = clipHi_;
  }
  return options;
}

std::vector<Camera> FrameReconstructor::cameraModels() const {
  std::vector<Camera> models;
  for (size_t c : cameras_)
    models.push_back(dataset_.cameras[c].camera);
  return models;
}

CalibrationRefinementResult FrameReconstructor::refineCalibration(int frame, Dataset& dataset) {
  check(&dataset == &dataset_, "refineCalibration: not the reconstructor's dataset");
  keptFrame_ = frame;
  keptSilhouettes_.clear();
  keptImages_.assign(cameras_.size(), Image());
  for (size_t u = 0; u < cameras_.size(); ++u)
    keptSilhouettes_.push_back(silhouette(u, frame, &keptImages_[u]));
  const std::vector<CarvingView> views = carvingViews(keptSilhouettes_);
  const HullOptions options = hullOptions();
  const CaptureCube cube = estimateCaptureCube(views, options, params_.volumeMargin);
  std::vector<Camera> cameras = cameraModels();
  CalibrationRefinementOptions refine = params_.calibration;
  refine.hull = options;
  const CalibrationRefinementResult result =
      tdvo::refineCalibration(cameras, keptSilhouettes_, cube, refine);
  for (size_t u = 0; u < cameras_.size(); ++u) {
    dataset.cameras[cameras_[u]].camera = cameras[u];
    states_[u]->canvas = CanvasMap::build(cameras[u]);
  }
  haveCube_ = false;
  return result;
}

ReconstructedFrame FrameReconstructor::reconstruct(int frame) {
  ReconstructedFrame out;
  auto start = std::chrono::steady_clock::now();
  std::vector<Image> images(cameras_.size());
  if (frame == keptFrame_) {
    out.silhouettes = std::move(keptSilhouettes_);
    images = std::move(keptImages_);
    keptFrame_ = -1;
  } else {
    for (size_t u = 0; u < cameras_.size(); ++u)
      out.silhouettes.push_back(silhouette(u, frame, params_.photoRefine ? &images[u] : nullptr));
  }
  const std::vector<CarvingView> views = carvingViews(out.silhouettes);
  out.silhouetteSeconds = secondsSince(start);

  const HullOptions options = hullOptions();
  if (!haveCube_) {
    cube_ = estimateCaptureCube(views, options, params_.volumeMargin);
    haveCube_ = true;
  }
  out.stats = carveVisualHull(views, cube_, options);
  if (touchesCube(out.stats.surface, cube_, out.stats.voxelSize)) {
    // The object moved out of the cube found earlier: find it again.
    const double before = out.stats.carvingSeconds + out.stats.surfaceSeconds;
    cube_ = estimateCaptureCube(views, options, params_.volumeMargin);
    out.stats = carveVisualHull(views, cube_, options);
    out.stats.carvingSeconds += before;
  }
  out.cube = cube_;
  out.hull = std::move(out.stats.surface);
  out.stats.surface = Mesh();
  check(!out.hull.triangles.empty(),
        "frame " + std::to_string(frame) +
            ": the visual hull is empty (the silhouettes do not agree on any region)");

  start = std::chrono::steady_clock::now();
  out.surface = out.hull;
  out.components = params_.keepLargestComponent ? keepLargestComponent(out.surface) : 1;
  SmoothingOptions smoothing;
  smoothing.iterations = params_.smoothingIterations;
  smoothing.maxDisplacement = params_.smoothingMaxDisplacement * out.stats.voxelSize;
  smoothMesh(out.surface, smoothing);
  out.smoothingSeconds = secondsSince(start);
  if (params_.photoRefine) {
    out.photo =
        photoRefine(out.surface, cameraModels(), images, views, out.stats.voxelSize, params_.photo);
    out.photoRefined = true;
  }
  return out;
}

}  // namespace tdvo
