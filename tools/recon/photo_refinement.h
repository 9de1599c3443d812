// Photo-consistency refinement of a visual hull's surface (docs/reconstruction.md,
// "Photo-consistency refinement").
//
// A visual hull is the largest shape the silhouettes allow: concavities are filled and, with
// few cameras, the outline bulges between them. The camera images say more: at the true surface
// the cameras that see a point agree on its colour. Each iteration:
//   1. vertex normals (area-weighted) and, per camera, the depth map of the current mesh
//      (renderDepth); a vertex is visible in a camera when it faces it (normal within 75° of
//      the direction to the camera) and is not behind the depth map by more than 1.5 voxels;
//   2. for each vertex seen by at least `minCameras` cameras, candidate depths along its normal
//      from −inward to +outward voxels (in `step`s, measured from where the vertex started) are
//      scored by photo-consistency: a 5 × 5 patch in the tangent plane, one pixel of the most
//      frontal camera apart, is projected into every camera that sees the vertex (grey levels,
//      bilinear, lens distortion included); the score is the mean normalised cross-correlation
//      of the frontal camera's patch with each other camera's. Candidates outside the visual
//      hull (a negative CarvingView signed distance in any view that sees them) are skipped;
//   3. the best depth becomes the vertex's target when its score reaches `minScore` and beats
//      the current position's; the displacement field is then regularised by `smoothing`
//      Jacobi iterations of d ← (w·target + mean of the neighbours' d) / (w + 1) (w = 1 for a
//      vertex with a target, 0.1 towards 0 for one without), and the vertices move along their
//      normals. A move that would leave the hull is undone.
#pragma once

#include <cstddef>
#include <vector>

#include "common/core/mesh.h"
#include "common/views/camera.h"
#include "common/views/image.h"
#include "tools/recon/carving_view.h"

namespace tdvo {

struct PhotoRefineOptions {
  int iterations = 2;
  double inward = 3;      // voxels: search range inwards along the normal
  double outward = 0.5;   // voxels: outwards (the hull bounds it too)
  double step = 0.5;      // voxels between candidates
  double minScore = 0.5;  // least NCC of the best candidate for a vertex to get a target
  int smoothing = 10;     // Jacobi iterations regularising the displacements
  int minCameras = 2;     // cameras that must see a vertex
};

struct PhotoRefineStats {
  size_t vertices = 0;          // vertices of the surface
  size_t targets = 0;           // vertices given a target (last iteration)
  double meanDisplacement = 0;  // mean |displacement| at the end (voxels)
  double meanScoreBefore = 0;   // mean NCC of the vertices with targets, first iteration, t = 0
  double meanScoreAfter = 0;    // ... at the chosen depth
  double seconds = 0;
};

// Refines `surface` (closed, outward-facing triangles) in place. `cameras` and `images` (RGB,
// RGBA or grey, each the camera's own image) are the views to compare; `hull` are the carving
// views that bound the result (may be empty: no bound); `voxel` is the voxel size.
PhotoRefineStats photoRefine(Mesh& surface, const std::vector<Camera>& cameras,
                             const std::vector<Image>& images, const std::vector<CarvingView>& hull,
                             double voxel, const PhotoRefineOptions& options);

}  // namespace tdvo
