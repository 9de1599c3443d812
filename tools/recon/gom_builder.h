// Cuts a sequence of reconstructed surfaces (any connectivity) into GOMs of constant
// connectivity: each GOM's first frame is its own surface, decimated (the I mesh); each later
// frame is the I mesh deformed to fit that frame (MeshTracker). In the adaptive mode a frame
// whose fit is worse than TrackMaxError (symmetric Hausdorff distance over the frame's
// bounding-box diagonal) starts a new GOM instead, as does a frame that would make the GOM
// longer than GOMSize; in the fixed mode every GOM has GOMSize frames whatever the error.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "common/core/mesh.h"
#include "tools/recon/recon_params.h"
#include "tools/recon/tracking.h"

namespace tdvo {

struct GomStep {
  Mesh mesh;                 // the output frame
  int gom = 0;               // index of its GOM
  bool iMesh = false;        // first frame of its GOM
  bool rejectedFit = false;  // a fit was tried but its error was too large (new GOM)
  double fitHausdorff = 0;   // symmetric Hausdorff distance of `mesh` to the frame's surface
  double fitMean = 0;        // symmetric mean distance, same convention as metrics.h
  double diagonal = 0;       // bounding-box diagonal of the frame's surface
  FitStats fit;              // of the accepted or rejected fit (zero for I meshes)
  double decimationSeconds = 0, trackingSeconds = 0, distanceSeconds = 0;
};

class GomBuilder {
 public:
  explicit GomBuilder(const ReconParams& params);
  ~GomBuilder();

  // The next frame's surface. `voxelSize` scales DecimationMaxError (0: the bound is off).
  GomStep add(const Mesh& surface, double voxelSize);

  // GOMs so far as (first output frame, frame count).
  const std::vector<std::pair<int, int>>& goms() const { return goms_; }

 private:
  const ReconParams& params_;
  std::unique_ptr<MeshTracker> tracker_;
  std::vector<std::pair<int, int>> goms_;
  int frames_ = 0;
};

}  // namespace tdvo
