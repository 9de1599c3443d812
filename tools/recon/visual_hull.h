// Octree shape-from-silhouette: the visual hull of a set of silhouettes and its surface.
//
// The capture volume is a cube split into 2^depth voxels per axis. Starting from the whole
// cube, each cell is judged by every view (CarvingView::judgeBox, a conservative test on the
// projected cell's bounding rectangle):
//   - outside when one view sees it on background only, or when fewer than `minViews` views
//     can see any of it;
//   - inside when no view is partial and at least `minViews` views see all of it on object
//     pixels;
//   - partial otherwise, and split into its eight children down to the voxel level.
// A view that judges a cell inside-and-seen or unseen judges all its children the same way and
// is not asked again below it. Partial voxels carry the surface: the hull's signed distance is
// sampled at their corners (the smallest of the views' signed distances, CarvingView::
// signedDistance) and marching cubes places each surface vertex where that distance changes
// sign along a voxel edge, so vertices land between voxel corners rather than at edge midpoints.
// Corners on the cube's faces are forced outside, so the surface is always closed. With a clip
// box, cells outside it are outside, cells not strictly inside it are partial, and the corner
// value is also limited by the signed distance to the box.
#pragma once

#include <cstddef>
#include <vector>

#include "common/core/mesh.h"
#include "tools/recon/carving_view.h"

namespace tdvo {

// An axis-aligned cube: lowest corner and edge length.
struct CaptureCube {
  Vec3d origin = {0, 0, 0};
  double size = 1;
};

struct HullOptions {
  int depth = 8;     // octree depth: 2^depth voxels per axis
  int minViews = 2;  // a point must be seen by at least this many views to be kept
  // An optional box the hull is cut to (e.g. a known bounding box, or a floor): it acts like one
  // more view, and its faces become part of the surface where the hull reaches them.
  bool clip = false;
  Vec3d clipLo = {0, 0, 0}, clipHi = {0, 0, 0};
};

struct HullResult {
  Mesh surface;               // marching cubes mesh (watertight, outward normals)
  double voxelSize = 0;       // edge of a voxel
  size_t cellsJudged = 0;     // octree cells visited (all levels)
  size_t insideCells = 0;     // cells found inside (all levels)
  size_t surfaceVoxels = 0;   // partial voxels at the finest level
  double insideVolume = 0;    // volume of the inside cells (partial voxels not counted)
  double carvingSeconds = 0;  // octree carving
  double surfaceSeconds = 0;  // corner distances and marching cubes
};

// Carves the hull in `cube` from `views` and extracts its surface.
HullResult carveVisualHull(const std::vector<CarvingView>& views, const CaptureCube& cube,
                           const HullOptions& options);

// The cube to carve: a first guess (the clip box's bounding cube when options.clip is set; else
// a cube around the point nearest to all optical axes, reaching three quarters of the way to
// the nearest camera), then two coarse carvings (depth 6, with options.minViews and the clip
// box) that shrink it to the occupied cells plus a margin of `margin` × the hull's largest
// extent on every side. Throws Error when nothing survives the carving (the silhouettes do not
// agree on any region).
CaptureCube estimateCaptureCube(const std::vector<CarvingView>& views, const HullOptions& options,
                                double margin);

// The bounding box of the cells a carving keeps (inside or partial), at options.depth; empty
// (lo > hi) when nothing is kept.
void occupiedBounds(const std::vector<CarvingView>& views, const CaptureCube& cube,
                    const HullOptions& options, Vec3d& lo, Vec3d& hi);

// Volume enclosed by a closed, consistently oriented mesh (divergence theorem).
double enclosedVolume(const Mesh& mesh);

}  // namespace tdvo
