#include "tools/recon/closest_point.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/core/error.h"
#include "common/views/camera.h"

namespace tdvo {

namespace {

// Inline vector helpers: the search's inner loops call them millions of times.
inline Vec3d sub(const Vec3d& a, const Vec3d& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline double dot3(const Vec3d& a, const Vec3d& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

}  // namespace

ClosestPoint closestPointOnTriangle(const Vec3d& p, const Vec3d& a, const Vec3d& b,
                                    const Vec3d& c) {
  // Ericson, Real-Time Collision Detection, §5.1.5: which Voronoi region of the triangle p
  // falls in decides the closest feature.
  ClosestPoint r;
  auto finish = [&](double u, double v, double w) {
    r.barycentric = {u, v, w};
    r.point = {u * a[0] + v * b[0] + w * c[0], u * a[1] + v * b[1] + w * c[1],
               u * a[2] + v * b[2] + w * c[2]};
    const Vec3d d = sub(p, r.point);
    r.squaredDistance = dot3(d, d);
    return r;
  };
  const Vec3d ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
  if (d1 <= 0 && d2 <= 0) return finish(1, 0, 0);
  const Vec3d bp = sub(p, b);
  const double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
  if (d3 >= 0 && d4 <= d3) return finish(0, 1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 - d3 > 0 ? d1 / (d1 - d3) : 0;
    return finish(1 - v, v, 0);
  }
  const Vec3d cp = sub(p, c);
  const double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
  if (d6 >= 0 && d5 <= d6) return finish(0, 0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 - d6 > 0 ? d2 / (d2 - d6) : 0;
    return finish(1 - w, 0, w);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const double den = (d4 - d3) + (d5 - d6);
    const double w = den > 0 ? (d4 - d3) / den : 0;
    return finish(0, 1 - w, w);
  }
  const double sum = va + vb + vc;
  if (!(sum > 0)) {
    // A degenerate (zero-area) triangle that reached the face case: the nearest point of its
    // three edges, as (weight of the edge's start, its end).
    auto onSegment = [&p](const Vec3d& s, const Vec3d& e) {
      const Vec3d d = sub(e, s);
      const double len = dot3(d, d);
      const double t = len > 0 ? std::clamp(dot3(sub(p, s), d) / len, 0.0, 1.0) : 0.0;
      const Vec3d q = s + t * d;
      const Vec3d pq = sub(p, q);
      return std::make_pair(dot3(pq, pq), t);
    };
    const auto e0 = onSegment(a, b), e1 = onSegment(b, c), e2 = onSegment(c, a);
    if (e0.first <= e1.first && e0.first <= e2.first) return finish(1 - e0.second, e0.second, 0);
    if (e1.first <= e2.first) return finish(0, 1 - e1.second, e1.second);
    return finish(e2.second, 0, 1 - e2.second);
  }
  const double v = vb / sum, w = vc / sum;
  return finish(1 - v - w, v, w);
}

TriangleBvh::TriangleBvh(const Mesh& mesh) {
  check(!mesh.triangles.empty(), "closest points: the mesh has no triangles");
  triangles_.reserve(mesh.triangles.size());
  std::vector<Vec3d> centroids;
  centroids.reserve(mesh.triangles.size());
  for (const Triangle& t : mesh.triangles) {
    for (uint32_t v : t)
      check(v < mesh.positions.size(), "closest points: a triangle refers to a missing vertex");
    const std::array<Vec3d, 3> corners = {mesh.positions[t[0]], mesh.positions[t[1]],
                                          mesh.positions[t[2]]};
    triangles_.push_back(corners);
    const Vec3d n = cross(corners[1] - corners[0], corners[2] - corners[0]);
    const double len = norm(n);
    normals_.push_back(len > 0 ? (1 / len) * n : Vec3d{0, 0, 0});
    centroids.push_back((1.0 / 3) * (corners[0] + corners[1] + corners[2]));
  }
  order_.resize(triangles_.size());
  for (uint32_t i = 0; i < order_.size(); ++i)
    order_[i] = i;
  nodes_.reserve(2 * triangles_.size() / 4 + 1);
  build(0, order_.size(), centroids);
}

void TriangleBvh::refit(const Mesh& mesh) {
  check(mesh.triangles.size() == triangles_.size(), "closest points: refit with another mesh");
  for (size_t t = 0; t < triangles_.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    for (size_t k = 0; k < 3; ++k)
      triangles_[t][k] = mesh.positions[tri[k]];
    const auto& c = triangles_[t];
    const Vec3d n = cross(sub(c[1], c[0]), sub(c[2], c[0]));
    const double len = std::sqrt(dot3(n, n));
    normals_[t] = len > 0 ? (1 / len) * n : Vec3d{0, 0, 0};
  }
  // Children come after their parent in nodes_, so a backward pass sees them first.
  for (size_t i = nodes_.size(); i-- > 0;) {
    Node& node = nodes_[i];
    Vec3d lo = {1e300, 1e300, 1e300}, hi = {-1e300, -1e300, -1e300};
    auto grow = [&](const Vec3d& a, const Vec3d& b) {
      for (size_t k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], a[k]);
        hi[k] = std::max(hi[k], b[k]);
      }
    };
    if (node.count > 0) {
      for (uint32_t j = node.first; j < node.first + node.count; ++j)
        for (const Vec3d& p : triangles_[order_[j]])
          grow(p, p);
    } else {
      grow(nodes_[i + 1].lo, nodes_[i + 1].hi);
      grow(nodes_[node.first].lo, nodes_[node.first].hi);
    }
    node.lo = lo;
    node.hi = hi;
  }
}

uint32_t TriangleBvh::build(size_t begin, size_t end, std::vector<Vec3d>& centroids) {
  const uint32_t index = static_cast<uint32_t>(nodes_.size());
  nodes_.push_back({});
  Vec3d lo = {1e300, 1e300, 1e300}, hi = {-1e300, -1e300, -1e300};
  Vec3d clo = lo, chi = hi;
  for (size_t i = begin; i < end; ++i) {
    for (const Vec3d& p : triangles_[order_[i]])
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
    const Vec3d& c = centroids[order_[i]];
    for (int k = 0; k < 3; ++k) {
      clo[k] = std::min(clo[k], c[k]);
      chi[k] = std::max(chi[k], c[k]);
    }
  }
  nodes_[index].lo = lo;
  nodes_[index].hi = hi;
  if (end - begin <= 4) {
    nodes_[index].first = static_cast<uint32_t>(begin);
    nodes_[index].count = static_cast<uint32_t>(end - begin);
    return index;
  }
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (chi[k] - clo[k] > chi[axis] - clo[axis]) axis = k;
  const size_t middle = (begin + end) / 2;
  std::nth_element(order_.begin() + static_cast<long>(begin),
                   order_.begin() + static_cast<long>(middle),
                   order_.begin() + static_cast<long>(end), [&](uint32_t x, uint32_t y) {
                     return centroids[x][axis] < centroids[y][axis] ||
                            (centroids[x][axis] == centroids[y][axis] && x < y);
                   });
  build(begin, middle, centroids);
  const uint32_t right = build(middle, end, centroids);
  nodes_[index].first = right;
  nodes_[index].count = 0;
  return index;
}

namespace {

double boxSquaredDistance(const Vec3d& p, const Vec3d& lo, const Vec3d& hi) {
  double d = 0;
  for (int k = 0; k < 3; ++k) {
    const double e = p[k] < lo[k] ? lo[k] - p[k] : p[k] > hi[k] ? p[k] - hi[k] : 0;
    d += e * e;
  }
  return d;
}

}  // namespace

void TriangleBvh::search(uint32_t index, const Query& q, ClosestPoint& best) const {
  const Node& node = nodes_[index];
  if (node.count > 0) {
    for (uint32_t i = node.first; i < node.first + node.count; ++i) {
      const uint32_t t = order_[i];
      if (q.minCos > -2 && dot3(normals_[t], q.normal) < q.minCos) continue;
      const auto& c = triangles_[t];
      ClosestPoint r = closestPointOnTriangle(q.point, c[0], c[1], c[2]);
      if (r.squaredDistance < best.squaredDistance ||
          (r.squaredDistance == best.squaredDistance && t < best.triangle)) {
        r.triangle = t;
        best = r;
      }
    }
    return;
  }
  const uint32_t left = index + 1, right = node.first;
  const double dl = boxSquaredDistance(q.point, nodes_[left].lo, nodes_[left].hi);
  const double dr = boxSquaredDistance(q.point, nodes_[right].lo, nodes_[right].hi);
  if (dl <= dr) {
    if (dl <= best.squaredDistance) search(left, q, best);
    if (dr <= best.squaredDistance) search(right, q, best);
  } else {
    if (dr <= best.squaredDistance) search(right, q, best);
    if (dl <= best.squaredDistance) search(left, q, best);
  }
}

ClosestPoint TriangleBvh::run(const Query& q, uint32_t hint) const {
  ClosestPoint best;
  best.squaredDistance = std::numeric_limits<double>::infinity();
  best.triangle = UINT32_MAX;
  if (hint < triangles_.size() && (q.minCos <= -2 || dot3(normals_[hint], q.normal) >= q.minCos)) {
    const auto& c = triangles_[hint];
    best = closestPointOnTriangle(q.point, c[0], c[1], c[2]);
    best.triangle = hint;
  }
  search(0, q, best);
  return best;
}

ClosestPoint TriangleBvh::closest(const Vec3d& p, uint32_t hint) const {
  return run({p, {0, 0, 0}, -2}, hint);
}

ClosestPoint TriangleBvh::closestFacing(const Vec3d& p, const Vec3d& normal, double minCos,
                                        uint32_t hint) const {
  return run({p, normal, minCos}, hint);
}

}  // namespace tdvo
