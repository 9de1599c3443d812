// Fuzz target: the PLY reader (parsePly), plus a property check: whatever it accepts, written
// back with formatPly (binary and ascii), must parse to exactly the same mesh (positions bit for
// bit, triangles by index).
//
// The input is PLY data. Seeds: frame 0 of each conformance input as binary little-endian and
// ascii PLY, and a big-endian file with skipped properties and elements (fuzz_make_corpus).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "common/core/error.h"
#include "common/core/ply_io.h"
#include "fuzz/fuzz_support.h"

namespace {

bool same(const tdvo::Mesh& a, const tdvo::Mesh& b) {
  return a.triangles == b.triangles && a.positions.size() == b.positions.size() &&
         std::memcmp(a.positions.data(), b.positions.data(),
                     a.positions.size() * sizeof(tdvo::Vec3d)) == 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  tdvo::Mesh mesh;
  try {
    mesh = tdvo::parsePly(bytes, "fuzz.ply");
  } catch (const tdvo::Error&) {
    return 0;
  }
  for (tdvo::PlyEncoding e : {tdvo::PlyEncoding::kBinaryLittleEndian, tdvo::PlyEncoding::kAscii})
    if (!same(tdvo::parsePly(tdvo::formatPly(mesh, e), "formatted.ply"), mesh)) {
      std::fprintf(stderr, "ply fuzz target: formatPly output does not parse back to the mesh\n");
      std::abort();
    }
  return 0;
}
