// Refining approximate camera poses against the silhouettes (docs/reconstruction.md,
// "Calibration refinement").
//
// Each camera in turn is moved so that its silhouette and the visual hull of the OTHER cameras
// agree: the hull is carved without it (CarvingView, carveVisualHull at a coarse depth), and a
// Nelder–Mead search over six parameters (a rotation about the camera's centre, as a Rodrigues
// vector in the camera frame, and a displacement of the centre; optionally a seventh, the log
// of the focal length) maximises the IoU of that hull's reprojection (renderMask, distortion
// included) with the camera's silhouette. The search stays within a bounded pose change. A
// pass over all cameras is kept only when it raises the agreement of the hull of ALL cameras
// with every silhouette (mean reprojection IoU); otherwise the cameras are restored and the
// refinement stops.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "common/views/camera.h"
#include "common/views/image.h"
#include "tools/recon/visual_hull.h"

namespace tdvo {

struct CalibrationRefinementOptions {
  int depth = 6;                  // octree depth of the hulls carved for the search
  int rounds = 2;                 // passes over the cameras
  int evaluations = 150;          // objective evaluations per camera and pass
  double rotationStep = 0.5;      // first simplex size: degrees
  double translationStep = 0.01;  // first simplex size: fraction of the distance to the hull
  double maxRotation = 2;         // largest rotation from the input pose (degrees)
  double maxTranslation = 0.04;   // largest centre move (fraction of the distance to the hull)
  bool focal = false;             // also refine the focal length (fx and fy by one factor)
  double maxFocalChange = 0.1;    // largest relative focal length change
  HullOptions hull;               // minViews (capped at cameras − 1 for the search) and clip box
};

struct CameraRefinement {
  std::string name;
  double iouBefore = 0, iouAfter = 0;  // with the hull of the other cameras
  double rotationDegrees = 0;          // rotation from the input pose
  double translation = 0;              // centre move (world units)
  double focalFactor = 1;              // new focal / input focal
};

struct CalibrationRefinementResult {
  std::vector<CameraRefinement> cameras;  // per camera (the last kept pass)
  double meanIouBefore = 0;               // hull of all cameras vs every silhouette, input poses
  double meanIouAfter = 0;                // the same with the returned poses
  int passesKept = 0;
  double seconds = 0;
};

// Refines `cameras` (in place) against `silhouettes` (grey, ≥ 128 object, one per camera in the
// camera's own image) inside `cube`. Throws Error with fewer than two cameras.
CalibrationRefinementResult refineCalibration(std::vector<Camera>& cameras,
                                              const std::vector<Image>& silhouettes,
                                              const CaptureCube& cube,
                                              const CalibrationRefinementOptions& options);

// Nelder–Mead minimisation of `f` from `start` with a first simplex of `steps` along each
// coordinate, at most `evaluations` calls to `f`. Returns the best point; `best` gets its value.
std::vector<double> nelderMead(const std::function<double(const std::vector<double>&)>& f,
                               const std::vector<double>& start, const std::vector<double>& steps,
                               int evaluations, double& best);

}  // namespace tdvo
