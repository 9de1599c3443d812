// Mesh files of any supported format, chosen by the file name's extension
// (docs/user-guide.md, "Mesh files"): .ply and .ply.gz are PLY, .gltf and .glb are glTF 2.0,
// anything else (.obj, .obj.gz, ...) is OBJ, as before.
#pragma once

#include <string>

#include "common/core/mesh.h"

namespace tdvo {

enum class MeshFileFormat { kObj, kPly, kGltf };

// The format of a mesh file by its name (case-insensitive; a trailing .gz is looked through for
// OBJ and PLY).
MeshFileFormat meshFileFormat(const std::string& path);

// Reads one mesh (one frame) with readObj, readPly or readGltf (frame 0 of a glTF file).
Mesh readMesh(const std::string& path);

// What 3dvo-dec writes per frame (--MeshFormat).
enum class MeshOutputFormat { kObj, kPly, kPlyAscii, kGltf, kGlb };

// The format a file name asks for: .ply (binary), .gltf, .glb, else OBJ.
MeshOutputFormat meshOutputFormat(const std::string& path);

// The file extension of a format (".obj", ".ply", ".gltf", ".glb").
const char* meshOutputExtension(MeshOutputFormat format);

// The bytes of a mesh file in `format` (formatObj, formatPly, formatGltf).
std::string formatMeshFile(const Mesh& mesh, MeshOutputFormat format);

// True when a frame pattern names one glTF file holding the whole sequence: it ends in .gltf or
// .glb and has no frame-number conversion (docs/user-guide.md, "A glTF animation as input").
bool isMeshAnimationFile(const std::string& pattern);

}  // namespace tdvo
