#include "tools/recon/gom_builder.h"

#include <chrono>
#include <cmath>

#include "tools/eval/metrics.h"
#include "tools/recon/surface_processing.h"

namespace tdvo {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void measure(const Mesh& surface, GomStep& step) {
  const auto start = std::chrono::steady_clock::now();
  const SurfaceDistance d = surfaceDistance(surface, step.mesh);
  step.fitHausdorff = d.hausdorff();
  step.fitMean = d.mean();
  step.distanceSeconds += secondsSince(start);
}

}  // namespace

GomBuilder::GomBuilder(const ReconParams& params) : params_(params) {}
GomBuilder::~GomBuilder() = default;

GomStep GomBuilder::add(const Mesh& surface, double voxelSize) {
  GomStep step;
  BoundingBox box;
  box.extend(surface.positions);
  step.diagonal = box.diagonal();
  const int frame = frames_++;

  if (params_.tracking && tracker_ && goms_.back().second < params_.gomSize) {
    step.fit = tracker_->fit(surface);
    step.trackingSeconds = step.fit.seconds;
    step.mesh = tracker_->current();
    measure(surface, step);
    // (A fit whose error overflowed, e.g. on coordinates near 1e300, is no fit.)
    if (params_.gomMode == GomMode::fixed ||
        (std::isfinite(step.fitHausdorff) &&
         step.fitHausdorff <= params_.trackMaxError * step.diagonal)) {
      step.gom = static_cast<int>(goms_.size()) - 1;
      ++goms_.back().second;
      return step;
    }
    step.rejectedFit = true;
  }

  // A new GOM: this frame's surface, decimated, is its I mesh.
  auto start = std::chrono::steady_clock::now();
  step.mesh = surface;
  if (params_.decimationFaces > 0) {
    DecimationOptions options;
    options.targetFaces = static_cast<size_t>(params_.decimationFaces);
    options.maxNormalDeviation = params_.decimationMaxAngle;
    options.maxError = params_.decimationMaxError * voxelSize * voxelSize;
    decimateMesh(step.mesh, options);
  }
  step.decimationSeconds = secondsSince(start);
  measure(surface, step);
  step.iMesh = true;
  step.gom = static_cast<int>(goms_.size());
  goms_.emplace_back(frame, 1);
  if (params_.tracking)
    tracker_ = std::make_unique<MeshTracker>(step.mesh, params_.trackingOptions);
  return step;
}

}  // namespace tdvo
