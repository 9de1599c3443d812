// The parameters of 3dvo-recon and their cfg keys (docs/reconstruction.md lists every key).
#pragma once

#include <string>
#include <vector>

#include "common/core/config.h"
#include "tools/recon/calibration_refinement.h"
#include "tools/recon/photo_refinement.h"
#include "tools/recon/silhouettes.h"
#include "tools/recon/surface_processing.h"
#include "tools/recon/tracking.h"

namespace tdvo {

enum class SilhouetteMethod { automatic, masks, alpha, threshold, background };
enum class GomMode { adaptive, fixed };

struct ReconParams {
  // Input and output.
  std::string input;                  // dataset folder, or anything tools/multiview imports
  std::string inputMeshPattern;       // or: an OBJ sequence to track (no reconstruction)
  std::string output;                 // output folder
  bool overwrite = false;             // replace a non-empty output folder's contents
  std::vector<std::string> cfgFiles;  // the cfg files read (not a key): never replaced
  int firstFrame = 0;                 // dataset frame index / number of the first input mesh file
  int frameCount = 0;                 // frames to process; 0: every frame from firstFrame on
  std::string cameras;                // comma-separated camera names to use; empty: all
  std::string excludeCameras;         // comma-separated camera names to leave out
  std::string outputMeshPattern = "%04d.obj";  // OBJ name inside Output, numbered from 0
  bool writeSilhouettes = false;               // silhouettes/<camera>/%04d.png
  bool writeHull = false;  // hull/%04d.obj: each frame's reconstruction before tracking

  // Silhouettes.
  SilhouetteMethod silhouetteMethod = SilhouetteMethod::automatic;
  ThresholdRecipe threshold;
  BackgroundOptions background;
  int backgroundFrames = 0;  // background frames to learn from; 0: all (up to the history)

  // Visual hull.
  int octreeDepth = 7;
  int minViews = 0;                  // 0: three quarters of the views, rounded up (at least 1)
  std::string volumeMin, volumeMax;  // capture box corners "x,y,z"; empty: estimated
  double volumeMargin = 0.1;         // estimated cube: margin around the hull (× its extent)
  bool keepLargestComponent = true;

  // Calibration refinement (calibration_refinement.h), on the first frame.
  bool refineCalibration = false;
  CalibrationRefinementOptions calibration;

  // Photo-consistency refinement of each frame's surface (photo_refinement.h).
  bool photoRefine = false;
  PhotoRefineOptions photo;

  // Surface.
  int smoothingIterations = 3;
  double smoothingMaxDisplacement = 0.5;  // voxels; 0: unlimited
  int decimationFaces = 10000;            // target triangles of an I mesh; 0: no decimation
  double decimationMaxAngle = 30;         // degrees of normal deviation
  double decimationMaxError = 0;          // quadric error bound in voxels²; 0: none

  // Tracking into GOMs.
  bool tracking = true;  // false: every frame its own reconstruction (one-frame GOMs)
  GomMode gomMode = GomMode::adaptive;
  int gomSize = 16;              // adaptive: longest GOM; fixed: every GOM's length
  double trackMaxError = 0.009;  // adaptive: a new GOM starts when the fit's symmetric
                                 // Hausdorff distance exceeds this × the frame's box diagonal
  TrackingOptions trackingOptions;
  bool weldInput = true;  // InputMeshPattern: merge coincident vertices first
};

// Registers every key in the table, bound to `params`.
// (Also adds the --version lines of the libraries reconstruction links: OpenMesh, OpenCV.)
void addReconOptions(OptionTable& table, ReconParams& params);

// Checks the combination of values (ranges are checked by the table). Throws Error.
void checkReconParams(const ReconParams& params);

}  // namespace tdvo
