// Fuzz target: the OBJ parser (parseObj), plus a property check: whatever it accepts, written
// back with formatObj, must parse to exactly the same mesh (positions bit for bit).
//
// The input is OBJ text. Seeds: frame 0 of each conformance input and fuzz/seeds/obj/.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "common/core/error.h"
#include "common/core/obj_io.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  tdvo::Mesh mesh;
  try {
    mesh = tdvo::parseObj(text, "fuzz.obj");
  } catch (const tdvo::Error&) {
    return 0;
  }
  const tdvo::Mesh again = tdvo::parseObj(tdvo::formatObj(mesh), "formatted.obj");
  const bool same = again.triangles == mesh.triangles &&
                    again.positions.size() == mesh.positions.size() &&
                    std::memcmp(again.positions.data(), mesh.positions.data(),
                                mesh.positions.size() * sizeof(tdvo::Vec3d)) == 0;
  if (!same) {
    std::fprintf(stderr, "obj fuzz target: formatObj output does not parse back to the mesh\n");
    std::abort();
  }
  return 0;
}
