// Mesh types shared by every part of 3DVO.
//
// A frame of a 3D video object is a triangle mesh. Geometry coding works on IntMesh, whose
// positions are integers on the sequence's grid (see grid.h); float positions (Mesh) appear
// only at the edges: reading input, writing output, rendering and metrics.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace tdvo {

using Vec3d = std::array<double, 3>;
using Vec3i = std::array<int32_t, 3>;
// Vertex indices of one triangle, counter-clockwise seen from outside.
using Triangle = std::array<uint32_t, 3>;

// A triangle mesh with float positions.
struct Mesh {
  std::vector<Vec3d> positions;
  std::vector<Triangle> triangles;
};

// A triangle mesh with integer positions on the grid.
struct IntMesh {
  std::vector<Vec3i> positions;
  std::vector<Triangle> triangles;
};

}  // namespace tdvo
