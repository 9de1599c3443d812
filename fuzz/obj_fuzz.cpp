// Fuzz target: the OBJ parser (parseObj), plus a property check: whatever it accepts, written
// back with formatObj, must parse to exactly the same mesh (positions, texture coordinates and
// normals bit for bit).
//
// The input is OBJ text. Seeds: frame 0 of each conformance input and fuzz/seeds/obj/.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "common/core/error.h"
#include "common/core/obj_io.h"
#include "common/core/warnings.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // What the reader leaves out it says (warnings.h): not on stderr at every input here.
  static const bool quiet = (tdvo::setWarningHandler([](const std::string&) {}), true);
  (void)quiet;
  const std::string text(reinterpret_cast<const char*>(data), size);
  tdvo::Mesh mesh;
  try {
    mesh = tdvo::parseObj(text, "fuzz.obj");
  } catch (const tdvo::Error&) {
    return 0;
  }
  const tdvo::Mesh again = tdvo::parseObj(tdvo::formatObj(mesh), "formatted.obj");
  const tdvo::MeshAttributes &a = mesh.attributes, &b = again.attributes;
  const bool same =
      again.triangles == mesh.triangles && again.positions.size() == mesh.positions.size() &&
      std::memcmp(again.positions.data(), mesh.positions.data(),
                  mesh.positions.size() * sizeof(tdvo::Vec3d)) == 0 &&
      a.uvTriangles == b.uvTriangles && a.normalTriangles == b.normalTriangles &&
      a.uvs.size() == b.uvs.size() && a.normals.size() == b.normals.size() &&
      std::memcmp(a.uvs.data(), b.uvs.data(), a.uvs.size() * sizeof(tdvo::Vec2f)) == 0 &&
      std::memcmp(a.normals.data(), b.normals.data(), a.normals.size() * sizeof(tdvo::Vec3f)) == 0;
  if (!same) {
    std::fprintf(stderr, "obj fuzz target: formatObj output does not parse back to the mesh\n");
    std::abort();
  }
  return 0;
}
