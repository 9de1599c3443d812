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
  // Bit for bit (NaN payloads and -0 included); empty lists may have null data, which memcmp
  // must not be given.
  auto sameBits = [](const auto& x, const auto& y) {
    return x.size() == y.size() &&
           (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0);
  };
  const bool same = again.triangles == mesh.triangles &&
                    again.positions.size() == mesh.positions.size() &&
                    sameBits(again.positions, mesh.positions) && a.uvTriangles == b.uvTriangles &&
                    a.normalTriangles == b.normalTriangles && sameBits(a.uvs, b.uvs) &&
                    sameBits(a.normals, b.normals);
  if (!same) {
    std::fprintf(stderr, "obj fuzz target: formatObj output does not parse back to the mesh\n");
    std::abort();
  }
  return 0;
}
