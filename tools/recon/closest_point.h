// Closest points on a triangle mesh: the correspondence search of the tracking's fitting
// (which point of the target surface is nearest to a vertex, and which point of the deforming
// mesh is nearest to a target sample). tools/eval/metrics.h answers only "how far"; here the point,
// its triangle and its barycentric coordinates are needed.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/core/mesh.h"

namespace tdvo {

struct ClosestPoint {
  double squaredDistance = 0;
  uint32_t triangle = 0;                // index into the mesh's triangles
  std::array<double, 3> barycentric{};  // weights of the triangle's corners 0, 1, 2
  Vec3d point{};
};

// The closest point of triangle abc to p, with its barycentric coordinates (Voronoi-region
// case analysis of the triangle's vertices, edges and face). Degenerate triangles are handled
// by the edge cases.
ClosestPoint closestPointOnTriangle(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c);

// A bounding volume hierarchy (median splits on the longest axis of the centroids' box, four
// triangles per leaf) over a mesh's triangles. Holds a copy of the corners.
class TriangleBvh {
 public:
  TriangleBvh() = default;
  // Throws Error when the mesh has no triangles or refers to a missing vertex.
  explicit TriangleBvh(const Mesh& mesh);

  // The closest point on any triangle. `hint`, when given, is a triangle tried first (e.g.
  // the answer for a nearby point), which speeds up the search; the result does not depend
  // on it except between equally distant triangles.
  ClosestPoint closest(const Vec3d& p, uint32_t hint = UINT32_MAX) const;

  // The closest point among the triangles whose unit normal n_t has n_t · normal ≥ minCos
  // (facing the same way as the query). Returns a result with infinite squaredDistance and
  // triangle UINT32_MAX when no triangle qualifies.
  ClosestPoint closestFacing(const Vec3d& p, const Vec3d& normal, double minCos,
                             uint32_t hint = UINT32_MAX) const;

  // Unit normal of a triangle (zero for a degenerate one), in the mesh's triangle order.
  const Vec3d& normal(uint32_t triangle) const { return normals_[triangle]; }

  // Moves the triangles to the positions of `mesh`, which must have the same triangles as the
  // mesh the hierarchy was built from; the tree is kept and its boxes recomputed (cheaper than
  // a rebuild, and as good while the motion is small).
  void refit(const Mesh& mesh);

  size_t triangleCount() const { return triangles_.size(); }

 private:
  struct Node {
    Vec3d lo, hi;
    uint32_t first, count;  // leaf: range in order_; inner: count 0, first = right child
  };
  uint32_t build(size_t begin, size_t end, std::vector<Vec3d>& centroids);
  struct Query {
    Vec3d point, normal;
    double minCos;  // −2 accepts every triangle
  };
  void search(uint32_t node, const Query& q, ClosestPoint& best) const;
  ClosestPoint run(const Query& q, uint32_t hint) const;

  std::vector<std::array<Vec3d, 3>> triangles_;  // corners, in the mesh's triangle order
  std::vector<Vec3d> normals_;                   // unit normals, same order
  std::vector<uint32_t> order_;                  // triangle indices in leaf order
  std::vector<Node> nodes_;
};

}  // namespace tdvo
