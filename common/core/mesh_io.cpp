#include "common/core/mesh_io.h"

#include <algorithm>
#include <cctype>

#include "common/core/gltf_io.h"
#include "common/core/obj_io.h"
#include "common/core/ply_io.h"

namespace tdvo {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

}  // namespace

MeshFileFormat meshFileFormat(const std::string& path) {
  std::string name = lower(path);
  if (endsWith(name, ".gltf") || endsWith(name, ".glb")) return MeshFileFormat::kGltf;
  if (endsWith(name, ".gz")) name.resize(name.size() - 3);
  if (endsWith(name, ".ply")) return MeshFileFormat::kPly;
  return MeshFileFormat::kObj;
}

Mesh readMesh(const std::string& path) {
  switch (meshFileFormat(path)) {
    case MeshFileFormat::kPly:
      return readPly(path);
    case MeshFileFormat::kGltf:
      return readGltf(path);
    case MeshFileFormat::kObj:
      break;
  }
  return readObj(path);
}

MeshOutputFormat meshOutputFormat(const std::string& path) {
  switch (meshFileFormat(path)) {
    case MeshFileFormat::kPly:
      return MeshOutputFormat::kPly;
    case MeshFileFormat::kGltf:
      return endsWith(lower(path), ".glb") ? MeshOutputFormat::kGlb : MeshOutputFormat::kGltf;
    case MeshFileFormat::kObj:
      break;
  }
  return MeshOutputFormat::kObj;
}

const char* meshOutputExtension(MeshOutputFormat format) {
  switch (format) {
    case MeshOutputFormat::kPly:
    case MeshOutputFormat::kPlyAscii:
      return ".ply";
    case MeshOutputFormat::kGltf:
      return ".gltf";
    case MeshOutputFormat::kGlb:
      return ".glb";
    case MeshOutputFormat::kObj:
      break;
  }
  return ".obj";
}

std::string formatMeshFile(const Mesh& mesh, MeshOutputFormat format) {
  switch (format) {
    case MeshOutputFormat::kPly:
      return formatPly(mesh, PlyEncoding::kBinaryLittleEndian);
    case MeshOutputFormat::kPlyAscii:
      return formatPly(mesh, PlyEncoding::kAscii);
    case MeshOutputFormat::kGltf:
      return formatGltf(mesh, GltfContainer::kGltf);
    case MeshOutputFormat::kGlb:
      return formatGltf(mesh, GltfContainer::kGlb);
    case MeshOutputFormat::kObj:
      break;
  }
  return formatObj(mesh);
}

bool isMeshAnimationFile(const std::string& pattern) {
  if (meshFileFormat(pattern) != MeshFileFormat::kGltf) return false;
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') continue;
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      ++i;
      continue;
    }
    return false;  // a conversion (checkFramePattern judges it)
  }
  return true;
}

}  // namespace tdvo
