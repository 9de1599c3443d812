// The Python module's frame reader (docs/python.md, "Encoding"): one input frame for
// tdvo.encode from two arrays as numpy describes them (element kind and size, shape, strides in
// bytes, a data pointer), without Python, so that the fuzz target fuzz/arrays_fuzz.cpp runs it
// as the module does.
//
// It is input like an OBJ file and checked like one, before anything is encoded: shapes
// (N, 3) and (M, 3), real positions and integer triangles, finite coordinates, indices in
// [0, N), at least one vertex, one triangle and one proper triangle, and the OBJ reader's
// limits (kMaxObjVertices, kMaxObjTriangles). Errors are tdvo::Error naming `frame` (e.g.
// "frame 2") and the element: docs/errors.md, "Python module (tdvo)".
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/core/mesh.h"

namespace tdvo::python {

// A numpy array's memory as the buffer protocol gives it. Native byte order; `data` holds
// every element the shape and strides reach (numpy guarantees it; strides may be negative or
// 0, as in a broadcast view).
struct ArrayView {
  char kind = 'f';        // numpy's dtype.kind: 'f' float, 'i' signed, 'u' unsigned integer
  int itemSize = 8;       // bytes per element: 4 or 8 for 'f', 1, 2, 4 or 8 for 'i' and 'u'
  std::string dtypeName;  // for messages ("float64", "complex128", ...)
  std::vector<int64_t> shape, strides;  // strides in bytes
  const uint8_t* data = nullptr;
};

// True when `kind` and `itemSize` are one of the element types frameMesh reads (others of a
// real or integer kind are converted by the caller: numpy's astype to float64 or int64).
bool readableElement(char kind, int itemSize);

// The frame's mesh, checked as described above.
Mesh frameMesh(const ArrayView& positions, const ArrayView& triangles, const std::string& frame);

}  // namespace tdvo::python
