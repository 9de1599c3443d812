// The integer geometry grid of a sequence.
//
// The sequence header defines one axis-aligned grid for all frames: an origin, one step for all
// three axes, and a bit depth. Coordinates on the grid are integers in [0, 2^bits - 1]. The
// step is chosen either so that the largest extent of the sequence's bounding box spans the full
// range (GridFit sequence) or so that the object itself, the largest extent of any one frame,
// spans 2^GridBits - 1 steps, the grid getting the further bits the object's path needs
// (GridFit object).
// All normative geometry (prediction, reconstruction, hashes) is in these integers; dequantised
// float positions exist only for output.
#pragma once

#include <cstdint>
#include <vector>

#include "common/core/mesh.h"

namespace tdvo {

// How the encoder sets the grid's step (cfg key GridFit).
enum class GridFit { kSequence, kObject };

struct Grid {
  static constexpr int kMinBits = 8;
  static constexpr int kMaxBits = 20;

  Vec3d origin{0, 0, 0};
  double step = 1.0;
  int bits = 12;

  // The grid for a bounding box [lo, hi]. A box of zero extent gets step 1; an extent so small
  // that the step would not be a normal double (below 2.2e-308) is an Error.
  static Grid fromBounds(const Vec3d& lo, const Vec3d& hi, int bits);
  // The grid for bounds [lo, hi] whose step is set by the object instead: `objectExtent` (the
  // largest extent of any one frame, at most the bounds' largest extent) spans
  // 2^precisionBits - 1 steps, and the grid has the fewest bits in [precisionBits, kMaxBits]
  // that cover the bounds at that step. Bounds too large for kMaxBits at that step get the
  // kMaxBits grid of fromBounds (a coarser step than asked; the caller can compare `step`).
  static Grid fitObject(const Vec3d& lo, const Vec3d& hi, double objectExtent, int precisionBits);
  // The largest extent of the box [lo, hi] over the three axes.
  static double largestExtent(const Vec3d& lo, const Vec3d& hi);
  // The size that 2^bits - 1 steps span on the grid of `fit` for bounds [lo, hi]: the bounds'
  // largest extent (GridFit sequence, fromBounds), or `objectExtent` when it is positive and
  // smaller (GridFit object, fitObject; before its fallback to the kMaxBits grid).
  static double spannedSize(const Vec3d& lo, const Vec3d& hi, double objectExtent, GridFit fit);

  int32_t maxCoordinate() const { return (int32_t{1} << bits) - 1; }

  // Nearest grid point, clamped into the grid (clamping only matters for positions outside the
  // bounds the grid was made from).
  Vec3i quantise(const Vec3d& p) const;
  Vec3d dequantise(const Vec3i& q) const;

  IntMesh quantise(const Mesh& mesh) const;
  Mesh dequantise(const IntMesh& mesh) const;
};

// Bounding box of many meshes; throws Error if there are no positions.
void boundingBox(const std::vector<Mesh>& meshes, Vec3d& lo, Vec3d& hi);

}  // namespace tdvo
