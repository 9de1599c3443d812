// One frame of multi-view input to one closed surface: silhouettes of every used camera,
// octree visual hull, marching cubes, largest component, umbrella smoothing. (Decimation and
// tracking happen per GOM, in gom_builder.h.)
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "common/media/dataset.h"
#include "tools/recon/photo_refinement.h"
#include "tools/recon/recon_params.h"
#include "tools/recon/visual_hull.h"

namespace tdvo {

struct ReconstructedFrame {
  Mesh surface;                    // smoothed, largest component (what the GOMs follow)
  Mesh hull;                       // the marching cubes mesh as carved (all components)
  std::vector<Image> silhouettes;  // per used camera, grey 255/0, the camera's own image
  CaptureCube cube;                // the carved cube
  HullResult stats;                // counts and carving/surface times (stats.surface empty)
  size_t components = 0;           // connected parts of the hull mesh
  double silhouetteSeconds = 0, smoothingSeconds = 0;
  bool photoRefined = false;  // PhotoRefine ran (photo holds its figures)
  PhotoRefineStats photo;
};

class FrameReconstructor {
 public:
  // Prepares the used cameras (undistortion maps) and, for background subtraction, learns
  // the background models. Throws Error for unknown camera names or missing silhouette
  // sources.
  FrameReconstructor(const Dataset& dataset, const ReconParams& params);
  ~FrameReconstructor();

  // Reconstructs dataset frame index `frame`. Video frames must be asked for in increasing
  // order when background subtraction is used (its model follows the video).
  ReconstructedFrame reconstruct(int frame);

  // The used cameras (in dataset order) and how their silhouettes are made.
  const std::vector<size_t>& cameras() const { return cameras_; }
  // The used cameras' models, in that order (refined ones after refineCalibration).
  std::vector<Camera> cameraModels() const;
  std::string silhouetteMethodName(size_t usedCamera) const;
  int minViews() const { return minViews_; }

  // RefineCalibration: refines the used cameras' poses on dataset frame index `frame`
  // (calibration_refinement.h) and stores them in `dataset` (the dataset this reconstructor
  // reads); the capture cube is found again with them. The frame's silhouettes are kept for
  // the next reconstruct(frame).
  CalibrationRefinementResult refineCalibration(int frame, Dataset& dataset);

 private:
  // The silhouette of one used camera; `image` (if not null) gets the camera image.
  Image silhouette(size_t usedCamera, int frame, Image* image);
  std::vector<CarvingView> carvingViews(const std::vector<Image>& silhouettes) const;
  HullOptions hullOptions() const;

  struct CameraState;
  const Dataset& dataset_;
  const ReconParams& params_;
  std::vector<size_t> cameras_;
  std::vector<std::unique_ptr<CameraState>> states_;
  int minViews_ = 1;
  bool clipBox_ = false;  // VolumeMin/VolumeMax given
  bool haveCube_ = false;
  CaptureCube cube_;
  int keptFrame_ = -1;  // frame whose silhouettes and images are kept (refineCalibration)
  std::vector<Image> keptSilhouettes_, keptImages_;
  Vec3d clipLo_ = {0, 0, 0}, clipHi_ = {0, 0, 0};  // VolumeMin, VolumeMax
};

// The used cameras: all, or those named in `names` (comma-separated), minus those in
// `exclude`. Throws Error naming an unknown camera or when none is left.
std::vector<size_t> selectCameras(const Dataset& dataset, const std::string& names,
                                  const std::string& exclude);

}  // namespace tdvo
