#include "common/core/grid.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "common/core/error.h"

namespace tdvo {

Grid Grid::fromBounds(const Vec3d& lo, const Vec3d& hi, int bits) {
  check(bits >= kMinBits && bits <= kMaxBits, "grid bits must be in [8, 20]");
  Grid grid;
  grid.bits = bits;
  grid.origin = lo;
  const double extent = largestExtent(lo, hi);
  grid.step = extent > 0 ? extent / grid.maxCoordinate() : 1.0;
  // A step below the smallest normal double loses precision (or is 0): positions could not come
  // back within half a step, and the stream could not carry it (sh_grid_step must be positive).
  if (!(grid.step >= std::numeric_limits<double>::min())) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "the extent %.17g is too small for a grid: its step (extent / %d) would be below "
                  "the smallest normal double (%.17g); scale the input up",
                  extent, grid.maxCoordinate(), std::numeric_limits<double>::min());
    throw Error(text);
  }
  return grid;
}

Grid Grid::fitObject(const Vec3d& lo, const Vec3d& hi, double objectExtent, int precisionBits) {
  Grid grid = fromBounds(lo, hi, precisionBits);
  const double extent = largestExtent(lo, hi);
  const double size = spannedSize(lo, hi, objectExtent, GridFit::kObject);
  if (size >= extent) return grid;  // the object spans its path
  const double step = size / grid.maxCoordinate();
  if (!(step >= std::numeric_limits<double>::min())) return grid;
  for (int bits = precisionBits; bits <= kMaxBits; ++bits) {
    // The bounds' largest extent must round to a coordinate within the grid.
    if (std::floor(extent / step + 0.5) <= double((int64_t{1} << bits) - 1)) {
      grid.bits = bits;
      grid.step = step;
      return grid;
    }
  }
  return fromBounds(lo, hi, kMaxBits);
}

double Grid::largestExtent(const Vec3d& lo, const Vec3d& hi) {
  double extent = 0;
  for (int a = 0; a < 3; ++a)
    extent = std::max(extent, hi[a] - lo[a]);
  return extent;
}

double Grid::spannedSize(const Vec3d& lo, const Vec3d& hi, double objectExtent, GridFit fit) {
  const double extent = largestExtent(lo, hi);
  return fit == GridFit::kObject && objectExtent > 0 && objectExtent < extent ? objectExtent
                                                                              : extent;
}

Vec3i Grid::quantise(const Vec3d& p) const {
  Vec3i q;
  const double maxQ = maxCoordinate();
  for (int a = 0; a < 3; ++a) {
    double v = std::floor((p[a] - origin[a]) / step + 0.5);
    q[a] = static_cast<int32_t>(std::clamp(v, 0.0, maxQ));
  }
  return q;
}

Vec3d Grid::dequantise(const Vec3i& q) const {
  return {origin[0] + q[0] * step, origin[1] + q[1] * step, origin[2] + q[2] * step};
}

IntMesh Grid::quantise(const Mesh& mesh) const {
  IntMesh out;
  out.positions.reserve(mesh.positions.size());
  for (const Vec3d& p : mesh.positions)
    out.positions.push_back(quantise(p));
  out.triangles = mesh.triangles;
  out.attributes = mesh.attributes;
  return out;
}

Mesh Grid::dequantise(const IntMesh& mesh) const {
  Mesh out;
  out.positions.reserve(mesh.positions.size());
  for (const Vec3i& q : mesh.positions)
    out.positions.push_back(dequantise(q));
  out.triangles = mesh.triangles;
  out.attributes = mesh.attributes;
  return out;
}

void boundingBox(const std::vector<Mesh>& meshes, Vec3d& lo, Vec3d& hi) {
  bool any = false;
  for (const Mesh& m : meshes)
    for (const Vec3d& p : m.positions) {
      for (int a = 0; a < 3; ++a) {
        lo[a] = any ? std::min(lo[a], p[a]) : p[a];
        hi[a] = any ? std::max(hi[a], p[a]) : p[a];
      }
      any = true;
    }
  check(any, "no vertex positions to bound");
}

}  // namespace tdvo
