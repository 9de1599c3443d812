// Wavefront OBJ reading and writing (v, vt, vn and f lines).
#pragma once

#include <cstddef>
#include <string>

#include "common/core/mesh.h"

namespace tdvo {

// Limits of the OBJ reader (docs/robustness.md, "Input files"): beyond them it throws Error
// naming the file and line. The file is parsed as it is read (decompressed), so a file of any
// size takes memory for its mesh and one line only.
constexpr size_t kMaxObjLineBytes = size_t{1} << 20;
constexpr size_t kMaxObjVertices = size_t{1} << 26;   // 4 x the codec's 2^24
constexpr size_t kMaxObjTriangles = size_t{1} << 27;  // 4 x the codec's 2^25

// Reads an OBJ file; a name ending in .gz (or any gzip content) is decompressed on the fly.
// Takes `v x y z` and `f a b c ...` lines (a/b/c index forms and negative indices allowed);
// polygons with more than three corners are triangulated as a fan around their first corner.
// `vt u v` and `vn x y z` lines with the faces' `v/vt`, `v//vn` or `v/vt/vn` corner indices are
// the mesh's attributes (per corner, mesh.h; read as float) when every face corner gives the
// index and the file has the values (an index beyond them is an error); otherwise that
// attribute is left out (a mesh has it at every corner or not at all). Groups, materials and
// comments are ignored. Throws Error naming the file and line for anything malformed (bad numbers,
// indices out of range, faces with fewer than three corners, unknown statements), for a mesh
// without faces and for one whose every face has a repeated vertex. Triangles with a repeated
// vertex among proper ones are kept (3dvo-enc drops them, counting them in a warning).
Mesh readObj(const std::string& path);

// Parses OBJ text; `name` is used in error messages only.
Mesh parseObj(const std::string& text, const std::string& name);

// Writes `mesh` as OBJ text, positions in the shortest decimal form that reads back to the
// same double, texture coordinates and normals (when present) to the same float, faces as
// `v/vt/vn` (or `v/vt`, `v//vn`). The file is written under a temporary name and renamed when
// complete.
void writeObj(const std::string& path, const Mesh& mesh);

// The OBJ text writeObj writes.
std::string formatObj(const Mesh& mesh);

}  // namespace tdvo
