#include "tools/recon/recon_params.h"

#include <OpenMesh/Core/System/config.h>
#include <opencv2/core/version.hpp>

#include "common/core/error.h"
#include "common/core/sequence.h"

namespace tdvo {

void addReconOptions(OptionTable& table, ReconParams& p) {
  table.addVersionLines({"OpenMesh " + std::to_string(OM_GET_VER) + "." +
                             std::to_string(OM_GET_MAJ) + "." + std::to_string(OM_GET_MIN),
                         std::string("OpenCV ") + CV_VERSION});
  table.section("Input and output");
  table.add("Input", p.input,
            "dataset folder (dataset.json) or any input 3dvo-import recognises (Middlebury "
            "*_par.txt, OpenCV camera folders, NeRF transforms*.json)",
            "-i");
  table.add("InputMeshPattern", p.inputMeshPattern,
            "instead of Input: a mesh sequence (OBJ, PLY or glTF frames; printf pattern) to track "
            "into GOMs without "
            "reconstruction");
  table.add("Output", p.output, "output folder: OBJ frames, GOM list, encoder cfg, report", "-o");
  table.add(
      "Overwrite", p.overwrite,
      "replace the contents of a non-empty output folder (without it such a folder is refused)",
      "--Overwrite");
  table.add("FirstFrame", p.firstFrame, 0, 1000000000,
            "first dataset frame index (Input) or first file number (InputMeshPattern)");
  table.add("FrameCount", p.frameCount, 0, 1000000,
            "frames to process; 0: all from FirstFrame on (InputMeshPattern: required)");
  table.add("Cameras", p.cameras, "comma-separated camera names to use (empty: all)");
  table.add("ExcludeCameras", p.excludeCameras, "comma-separated camera names to leave out");
  table.add("OutputMeshPattern", p.outputMeshPattern,
            "file name of output frame n inside Output: n is the input's frame number (the "
            "dataset's frames.first + index, or the input file's number: InputMeshPattern with "
            "FirstFrame 200 writes 0200.obj ...)");
  table.add("WriteSilhouettes", p.writeSilhouettes,
            "also write the silhouettes (silhouettes/<camera>/%04d.png)");
  table.add("WriteHull", p.writeHull,
            "also write each frame's reconstruction before tracking (hull/%04d.obj)");

  table.section("Silhouettes");
  table.addEnum("SilhouetteMethod", p.silhouetteMethod,
                {{"auto", SilhouetteMethod::automatic},
                 {"masks", SilhouetteMethod::masks},
                 {"alpha", SilhouetteMethod::alpha},
                 {"threshold", SilhouetteMethod::threshold},
                 {"background", SilhouetteMethod::background}},
                "auto: the dataset's masks or alpha, else background subtraction when it has a "
                "background, else thresholding");
  table.add("Threshold", p.threshold.threshold, 0, 1,
            "threshold: luma level (0..1) above which a pixel is object");
  table.add("DilateRadius", p.threshold.dilate, 0, 1000, "threshold: dilation disc radius (px)");
  table.add("ErodeRadius", p.threshold.erode, 0, 1000, "threshold: erosion disc radius (px)");
  table.add("BackgroundFrames", p.backgroundFrames, 0, 1000000,
            "background: frames of the background video to learn from; 0: all (up to "
            "BackgroundHistory)");
  table.add("BackgroundHistory", p.background.history, 1, 100000,
            "background: frames the per-pixel model remembers (MOG2 history)");
  table.add("BackgroundVarThreshold", p.background.varThreshold, 1, 10000,
            "background: squared Mahalanobis distance above which a pixel is foreground");
  table.add("BackgroundShadows", p.background.detectShadows,
            "background: detect shadows and count them as background");
  table.add("BackgroundLearningRate", p.background.learningRate, 0, 1,
            "background: model update per object frame, outside the object's region");
  table.add("OpenRadius", p.background.openRadius, 0, 100,
            "background: morphological opening disc radius (px)");
  table.add("CloseRadius", p.background.closeRadius, 0, 100,
            "background: morphological closing disc radius (px)");
  table.add("MinBlobArea", p.background.minBlobArea, 0, 1,
            "background: smallest foreground blob kept (fraction of the image)");
  table.add("RegionMargin", p.background.regionMargin, 0, 10,
            "background: margin around the tracked object box (fraction of its size)");
  table.add("KalmanProcessNoise", p.background.processNoise, 1e-6, 1e6,
            "background: Kalman process noise, std. dev. of the box's change per frame (px)");
  table.add("KalmanMeasurementNoise", p.background.measurementNoise, 1e-6, 1e6,
            "background: Kalman measurement noise, std. dev. of the measured box (px)");

  table.section("Visual hull");
  table.add("OctreeDepth", p.octreeDepth, 3, 11, "octree depth: 2^depth voxels per axis");
  table.add("MinViews", p.minViews, 0, 65535,
            "views that must see a point for it to be kept; 0: 3/4 of the views, rounded up");
  table.add("VolumeMin", p.volumeMin, "capture box lowest corner x,y,z (empty: estimated)");
  table.add("VolumeMax", p.volumeMax, "capture box highest corner x,y,z (empty: estimated)");
  table.add("VolumeMargin", p.volumeMargin, 0, 10,
            "estimated capture cube: margin around the hull (fraction of its extent)");
  table.add("KeepLargestComponent", p.keepLargestComponent,
            "keep only the largest connected part of the surface");

  table.section("Calibration refinement");
  table.add("RefineCalibration", p.refineCalibration,
            "refine the camera poses on the first frame so that each silhouette agrees with the "
            "hull of the other cameras; writes the refined cameras to Output/dataset.json");
  table.add("RefineCalibrationDepth", p.calibration.depth, 3, 9,
            "octree depth of the hulls carved during the search");
  table.add("RefineCalibrationRounds", p.calibration.rounds, 1, 20, "passes over the cameras");
  table.add("RefineCalibrationEvaluations", p.calibration.evaluations, 10, 100000,
            "IoU evaluations per camera and pass (Nelder-Mead)");
  table.add("RefineMaxRotation", p.calibration.maxRotation, 0, 45,
            "largest rotation of a camera from its input pose (degrees)");
  table.add("RefineMaxTranslation", p.calibration.maxTranslation, 0, 1,
            "largest move of a camera centre (fraction of its distance to the object)");
  table.add("RefineFocal", p.calibration.focal, "also refine each camera's focal length");
  table.add("RefineMaxFocalChange", p.calibration.maxFocalChange, 0, 0.5,
            "largest relative change of a focal length");

  table.section("Photo-consistency refinement");
  table.add("PhotoRefine", p.photoRefine,
            "move each surface vertex along its normal to the most colour-consistent depth among "
            "the cameras that see it (never outside the hull)");
  table.add("PhotoRefineIterations", p.photo.iterations, 1, 100, "search + regularisation rounds");
  table.add("PhotoRefineInward", p.photo.inward, 0, 100,
            "search range inwards along the normal (voxels)");
  table.add("PhotoRefineOutward", p.photo.outward, 0, 100,
            "search range outwards along the normal (voxels; the hull still bounds it)");
  table.add("PhotoRefineStep", p.photo.step, 0.05, 10, "search step (voxels)");
  table.add("PhotoRefineMinScore", p.photo.minScore, -1, 1,
            "least mean NCC of the best depth for a vertex to move");
  table.add("PhotoRefineSmoothing", p.photo.smoothing, 0, 1000,
            "Laplacian smoothing iterations of the displacements");

  table.section("Surface");
  table.add("SmoothingIterations", p.smoothingIterations, 0, 1000,
            "umbrella (Laplacian) smoothing iterations");
  table.add("SmoothingMaxDisplacement", p.smoothingMaxDisplacement, 0, 1000,
            "smoothing moves no vertex farther than this along its normal (voxels; 0: unlimited)");
  table.add("DecimationFaces", p.decimationFaces, 0, 100000000,
            "target triangle count of each GOM's first mesh; 0: no decimation");
  table.add("DecimationMaxAngle", p.decimationMaxAngle, 0, 180,
            "decimation: largest normal deviation a collapse may cause (degrees)");
  table.add("DecimationMaxError", p.decimationMaxError, 0, 1e12,
            "decimation: quadric error bound (voxels squared); 0: none");

  table.section("Tracking");
  table.add("Tracking", p.tracking,
            "deform each GOM's first mesh through the following frames (false: every frame is "
            "its own GOM)");
  table.addEnum("GOMMode", p.gomMode, {{"adaptive", GomMode::adaptive}, {"fixed", GomMode::fixed}},
                "adaptive: a new GOM when the fit error passes TrackMaxError or the GOM reaches "
                "GOMSize; fixed: every GOM GOMSize frames");
  table.add("GOMSize", p.gomSize, 1, 65535, "adaptive: longest GOM; fixed: frames per GOM");
  table.add("TrackMaxError", p.trackMaxError, 0, 1,
            "adaptive: largest symmetric Hausdorff distance of a tracked frame to its "
            "reconstruction, as a fraction of the frame's bounding-box diagonal");
  table.add("TrackIterations", p.trackingOptions.iterations, 1, 1000,
            "fitting iterations per frame");
  table.add("TrackStiffness", p.trackingOptions.stiffness, 1e-9, 1e9,
            "as-rigid-as-possible weight at the first iteration");
  table.add("TrackFinalStiffness", p.trackingOptions.finalStiffness, 1e-9, 1e9,
            "as-rigid-as-possible weight at the last iteration");
  table.add("TrackMaxDistance", p.trackingOptions.maxDistance, 0, 10,
            "correspondences farther apart are dropped (fraction of the mesh's box diagonal)");
  table.add("TrackMaxAngle", p.trackingOptions.maxAngle, 0, 180,
            "correspondences whose normals differ more are dropped (degrees)");
  table.add("WeldInput", p.weldInput,
            "InputMeshPattern: merge vertices at identical positions (atlas seams) first");
}

void checkReconParams(const ReconParams& p) {
  check(p.input.empty() != p.inputMeshPattern.empty(),
        "give exactly one of Input (-i) and InputMeshPattern; see --help");
  check(!p.output.empty(), "no output folder given (-o DIR); see --help");
  if (!p.inputMeshPattern.empty()) {
    checkFramePattern(p.inputMeshPattern, "InputMeshPattern");
    check(p.frameCount > 0, "InputMeshPattern needs FrameCount");
  }
  checkOutputFramePattern(p.outputMeshPattern, "OutputMeshPattern");
  check(p.volumeMin.empty() == p.volumeMax.empty(),
        "VolumeMin and VolumeMax must be given together");
  check(p.trackingOptions.finalStiffness <= p.trackingOptions.stiffness,
        "TrackFinalStiffness must not exceed TrackStiffness");
}

}  // namespace tdvo
