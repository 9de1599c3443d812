// Marching cubes (Lorensen & Cline 1987): the iso-surface of a scalar field sampled at the
// corners of a regular grid, one cube at a time.
//
// Cube numbering used by this file (and by the case table):
// - corner c (0 … 7) sits at offset (c & 1, (c >> 1) & 1, (c >> 2) & 1) from the cube's lowest
//   corner;
// - edge e (0 … 11) joins two corners that differ in one axis: edges 0–3 run along x, 4–7
//   along y, 8–11 along z (kCubeEdgeCorners lists them).
// A corner is *inside* when its value is > 0; the case index has bit c set for each inside
// corner. The surface passes through every edge whose corners differ.
//
// The case table is derived rather than typed in: for each of the 256 cases the crossings on
// each cube face are paired by one fixed rule — on an ambiguous face (two diagonal corners
// inside, the other two outside) the inside corners are separated — and the face segments are
// chained into closed loops. Each loop is split into triangles by diagonals between crossings
// on different faces only (a diagonal inside a face could meet the neighbouring cube's
// triangles there). Since the pairing depends only on the four corner signs of a face, the two
// cubes sharing a face cut it the same way, so the surface is closed, with no cracks (the
// classic 15-case table lacks this guarantee; see docs/reconstruction.md). Triangles are wound
// counter-clockwise seen from outside, i.e. their normals point from the inside corners to the
// outside ones.
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "common/core/mesh.h"

namespace tdvo {

// The corners of each cube edge, lower corner first.
extern const std::array<std::array<int, 2>, 12> kCubeEdgeCorners;

// The triangles of one case, as edge indices: each triangle's corners lie on three edges.
using CubeCaseTriangles = std::vector<std::array<uint8_t, 3>>;

// The table for all 256 cases (built once, on first use; thread-safe).
const std::array<CubeCaseTriangles, 256>& marchingCubesTable();

// The case index of a cube from its eight corner values (bit c set when value[c] > 0).
inline int cubeCase(const std::array<float, 8>& value) {
  int c = 0;
  for (int k = 0; k < 8; ++k)
    if (value[k] > 0) c |= 1 << k;
  return c;
}

// Builds one indexed mesh from cubes of a grid given one at a time (in any order, each at most
// once): a vertex per crossed grid edge, shared by all cubes around that edge. Vertices are
// placed at the linear zero crossing of the values along the edge, kept 0.1 % of the edge away
// from its corners so that no two vertices coincide.
class MarchingCubesMesher {
 public:
  // Grid corner (i, j, k) is at origin + step · (i, j, k); indices run from 0 to `corners` − 1
  // per axis.
  MarchingCubesMesher(const Vec3d& origin, double step, int64_t corners);

  // Adds the triangles of the cube whose lowest corner is (i, j, k), given its corner values.
  void addCube(int64_t i, int64_t j, int64_t k, const std::array<float, 8>& value);

  Mesh& mesh() { return mesh_; }

 private:
  Vec3d origin_;
  double step_;
  int64_t corners_;
  Mesh mesh_;
  std::unordered_map<uint64_t, uint32_t> edgeVertex_;
};

}  // namespace tdvo
