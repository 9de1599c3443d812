// The whole of 3dvo-recon: input (a multi-view dataset, or an OBJ sequence to track), per frame
// reconstruction and GOM building, and the outputs in the Output folder:
//
//   %04d.obj            the time-consistent mesh sequence (OutputMeshPattern), from 0
//   goms.txt            the GOM list: "first count" per line (common/core/gom_list.h)
//   encode.cfg          3dvo-enc input keys for the whole sequence as one stream: GOMSize when
//                       the GOMs have one length, else GOMListFile naming goms.txt
//   encode/gom_%04d.cfg 3dvo-enc keys coding one GOM as a stream of its own
//   report.txt          summary and per-frame table
//   frames.csv          the per-frame table as CSV
//   silhouettes/, hull/ (WriteSilhouettes, WriteHull)
//
// All files are staged and renamed together at the end: a failed run leaves no output under
// the final names. docs/reconstruction.md describes every file.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "common/core/gom_list.h"
#include "tools/recon/recon_params.h"

namespace tdvo {

// One output frame's record (the columns of report.txt and frames.csv). Distances are in world
// units; −1 marks what was not measured.
struct FrameRecord {
  int frame = 0;   // output frame number
  int source = 0;  // dataset frame index or input file number
  int gom = 0;
  bool iMesh = false;
  bool rejectedFit = false;
  // Seconds per stage.
  double silhouetteSeconds = 0, carvingSeconds = 0, surfaceSeconds = 0, smoothingSeconds = 0,
         decimationSeconds = 0, trackingSeconds = 0, metricSeconds = 0, totalSeconds = 0;
  // Counts.
  size_t cellsJudged = 0, surfaceVoxels = 0, hullTriangles = 0, components = 0;
  size_t vertices = 0, triangles = 0;
  double voxelSize = -1, hullVolume = -1;
  // Silhouette agreement: IoU of the output mesh's reprojection with each used silhouette.
  double iouMean = -1, iouMin = -1;
  // Fit of the output mesh to the frame's reconstruction (the decimation error for I meshes).
  double fitHausdorff = 0, fitMean = 0, diagonal = 0;
  // Distance to the dataset's ground-truth mesh, when it has one.
  double truthMean = -1, truthHausdorff = -1, truthDiagonal = -1;
  // PhotoRefine: seconds, vertices given a target, mean |displacement| (voxels).
  double photoSeconds = 0;
  size_t photoTargets = 0;
  double photoDisplacement = 0;
};

struct ReconResult {
  std::vector<FrameRecord> frames;
  GomList goms;                          // (first output frame, count)
  std::vector<std::string> cameras;      // used camera names
  std::vector<std::vector<double>> iou;  // per frame, per used camera
  std::string calibrationText;           // RefineCalibration's report lines
};

// Runs the reconstruction with `params` (checked first), printing one line per frame and a
// summary to `log` (may be null), progress to stderr when it is a terminal.
ReconResult runReconstruction(const ReconParams& params, std::FILE* log);

}  // namespace tdvo
