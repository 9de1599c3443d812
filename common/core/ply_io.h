// PLY (Stanford polygon file) reading and writing: vertex positions and faces.
//
// The reader is a small streaming parser of its own rather than OpenMesh's (docs/user-guide.md,
// "Mesh files", says why): the vertices and triangles come out exactly in the file's order,
// triangles with a repeated vertex are kept, and memory grows with what the file holds, not with
// what its header declares.
#pragma once

#include <cstddef>
#include <string>

#include "common/core/mesh.h"

namespace tdvo {

// Limits of the PLY reader (docs/robustness.md, "Input files"): beyond them it throws Error
// naming the file and the header line, body line (ascii) or byte offset (binary).
constexpr size_t kMaxPlyHeaderBytes = size_t{1} << 20;
constexpr size_t kMaxPlyLineBytes = size_t{1} << 20;   // an ascii body line
constexpr size_t kMaxPlyListLength = size_t{1} << 16;  // entries of one list property
constexpr size_t kMaxPlyVertices = size_t{1} << 26;    // as OBJ: 4 x the codec's 2^24
constexpr size_t kMaxPlyTriangles = size_t{1} << 27;   // as OBJ: 4 x the codec's 2^25
constexpr size_t kMaxPlyProperties = 256;              // properties of one element

// Reads a PLY file (format ascii, binary_little_endian or binary_big_endian, version 1.0); a
// gzip-compressed file (.ply.gz, or any gzip content) is decompressed on the fly. The `vertex`
// element's x, y and z (any numeric type) are the positions; the `face` element's
// `vertex_indices` (or `vertex_index`) list gives the faces, polygons triangulated as a fan
// around their first corner (as OBJ's). Every other property and element is read past and
// ignored, except the vertex's texture coordinates (u and v, or s and t, texture_u and
// texture_v, texture_s and texture_t) and normal (nx, ny, nz), which become the mesh's
// per-vertex attributes (mesh.h; read as float). Throws Error naming the file and the header line,
// ascii line or binary byte offset for anything malformed, for a file without vertices or faces and
// for one whose every face has a repeated vertex; triangles with a repeated vertex among proper
// ones are kept.
Mesh readPly(const std::string& path);

// Parses PLY data held in memory; `name` is used in error messages only.
Mesh parsePly(const std::string& data, const std::string& name);

enum class PlyEncoding { kBinaryLittleEndian, kAscii };

// The PLY data of `mesh`: x, y, z as double (positions exactly as held), then, when present,
// u, v and nx, ny, nz as float, faces as a list of uchar count and int indices. Attributes
// with seams (corners of one vertex with different values) are made per vertex by
// splitAttributeSeams (mesh_attributes.h): copies of such vertices follow the original
// vertices, and a header comment says how many. Binary little-endian by default.
std::string formatPly(const Mesh& mesh, PlyEncoding encoding = PlyEncoding::kBinaryLittleEndian);

// Writes formatPly(mesh, encoding) atomically (a temporary name renamed when complete).
void writePly(const std::string& path, const Mesh& mesh,
              PlyEncoding encoding = PlyEncoding::kBinaryLittleEndian);

}  // namespace tdvo
