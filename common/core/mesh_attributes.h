// Work on a mesh's texture coordinates and normals (MeshAttributes, mesh.h) that more than one
// part of 3DVO needs: per-vertex attributes for the file formats that only have those (PLY,
// glTF), and the normals a decoder computes from decoded geometry (docs/bitstream.md,
// "Attributes", at_normal_mode 3).
#pragma once

#include <cstddef>
#include <vector>

#include "common/core/mesh.h"

namespace tdvo {

// `a`'s texture coordinates with v measured from `origin`: v -> 1 - v (in float) when `a`'s
// origin is the other one, else as they are. The writers use it for their format's origin.
std::vector<Vec2f> uvsFrom(const MeshAttributes& a, UvOrigin origin);
// Converts `a`'s texture coordinates to `origin` (uvsFrom) and sets a.uvOrigin.
void setUvOrigin(MeshAttributes& a, UvOrigin origin);

// True when every present attribute is per vertex: its index triangles are the mesh's
// triangles and it has one value per vertex.
bool attributesPerVertex(const Mesh& mesh);

// `mesh` with per-vertex attributes, for PLY and glTF output. Where a vertex's corners refer to
// different texture coordinates or normals (a seam), the vertex is split: its first corner (in
// triangle order) keeps the original vertex, and each further combination of (texture
// coordinate, normal) at it becomes a copy of the vertex appended after the original vertices,
// in the order the corners meet them; the triangles then use the copies. A vertex no triangle
// uses takes value 0 unless the attribute was per vertex already. Returns the number of copies
// in `copies` (when given). Positions and triangle order are kept; nothing is dropped.
Mesh splitAttributeSeams(const Mesh& mesh, size_t* copies = nullptr);

// Per-vertex normals of a mesh on the grid, as a decoder computes them (normative,
// docs/bitstream.md, at_normal_mode 3): the sum over the triangles at each vertex of the
// triangle's cross product (b - a) x (c - a), exact in integers, then divided by its length in
// double and rounded to float; (0, 0, 0) where the sum is zero.
std::vector<Vec3f> computeVertexNormals(const std::vector<Vec3i>& positions,
                                        const std::vector<Triangle>& triangles);

}  // namespace tdvo
