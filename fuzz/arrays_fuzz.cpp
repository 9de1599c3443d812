// Fuzz target: the Python module's frame reader (tools/python/frame_arrays.h), which reads the
// numpy arrays given to tdvo.encode, on arrays of every element type, shape and layout numpy
// can hand it; plus a property check: whatever it accepts has the declared vertices, finite
// coordinates and indices in range.
//
// Input: a 9-byte header, then the elements of both arrays.
//   byte 0, 1   positions' and triangles' element type: kElements[byte % 13]
//   byte 2, 3   their column counts, byte % 5 (3 is valid)
//   byte 4      layout bits: 1 positions column-major, 2 triangles column-major, 4 positions'
//               rows reversed (negative stride), 8 triangles' rows reversed
//   bytes 5-8   the positions' row count (u32, little-endian), cut to what the data holds
//   then        the positions' elements (rows x columns), then the triangles' (as many whole
//               rows as the rest holds)
// Seeds (fuzz_make_corpus): frame 0 of each conformance input as float64 positions and uint32
// triangles.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "common/core/error.h"
#include "fuzz/fuzz_support.h"
#include "tools/python/frame_arrays.h"

namespace {

struct Element {
  char kind;
  int size;
  const char* name;
};
constexpr Element kElements[13] = {{'f', 4, "float32"}, {'f', 8, "float64"}, {'i', 1, "int8"},
                                   {'i', 2, "int16"},   {'i', 4, "int32"},   {'i', 8, "int64"},
                                   {'u', 1, "uint8"},   {'u', 2, "uint16"},  {'u', 4, "uint32"},
                                   {'u', 8, "uint64"},  {'f', 2, "float16"}, {'c', 8, "complex64"},
                                   {'b', 1, "bool"}};

// A rows x columns view of `data` with the given layout bits (column-major, reversed rows).
tdvo::python::ArrayView view(const Element& e, int64_t rows, int64_t columns, bool columnMajor,
                             bool reversed, const uint8_t* data) {
  tdvo::python::ArrayView v;
  v.kind = e.kind;
  v.itemSize = e.size;
  v.dtypeName = e.name;
  v.shape = {rows, columns};
  v.strides = columnMajor ? std::vector<int64_t>{e.size, rows * e.size}
                          : std::vector<int64_t>{columns * e.size, e.size};
  v.data = data;
  if (reversed && rows > 0) {
    v.data += (rows - 1) * v.strides[0];
    v.strides[0] = -v.strides[0];
  }
  return v;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 9) return 0;
  const Element& pe = kElements[data[0] % 13];
  const Element& te = kElements[data[1] % 13];
  const int64_t pc = data[2] % 5, tc = data[3] % 5;
  const uint8_t layout = data[4];
  const uint64_t declared = uint64_t{data[5]} | uint64_t{data[6]} << 8 | uint64_t{data[7]} << 16 |
                            uint64_t{data[8]} << 24;
  const uint8_t* elements = data + 9;
  const size_t bytes = size - 9;
  const int64_t pRowBytes = pc * pe.size, tRowBytes = tc * te.size;
  const int64_t pr =
      pRowBytes == 0 ? 0 : static_cast<int64_t>(std::min<uint64_t>(declared, bytes / pRowBytes));
  const size_t rest = bytes - static_cast<size_t>(pr * pRowBytes);
  const int64_t tr = tRowBytes == 0 ? 0 : static_cast<int64_t>(rest / tRowBytes);
  const auto positions = view(pe, pr, pc, layout & 1, layout & 4, elements);
  const auto triangles = view(te, tr, tc, layout & 2, layout & 8, elements + pr * pRowBytes);
  tdvo::Mesh mesh;
  try {
    mesh = tdvo::python::frameMesh(positions, triangles, "frame 0");
  } catch (const tdvo::Error&) {
    return 0;
  }
  bool ok = mesh.positions.size() == static_cast<size_t>(pr) &&
            mesh.triangles.size() == static_cast<size_t>(tr) && pc == 3 && tc == 3;
  for (const tdvo::Vec3d& p : mesh.positions)
    ok = ok && std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
  for (const tdvo::Triangle& t : mesh.triangles)
    ok = ok && t[0] < mesh.positions.size() && t[1] < mesh.positions.size() &&
         t[2] < mesh.positions.size();
  if (!ok) {
    std::fprintf(stderr, "arrays fuzz target: an accepted frame breaks the reader's checks\n");
    std::abort();
  }
  return 0;
}
