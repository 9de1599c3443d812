// Mesh types shared by every part of 3DVO.
//
// A frame of a 3D video object is a triangle mesh. Geometry coding works on IntMesh, whose
// positions are integers on the sequence's grid (see grid.h); float positions (Mesh) appear
// only at the edges: reading input, writing output, rendering and metrics.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace tdvo {

using Vec3d = std::array<double, 3>;
using Vec3i = std::array<int32_t, 3>;
// Vertex indices of one triangle, counter-clockwise seen from outside.
using Triangle = std::array<uint32_t, 3>;

// What the OBJ and PLY readers say (a warning, common/core/warnings.h) when a file has a face of
// more than three corners: every mesh is a triangle mesh.
inline constexpr char kPolygonsSplit[] =
    "faces with more than three corners are split into triangles (a fan from each face's first "
    "corner)";

using Vec2f = std::array<float, 2>;
using Vec3f = std::array<float, 3>;

// The coordinates 3DVO takes (the mesh readers, frames given from memory): finite and at most
// kMaxCoordinate in magnitude, so that the difference of two, a span, stays finite.
constexpr double kMaxCoordinate = 1e300;

// Whether a finite coordinate lies beyond kMaxCoordinate, which a message says with
// `coordinateText(c) + kBeyondCoordinateRange` ("1e+301 is beyond ±1e300, ...").
inline bool isBeyondCoordinateRange(double c) {
  return std::isfinite(c) && std::fabs(c) > kMaxCoordinate;
}
constexpr const char* kBeyondCoordinateRange = " is beyond ±1e300, 3DVO's coordinate range";
// A coordinate in a message, to 6 significant digits ("1e+301").
inline std::string coordinateText(double c) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", c);
  return text;
}

// Where a texture coordinate's v = 0 lies in the image: its bottom row, as in OBJ and PLY
// (Wavefront's and OpenGL's convention), or its top row, as in glTF.
enum class UvOrigin : uint8_t { kBottom = 0, kTop = 1 };

// Texture coordinates and normals of a mesh, each a list of values and one index triangle per
// triangle of the mesh (corner c of triangle t takes uvs[uvTriangles[t][c]]), as OBJ's
// `f v/vt/vn` gives them. Per-vertex attributes (PLY, glTF) have index triangles equal to the
// mesh's triangles. Empty lists: the attribute is absent. Values are float32 as read (glTF's
// type; OBJ and PLY values are rounded to float once, on reading), so they survive the codec
// bit for bit (docs/user-guide.md, "Texture coordinates and normals").
struct MeshAttributes {
  std::vector<Vec2f> uvs;
  std::vector<Triangle> uvTriangles;
  std::vector<Vec3f> normals;
  std::vector<Triangle> normalTriangles;
  // Where v = 0 lies in the texture image. The readers set it (glTF: kTop), the stream
  // carries it (at_uv_origin), and each writer converts to its format's (v -> 1 - v): a
  // texture made for an OBJ shows the same way through the decoded glTF.
  UvOrigin uvOrigin = UvOrigin::kBottom;

  bool hasUvs() const { return !uvs.empty(); }
  bool hasNormals() const { return !normals.empty(); }
  bool empty() const { return !hasUvs() && !hasNormals(); }
  bool operator==(const MeshAttributes& o) const {
    return uvs == o.uvs && uvTriangles == o.uvTriangles && normals == o.normals &&
           normalTriangles == o.normalTriangles && (uvs.empty() || uvOrigin == o.uvOrigin);
  }
  bool operator!=(const MeshAttributes& o) const { return !(*this == o); }
};

// A triangle mesh with float positions.
struct Mesh {
  std::vector<Vec3d> positions;
  std::vector<Triangle> triangles;
  MeshAttributes attributes;  // optional UVs and normals
};

// A triangle mesh with integer positions on the grid (and the attributes of the frame it was
// made from or decoded for: they are not on the grid).
struct IntMesh {
  std::vector<Vec3i> positions;
  std::vector<Triangle> triangles;
  MeshAttributes attributes;
};

}  // namespace tdvo
