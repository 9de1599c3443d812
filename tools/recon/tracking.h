// Tracking into GOMs: the mesh of a GOM's first frame (its I mesh) is deformed, frame by frame,
// to follow the reconstructions of the next frames, so that all frames of a GOM share one
// connectivity (what the codec's P meshes need).
//
// Fitting one frame starts from the previous frame's pose, moved rigidly first (point-to-plane
// rigid ICP on a sample of the vertices: global motion is taken out before any vertex moves on
// its own), then
// non-rigid ICP with as-rigid-as-possible regularisation (Sorkine & Alexa 2007), repeated
// `iterations` times:
//   1. correspondences both ways: each vertex to its closest point on the target surface, and
//      each target vertex to its closest point on the deforming surface (a triangle and its
//      barycentric coordinates). Pairs farther apart than maxDistance or whose normals differ
//      by more than maxAngle are dropped;
//   2. local step: per vertex the rotation R_i that best maps its rest one-ring edges onto the
//      current ones (SVD of the 3 × 3 covariance);
//   3. global step: the positions minimising
//        stiffness · Σ_i Σ_j∈N(i) |(x_i − x_j) − ½ (R_i + R_j)(p_i − p_j)|²
//        + Σ_i |x_i − c_i|² + (V / S) Σ_s |Σ_k β_sk x_sk − q_s|²
//      (p the rest pose, c_i the vertex correspondences, q_s the S target samples with their
//      barycentric weights β on the deforming mesh), a sparse symmetric positive definite
//      system solved by Eigen's SimplicialLDLT for x, y and z at once.
// The stiffness is relaxed geometrically from `stiffness` to `finalStiffness` over the
// iterations (coarse alignment first, detail last).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "common/core/mesh.h"

namespace tdvo {

struct TrackingOptions {
  int rigidIterations = 10;     // rigid ICP iterations first (global motion); 0: none
  int iterations = 12;          // non-rigid ICP iterations per frame
  double stiffness = 10;        // ARAP weight at the first iteration
  double finalStiffness = 0.1;  // … and at the last
  double maxDistance = 0.05;    // correspondences farther apart are dropped (× the rest
                                // mesh's bounding-box diagonal)
  double maxAngle = 60;         // degrees between the normals of a correspondence
};

struct FitStats {
  size_t vertexPairs = 0;  // accepted vertex → target correspondences (last iteration)
  size_t targetPairs = 0;  // accepted target → mesh correspondences (last iteration)
  double seconds = 0;
};

class MeshTracker {
 public:
  // `rest`: the GOM's first mesh; it is also the starting pose. Throws Error when it has no
  // triangles.
  MeshTracker(const Mesh& rest, const TrackingOptions& options);
  ~MeshTracker();
  MeshTracker(MeshTracker&&) noexcept;
  MeshTracker& operator=(MeshTracker&&) noexcept;

  // Deforms the current pose to fit `target` (any connectivity) and returns statistics; the
  // result is current(). Throws Error when the target has no triangles.
  FitStats fit(const Mesh& target);

  // The current pose: the rest mesh's connectivity with the fitted positions.
  const Mesh& current() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace tdvo
