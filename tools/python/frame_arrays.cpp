#include "tools/python/frame_arrays.h"

#include <cmath>
#include <cstring>
#include <type_traits>

#include "common/core/error.h"
#include "common/core/obj_io.h"

namespace tdvo::python {
namespace {

std::string shapeText(const ArrayView& a) {
  std::string text = "(";
  for (size_t d = 0; d < a.shape.size(); ++d)
    text += (d ? ", " : "") + std::to_string(a.shape[d]);
  return text + (a.shape.size() == 1 ? ",)" : ")");
}

// `a` must be rows x 3 with rows in [1, maxRows]; `items` names its rows ("vertices"), `none`
// what is missing without any ("no vertices").
void checkShape(const ArrayView& a, size_t maxRows, const std::string& where, const char* rows,
                const char* items, const char* none) {
  if (a.shape.size() != 2 || a.strides.size() != 2 || a.shape[1] != 3)
    throw Error(where + ": expected an array of shape (" + rows + ", 3), got shape " +
                shapeText(a));
  if (a.shape[0] <= 0) throw Error(where + ": " + none);
  if (static_cast<uint64_t>(a.shape[0]) > maxRows)
    throw Error(where + ": more than " + std::to_string(maxRows) + " " + items);
}

// Calls f with element (row, column) of `a` as its C++ type (readableElement types only).
template <class F>
auto visitElement(const ArrayView& a, int64_t row, int64_t column, F f) {
  const uint8_t* at = a.data + row * a.strides[0] + column * a.strides[1];
  auto as = [&](auto type) {
    decltype(type) value;
    std::memcpy(&value, at, sizeof value);
    return f(value);
  };
  const int bits = 8 * a.itemSize;
  if (a.kind == 'f') return bits == 32 ? as(float{}) : as(double{});
  if (a.kind == 'i')
    return bits == 8    ? as(int8_t{})
           : bits == 16 ? as(int16_t{})
           : bits == 32 ? as(int32_t{})
                        : as(int64_t{});
  return bits == 8    ? as(uint8_t{})
         : bits == 16 ? as(uint16_t{})
         : bits == 32 ? as(uint32_t{})
                      : as(uint64_t{});
}

}  // namespace

bool readableElement(char kind, int itemSize) {
  if (kind == 'f') return itemSize == 4 || itemSize == 8;
  if (kind == 'i' || kind == 'u')
    return itemSize == 1 || itemSize == 2 || itemSize == 4 || itemSize == 8;
  return false;
}

Mesh frameMesh(const ArrayView& positions, const ArrayView& triangles, const std::string& frame) {
  const std::string p = frame + ": positions", t = frame + ": triangles";
  if (positions.kind != 'f' && positions.kind != 'i' && positions.kind != 'u')
    throw Error(p + ": expected real numbers (float or int), got dtype " + positions.dtypeName);
  if (triangles.kind != 'i' && triangles.kind != 'u')
    throw Error(t + ": expected integers, got dtype " + triangles.dtypeName);
  check(readableElement(positions.kind, positions.itemSize) &&
            readableElement(triangles.kind, triangles.itemSize),
        frame + ": arrays of dtype " + positions.dtypeName + " and " + triangles.dtypeName +
            " are not read (convert them to float64 and int64)");
  checkShape(positions, kMaxObjVertices, p, "N", "vertices", "no vertices");
  checkShape(triangles, kMaxObjTriangles, t, "M", "triangles", "no faces");

  Mesh mesh;
  const size_t n = static_cast<size_t>(positions.shape[0]);
  mesh.positions.resize(n);
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const double x = visitElement(positions, static_cast<int64_t>(i), c,
                                    [](auto v) { return static_cast<double>(v); });
      if (!std::isfinite(x))
        throw Error(p + "[" + std::to_string(i) + ", " + std::to_string(c) + "] is not finite (" +
                    (std::isnan(x) ? "nan"
                     : x > 0       ? "inf"
                                   : "-inf") +
                    ")");
      if (isBeyondCoordinateRange(x))
        throw Error(p + "[" + std::to_string(i) + ", " + std::to_string(c) +
                    "] = " + coordinateText(x) + kBeyondCoordinateRange);
      mesh.positions[i][c] = x;
    }

  const size_t m = static_cast<size_t>(triangles.shape[0]);
  mesh.triangles.resize(m);
  size_t proper = 0;
  std::string text;
  for (size_t k = 0; k < m; ++k) {
    Triangle& tri = mesh.triangles[k];
    for (int c = 0; c < 3; ++c) {
      // The index as its own type first, so that no value wraps before it is checked.
      uint64_t index = 0;
      const bool nonNegative = visitElement(triangles, static_cast<int64_t>(k), c, [&](auto v) {
        text = std::to_string(v);
        index = static_cast<uint64_t>(v);
        if constexpr (std::is_signed_v<decltype(v)>) return v >= 0;
        return true;
      });
      if (!nonNegative || index >= n)
        throw Error(t + "[" + std::to_string(k) + ", " + std::to_string(c) + "]: vertex index " +
                    text + " out of range (the frame has " + std::to_string(n) + " vertices)");
      tri[c] = static_cast<uint32_t>(index);
    }
    if (tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2]) ++proper;
  }
  if (proper == 0)
    throw Error(frame +
                ": every face has a repeated vertex (degenerate): no triangle is left to code");
  return mesh;
}

}  // namespace tdvo::python
