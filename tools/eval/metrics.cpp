#include "tools/eval/metrics.h"

#include "common/core/number_text.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <nanoflann.hpp>
#include <queue>
#include <string>
#include <tuple>
#include <utility>

#include "common/core/error.h"

namespace tdvo {

namespace {

Vec3d sub(const Vec3d& a, const Vec3d& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

double dot(const Vec3d& a, const Vec3d& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double squaredLength(const Vec3d& a) {
  return dot(a, a);
}

// Squared distance from p to the segment ab (a point when a == b). Beyond either end the
// distance to that end is computed directly, so a point equal to an end gives exactly 0.
double pointSegmentSquaredDistance(const Vec3d& p, const Vec3d& a, const Vec3d& b) {
  const Vec3d ab = sub(b, a), ap = sub(p, a);
  const double t = dot(ap, ab);
  if (t <= 0) return squaredLength(ap);
  const double length2 = squaredLength(ab);
  if (t >= length2) return squaredLength(sub(p, b));
  const double s = t / length2;
  return squaredLength({a[0] + s * ab[0] - p[0], a[1] + s * ab[1] - p[1], a[2] + s * ab[2] - p[2]});
}

// Squared distance from p to the box [lo, hi] (0 inside).
double pointBoxSquaredDistance(const Vec3d& p, const Vec3d& lo, const Vec3d& hi) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double d = p[k] < lo[k] ? lo[k] - p[k] : (p[k] > hi[k] ? p[k] - hi[k] : 0.0);
    d2 += d * d;
  }
  return d2;
}

void checkTriangles(const Mesh& mesh) {
  check(!mesh.triangles.empty(), "surface distance: the mesh has no triangles");
  const size_t n = mesh.positions.size();
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (uint32_t v : mesh.triangles[t])
      if (v >= n)  // (not check(): its message would be built for every corner)
        throw Error("surface distance: triangle " + std::to_string(t) + " refers to vertex " +
                    std::to_string(v) + " of " + std::to_string(n));
}

// The adaptor nanoflann needs to index a list of positions.
struct PositionCloud {
  const std::vector<Vec3d>& points;
  size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(size_t i, size_t dim) const { return points[i][dim]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using PositionTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PositionCloud>,
                                        PositionCloud, 3, uint32_t>;

constexpr uint32_t kLeafTriangles = 4;

// pointTriangleSquaredDistance for coordinates of magnitude at most about 2.
double unitTriangleSquaredDistance(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  const Vec3d n = cross(sub(b, a), sub(c, a));
  const double n2 = squaredLength(n);
  if (n2 > 0) {
    // The orthogonal projection of p onto the plane; when it falls inside the triangle (on the
    // inner side of all three edges) the plane distance is the answer. The height is measured
    // from the corner nearest to p, so that a point equal to a corner is at exactly 0.
    const double da = squaredLength(sub(p, a)), db = squaredLength(sub(p, b)),
                 dc = squaredLength(sub(p, c));
    const Vec3d& origin = da <= db && da <= dc ? a : (db <= dc ? b : c);
    const double h = dot(sub(p, origin), n);
    const Vec3d q{p[0] - n[0] * h / n2, p[1] - n[1] * h / n2, p[2] - n[2] * h / n2};
    if (dot(cross(sub(b, a), sub(q, a)), n) >= 0 && dot(cross(sub(c, b), sub(q, b)), n) >= 0 &&
        dot(cross(sub(a, c), sub(q, c)), n) >= 0)
      return h * h / n2;
  }
  // Otherwise the closest point lies on the boundary.
  return std::min({pointSegmentSquaredDistance(p, a, b), pointSegmentSquaredDistance(p, b, c),
                   pointSegmentSquaredDistance(p, c, a)});
}

}  // namespace

double pointTriangleSquaredDistance(const Vec3d& p, const Vec3d& a, const Vec3d& b,
                                    const Vec3d& c) {
  // Computed relative to a and scaled to unit size, then scaled back: a mesh far from the
  // origin loses no precision to its offset (differences of the inputs are taken first), and
  // the products below (up to the fourth power of the size) neither overflow nor underflow at
  // any size 3dvo-metrics accepts (coordinates up to 1e150, meshes down to 1e-140 across).
  // A point equal to a corner is still at exactly 0: its difference is that corner's.
  const Vec3d ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  double size = 0;
  for (const Vec3d* v : {&ab, &ac, &ap})
    for (double x : *v)
      size = std::max(size, std::fabs(x));
  if (size == 0) return 0;  // p = a = b = c
  const Vec3d ua{0, 0, 0}, ub{ab[0] / size, ab[1] / size, ab[2] / size},
      uc{ac[0] / size, ac[1] / size, ac[2] / size}, up{ap[0] / size, ap[1] / size, ap[2] / size};
  return unitTriangleSquaredDistance(up, ua, ub, uc) * size * size;
}

SurfaceIndex::SurfaceIndex(const Mesh& mesh) {
  checkTriangles(mesh);
  check(mesh.triangles.size() < (size_t{1} << 31), "surface distance: too many triangles");
  const size_t count = mesh.triangles.size();
  std::vector<std::array<Vec3d, 3>> triangles(count);
  std::vector<Vec3d> centroids(count);
  std::vector<uint32_t> order(count);
  for (size_t t = 0; t < count; ++t) {
    const Triangle& tri = mesh.triangles[t];
    triangles[t] = {mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]]};
    for (int k = 0; k < 3; ++k)
      centroids[t][k] = (triangles[t][0][k] + triangles[t][1][k] + triangles[t][2][k]) / 3;
    order[t] = static_cast<uint32_t>(t);
  }
  nodes_.reserve(2 * (count / kLeafTriangles + 1));
  corners_.reserve(count);
  build(order, centroids, 0, count, triangles);
}

uint32_t SurfaceIndex::build(std::vector<uint32_t>& order, std::vector<Vec3d>& centroids,
                             size_t begin, size_t end,
                             const std::vector<std::array<Vec3d, 3>>& triangles) {
  const uint32_t index = static_cast<uint32_t>(nodes_.size());
  nodes_.emplace_back();
  Node node;
  if (end - begin <= kLeafTriangles) {
    node.lo = node.hi = triangles[order[begin]][0];
    for (size_t i = begin; i < end; ++i)
      for (const Vec3d& corner : triangles[order[i]])
        for (int k = 0; k < 3; ++k) {
          node.lo[k] = std::min(node.lo[k], corner[k]);
          node.hi[k] = std::max(node.hi[k], corner[k]);
        }
    node.first = static_cast<uint32_t>(corners_.size());
    node.count = static_cast<uint32_t>(end - begin);
    for (size_t i = begin; i < end; ++i)
      corners_.push_back(triangles[order[i]]);
    nodes_[index] = node;
    return index;
  }
  // Median split along the longest extent of the centroids: the tree stays balanced (depth
  // about log2(T / 4)) whatever the triangle sizes, so the query stack below is bounded.
  Vec3d centroidLo = centroids[order[begin]], centroidHi = centroidLo;
  for (size_t i = begin; i < end; ++i)
    for (int k = 0; k < 3; ++k) {
      centroidLo[k] = std::min(centroidLo[k], centroids[order[i]][k]);
      centroidHi[k] = std::max(centroidHi[k], centroids[order[i]][k]);
    }
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (centroidHi[k] - centroidLo[k] > centroidHi[axis] - centroidLo[axis]) axis = k;
  const size_t mid = begin + (end - begin) / 2;
  std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                   [&](uint32_t a, uint32_t b) {
                     return std::tie(centroids[a][axis], a) < std::tie(centroids[b][axis], b);
                   });
  const uint32_t left = build(order, centroids, begin, mid, triangles);
  const uint32_t right = build(order, centroids, mid, end, triangles);
  // The node's box is the union of its children's.
  for (int k = 0; k < 3; ++k) {
    node.lo[k] = std::min(nodes_[left].lo[k], nodes_[right].lo[k]);
    node.hi[k] = std::max(nodes_[left].hi[k], nodes_[right].hi[k]);
  }
  node.first = right;  // the left child is index + 1
  node.count = 0;
  nodes_[index] = node;
  return index;
}

double SurfaceIndex::squaredDistance(const Vec3d& p) const {
  uint32_t hint = 0;
  return squaredDistance(p, hint);
}

double SurfaceIndex::squaredDistance(const Vec3d& p, uint32_t& hint) const {
  // The hinted triangle gives a first upper bound (exact for that triangle, so the minimum found
  // below is still exact); neighbouring query points share their nearest triangle often.
  if (hint >= corners_.size()) hint = 0;
  const auto& h = corners_[hint];
  double best = pointTriangleSquaredDistance(p, h[0], h[1], h[2]);
  // Depth-first, nearer child first, skipping nodes whose box is not nearer than the best so
  // far. The tree depth is at most about 32 (median splits), so 128 entries cannot overflow.
  struct Entry {
    uint32_t node;
    double d2;
  };
  Entry stack[128];
  int size = 0;
  stack[size++] = {0, pointBoxSquaredDistance(p, nodes_[0].lo, nodes_[0].hi)};
  while (size > 0) {
    const Entry e = stack[--size];
    if (e.d2 >= best) continue;
    const Node& node = nodes_[e.node];
    if (node.count > 0) {
      for (uint32_t t = node.first; t < node.first + node.count; ++t) {
        const auto& c = corners_[t];
        const double d2 = pointTriangleSquaredDistance(p, c[0], c[1], c[2]);
        if (d2 < best) {
          best = d2;
          hint = t;
        }
      }
      continue;
    }
    const uint32_t left = e.node + 1, right = node.first;
    const double dl = pointBoxSquaredDistance(p, nodes_[left].lo, nodes_[left].hi);
    const double dr = pointBoxSquaredDistance(p, nodes_[right].lo, nodes_[right].hi);
    if (dl <= dr) {
      if (dr < best) stack[size++] = {right, dr};
      if (dl < best) stack[size++] = {left, dl};
    } else {
      if (dl < best) stack[size++] = {left, dl};
      if (dr < best) stack[size++] = {right, dr};
    }
  }
  return best;
}

DirectedSurfaceDistance directedSurfaceDistance(const Mesh& from, const SurfaceIndex& to) {
  checkTriangles(from);
  std::vector<bool> referenced(from.positions.size(), false);
  for (const Triangle& t : from.triangles)
    for (uint32_t v : t)
      referenced[v] = true;
  DirectedSurfaceDistance result;
  double sum = 0;
  uint32_t hint = 0;  // vertices in file order are mostly near their predecessor
  for (size_t i = 0; i < from.positions.size(); ++i) {
    if (!referenced[i]) continue;
    const double d = std::sqrt(to.squaredDistance(from.positions[i], hint));
    result.max = std::max(result.max, d);
    sum += d;
    ++result.samples;
  }
  result.mean = sum / static_cast<double>(result.samples);
  return result;
}

double SurfaceDistance::hausdorff() const {
  return std::max(referenceToTest.max, testToReference.max);
}

double SurfaceDistance::mean() const {
  return std::max(referenceToTest.mean, testToReference.mean);
}

SurfaceDistance surfaceDistance(const Mesh& reference, const Mesh& test) {
  SurfaceDistance result;
  result.referenceToTest = directedSurfaceDistance(reference, SurfaceIndex(test));
  result.testToReference = directedSurfaceDistance(test, SurfaceIndex(reference));
  return result;
}

double vertexRmse(const std::vector<Vec3d>& reference, const std::vector<Vec3d>& test) {
  SequenceErrorAccumulator accumulator;
  accumulator.addFrame(reference, test);
  return accumulator.vertexRmse();
}

void SequenceErrorAccumulator::addFrame(const std::vector<Vec3d>& reference,
                                        const std::vector<Vec3d>& test) {
  check(!reference.empty(), "vertex errors: the reference frame has no vertices");
  check(reference.size() == test.size(), "vertex errors: the reference has " +
                                             std::to_string(reference.size()) +
                                             " vertices, the test " + std::to_string(test.size()));
  check(frames_ == 0 || reference.size() == vertices_,
        "vertex errors: frame " + std::to_string(frames_) + " has " +
            std::to_string(reference.size()) + " vertices, earlier frames " +
            std::to_string(vertices_));
  Vec3d centroid{0, 0, 0};
  for (const Vec3d& a : reference)
    for (int k = 0; k < 3; ++k)
      centroid[k] += a[k];
  for (int k = 0; k < 3; ++k)
    centroid[k] /= static_cast<double>(reference.size());
  for (size_t i = 0; i < reference.size(); ++i) {
    const double e2 = squaredLength(sub(reference[i], test[i]));
    sumSquaredError_ += e2;
    sumError_ += std::sqrt(e2);
    sumSquaredSpread_ += squaredLength(sub(reference[i], centroid));
  }
  vertices_ = reference.size();
  ++frames_;
}

double SequenceErrorAccumulator::temporalAverageError() const {
  check(frames_ > 0, "vertex errors: no frames");
  return sumError_ / (static_cast<double>(frames_) * static_cast<double>(vertices_));
}

double SequenceErrorAccumulator::vertexRmse() const {
  check(frames_ > 0, "vertex errors: no frames");
  return std::sqrt(sumSquaredError_ / (static_cast<double>(frames_) * vertices_));
}

double SequenceErrorAccumulator::kgError() const {
  check(frames_ > 0, "vertex errors: no frames");
  check(sumSquaredSpread_ > 0,
        "KG error: undefined, every reference frame has all its vertices at one point");
  return 100.0 * std::sqrt(sumSquaredError_) / std::sqrt(sumSquaredSpread_);
}

namespace {

SequenceErrorAccumulator accumulate(const std::vector<std::vector<Vec3d>>& reference,
                                    const std::vector<std::vector<Vec3d>>& test) {
  check(reference.size() == test.size(), "vertex errors: the reference has " +
                                             std::to_string(reference.size()) +
                                             " frames, the test " + std::to_string(test.size()));
  SequenceErrorAccumulator accumulator;
  for (size_t f = 0; f < reference.size(); ++f)
    accumulator.addFrame(reference[f], test[f]);
  return accumulator;
}

}  // namespace

double temporalAverageError(const std::vector<std::vector<Vec3d>>& reference,
                            const std::vector<std::vector<Vec3d>>& test) {
  return accumulate(reference, test).temporalAverageError();
}

double kgError(const std::vector<std::vector<Vec3d>>& reference,
               const std::vector<std::vector<Vec3d>>& test) {
  return accumulate(reference, test).kgError();
}

// ---- STED ----

StedAccumulator::StedAccumulator(const StedParams& params) : params_(params) {
  check(params.width >= 0 && std::isfinite(params.width),
        "STED: the neighbourhood width w must be 0 or more");
  check(params.timeStep > 0 && std::isfinite(params.timeStep),
        "STED: the temporal edge scale dt must be positive");
  check(params.temporalWeight >= 0 && std::isfinite(params.temporalWeight),
        "STED: the weight c must be 0 or more");
}

// From the first reference frame: the edges, the scale D and each vertex's neighbourhood.
void StedAccumulator::prepare(const Mesh& reference) {
  triangles_ = reference.triangles;
  vertexCount_ = reference.positions.size();
  const size_t n = vertexCount_;
  std::vector<std::array<uint32_t, 2>> directed;
  for (size_t t = 0; t < triangles_.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      const uint32_t a = triangles_[t][c], b = triangles_[t][(c + 1) % 3];
      if (a >= n || b >= n)
        throw Error("STED: triangle " + std::to_string(t) + " refers to a vertex beyond the " +
                    std::to_string(n) + " of the reference");
      if (a != b) directed.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(directed.begin(), directed.end());
  directed.erase(std::unique(directed.begin(), directed.end()), directed.end());
  edges_ = std::move(directed);

  // Incident edges of each vertex (CSR).
  std::vector<uint32_t> incidentStart(n + 1, 0), incident(2 * edges_.size());
  for (const auto& e : edges_) {
    ++incidentStart[e[0] + 1];
    ++incidentStart[e[1] + 1];
  }
  for (size_t v = 0; v < n; ++v)
    incidentStart[v + 1] += incidentStart[v];
  {
    std::vector<uint32_t> fill(incidentStart.begin(), incidentStart.end() - 1);
    for (uint32_t e = 0; e < edges_.size(); ++e) {
      incident[fill[edges_[e][0]]++] = e;
      incident[fill[edges_[e][1]]++] = e;
    }
  }
  auto other = [&](uint32_t e, uint32_t v) {
    return edges_[e][0] == v ? edges_[e][1] : edges_[e][0];
  };
  const std::vector<Vec3d>& p = reference.positions;
  auto length = [&](uint32_t e) {
    return std::sqrt(squaredLength(sub(p[edges_[e][0]], p[edges_[e][1]])));
  };

  BoundingBox box;
  box.extend(p);
  const double diagonal = box.diagonal();
  check(diagonal > 0, "STED: the first reference frame has all its vertices at one point");
  timeLength_ = params_.timeStep * diagonal;
  const double radius = params_.width * diagonal;

  // The neighbourhood of v: v, its 1-ring, and the vertices within along-edge distance `radius`
  // (Dijkstra, stopped at the radius); its edges are those with both ends in it.
  std::vector<double> distance(n, std::numeric_limits<double>::infinity());
  std::vector<uint32_t> stamp(n, UINT32_MAX), members;
  using Entry = std::pair<double, uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  vertices_.clear();
  neighbourhoodStart_.assign(1, 0);
  neighbourhoodEdges_.clear();
  for (uint32_t v = 0; v < n; ++v) {
    if (incidentStart[v] == incidentStart[v + 1]) continue;  // on no edge
    members.assign(1, v);
    stamp[v] = v;
    distance[v] = 0;
    queue.push({0.0, v});
    while (!queue.empty()) {
      const auto [d, u] = queue.top();
      queue.pop();
      if (d > distance[u]) continue;
      for (uint32_t k = incidentStart[u]; k < incidentStart[u + 1]; ++k) {
        const uint32_t e = incident[k], x = other(e, u);
        const double dx = d + length(e);
        if (!(dx <= radius || u == v)) continue;  // the 1-ring always belongs
        if (stamp[x] != v) {
          stamp[x] = v;
          members.push_back(x);
          distance[x] = std::numeric_limits<double>::infinity();
        }
        if (dx < distance[x]) {
          distance[x] = dx;
          queue.push({dx, x});
        }
      }
    }
    for (uint32_t u : members)
      for (uint32_t k = incidentStart[u]; k < incidentStart[u + 1]; ++k) {
        const uint32_t e = incident[k], x = other(e, u);
        if (u < x && stamp[x] == v) neighbourhoodEdges_.push_back(e);
      }
    // The neighbourhoods are kept for every frame: memory (and the time to find them) grows
    // with the width, up to the square of the mesh size at w = 1. Bounded, with an error that
    // says what to change rather than gigabytes.
    check(neighbourhoodEdges_.size() <= params_.maxNeighbourhoodEdges,
          "STED: the neighbourhoods of width w = " + formatDouble(params_.width) +
              " hold more than " + std::to_string(params_.maxNeighbourhoodEdges) +
              " edges in all (at vertex " + std::to_string(v) + " of " + std::to_string(n) +
              "); give a smaller StedWidth");
    vertices_.push_back(v);
    neighbourhoodStart_.push_back(static_cast<uint32_t>(neighbourhoodEdges_.size()));
  }
  check(!vertices_.empty(), "STED: the reference has no edges");
}

void StedAccumulator::addFrame(const Mesh& reference, const Mesh& test) {
  const std::string frame = "STED: frame " + std::to_string(frames_);
  if (frames_ == 0) prepare(reference);
  check(reference.positions.size() == vertexCount_ && reference.triangles == triangles_,
        frame +
            ": the reference's vertex count or triangle list differs from the first frame's "
            "(STED needs one connectivity for the whole sequence)");
  check(test.positions.size() == vertexCount_,
        frame + ": the test has " + std::to_string(test.positions.size()) +
            " vertices, the reference " + std::to_string(vertexCount_) +
            " (STED needs the same vertices in the same order)");
  check(test.triangles == triangles_,
        frame +
            ": the test's triangle list differs from the reference's (STED needs the same "
            "connectivity and vertex order)");
  const std::vector<Vec3d>&a = reference.positions, &b = test.positions;

  // Relative edge-length differences, weighted by the reference length; edges of zero reference
  // length are left out (weight 0).
  std::vector<double> difference(edges_.size()), weight(edges_.size());
  for (size_t e = 0; e < edges_.size(); ++e) {
    const auto [i, j] = edges_[e];
    const double l = std::sqrt(squaredLength(sub(a[i], a[j])));
    const double lt = std::sqrt(squaredLength(sub(b[i], b[j])));
    weight[e] = l;
    difference[e] = l > 0 ? std::abs(l - lt) / l : 0.0;
  }
  double frameSum = 0;
  size_t frameTerms = 0;
  for (size_t k = 0; k < vertices_.size(); ++k) {
    double sumWeight = 0, sumDifference = 0;
    for (uint32_t n = neighbourhoodStart_[k]; n < neighbourhoodStart_[k + 1]; ++n) {
      const uint32_t e = neighbourhoodEdges_[n];
      sumWeight += weight[e];
      sumDifference += weight[e] * difference[e];
    }
    if (!(sumWeight > 0)) continue;  // every edge of the neighbourhood degenerate
    const double mean = sumDifference / sumWeight;
    double sumSquares = 0;
    for (uint32_t n = neighbourhoodStart_[k]; n < neighbourhoodStart_[k + 1]; ++n) {
      const uint32_t e = neighbourhoodEdges_[n];
      sumSquares += weight[e] * (difference[e] - mean) * (difference[e] - mean);
    }
    frameSum += std::sqrt(sumSquares / sumWeight);
    ++frameTerms;
  }
  lastSpatial_ = frameTerms > 0 ? frameSum / static_cast<double>(frameTerms) : 0.0;
  sumSpatial_ += frameSum;
  spatialTerms_ += frameTerms;

  // Temporal edges from the previous frame: 4D vectors (displacement, dt·D).
  if (frames_ > 0) {
    const double t2 = timeLength_ * timeLength_;
    for (uint32_t v : vertices_) {
      const double l = std::sqrt(squaredLength(sub(a[v], previousReference_[v])) + t2);
      const double lt = std::sqrt(squaredLength(sub(b[v], previousTest_[v])) + t2);
      sumTemporal_ += std::abs(l - lt) / l;
    }
    temporalTerms_ += vertices_.size();
  }
  previousReference_ = a;
  previousTest_ = b;
  ++frames_;
}

double StedAccumulator::spatial() const {
  check(frames_ > 0, "STED: no frames");
  return spatialTerms_ > 0 ? sumSpatial_ / static_cast<double>(spatialTerms_) : 0.0;
}

std::optional<double> StedAccumulator::temporal() const {
  if (temporalTerms_ == 0) return std::nullopt;
  return sumTemporal_ / static_cast<double>(temporalTerms_);
}

std::optional<double> StedAccumulator::combined() const {
  const std::optional<double> t = temporal();
  if (!t) return std::nullopt;
  const double s = spatial(), c = params_.temporalWeight;
  return std::sqrt(s * s + c * c * *t * *t);
}

StedAccumulator sted(const std::vector<Mesh>& reference, const std::vector<Mesh>& test,
                     const StedParams& params) {
  check(reference.size() == test.size(), "STED: the reference has " +
                                             std::to_string(reference.size()) +
                                             " frames, the test " + std::to_string(test.size()));
  StedAccumulator accumulator(params);
  for (size_t f = 0; f < reference.size(); ++f)
    accumulator.addFrame(reference[f], test[f]);
  return accumulator;
}

std::vector<uint32_t> nearestVertexCorrespondence(const std::vector<Vec3d>& reference,
                                                  const std::vector<Vec3d>& test) {
  check(!reference.empty(), "vertex correspondence: the reference has no vertices");
  check(reference.size() == test.size(), "vertex correspondence: the reference has " +
                                             std::to_string(reference.size()) +
                                             " vertices, the test " + std::to_string(test.size()));
  check(reference.size() < (size_t{1} << 32), "vertex correspondence: too many vertices");
  const size_t n = reference.size();
  // Coincident reference vertices are one point of the tree, holding their indices in
  // ascending order: a point is taken when all of them are, so that many coincident vertices
  // (seams, a collapsed region) cost one search each, not a search among all of them (which
  // took time quadratic in their number).
  std::vector<uint32_t> byPosition(n);
  for (size_t i = 0; i < n; ++i)
    byPosition[i] = static_cast<uint32_t>(i);
  std::sort(byPosition.begin(), byPosition.end(), [&](uint32_t a, uint32_t b) {
    return std::tie(reference[a], a) < std::tie(reference[b], b);
  });
  std::vector<Vec3d> points;            // the distinct reference positions
  std::vector<uint32_t> pointStart{0};  // point p's indices: byPosition[pointStart[p] ..)
  for (size_t i = 0; i < n; ++i) {
    if (i > 0 && reference[byPosition[i]] != reference[byPosition[i - 1]]) {
      pointStart.push_back(static_cast<uint32_t>(i));
    }
    if (pointStart.size() > points.size()) points.push_back(reference[byPosition[i]]);
  }
  pointStart.push_back(static_cast<uint32_t>(n));
  const size_t numPoints = points.size();
  std::vector<uint32_t> nextFree(pointStart.begin(), pointStart.end() - 1);
  const PositionCloud cloud{points};
  PositionTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));

  // Pass 1: distance of each test vertex to its nearest reference vertex (sets the order).
  std::vector<double> nearest2(n);
  for (size_t i = 0; i < n; ++i) {
    uint32_t index = 0;
    double d2 = 0;
    tree.knnSearch(test[i].data(), 1, &index, &d2);
    nearest2[i] = d2;
  }
  std::vector<uint32_t> order(n);
  for (size_t i = 0; i < n; ++i)
    order[i] = static_cast<uint32_t>(i);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return std::tie(nearest2[a], a) < std::tie(nearest2[b], b);
  });

  // Pass 2: each test vertex takes the nearest free reference vertex (lowest index among equally
  // near ones). k nearest points are fetched, k starting at 2 and doubling until a point with a
  // free vertex is found whose distance is below the k-th (so no unseen point can be as near)
  // or k covers every point; among equally near points the one whose lowest free index is
  // lowest.
  std::vector<uint32_t> result(n);
  std::vector<uint32_t> indices;
  std::vector<double> d2s;
  std::vector<std::pair<double, uint32_t>> candidates;  // (distance², lowest free index)
  std::vector<uint32_t> pointOf(n);
  for (size_t p = 0; p < numPoints; ++p)
    for (uint32_t j = pointStart[p]; j < pointStart[p + 1]; ++j)
      pointOf[byPosition[j]] = static_cast<uint32_t>(p);
  for (uint32_t i : order) {
    size_t k = 2;
    for (;;) {
      k = std::min(k, numPoints);
      indices.resize(k);
      d2s.resize(k);
      const size_t found = tree.knnSearch(test[i].data(), k, indices.data(), d2s.data());
      candidates.clear();
      double farthest = 0;
      for (size_t j = 0; j < found; ++j) {
        farthest = std::max(farthest, d2s[j]);
        const uint32_t p = indices[j];
        if (nextFree[p] < pointStart[p + 1])
          candidates.emplace_back(d2s[j], byPosition[nextFree[p]]);
      }
      std::sort(candidates.begin(), candidates.end());
      if (!candidates.empty() && (candidates[0].first < farthest || found == numPoints)) {
        const uint32_t r = candidates[0].second;
        result[i] = r;
        ++nextFree[pointOf[r]];
        break;
      }
      k *= 2;
    }
  }
  return result;
}

std::vector<Vec3d> inReferenceOrder(const std::vector<Vec3d>& test,
                                    const std::vector<uint32_t>& correspondence) {
  check(test.size() == correspondence.size(),
        "vertex correspondence: " + std::to_string(correspondence.size()) + " entries for " +
            std::to_string(test.size()) + " vertices");
  std::vector<Vec3d> result(test.size());
  std::vector<bool> seen(test.size(), false);
  for (size_t i = 0; i < test.size(); ++i) {
    const uint32_t r = correspondence[i];
    if (r >= test.size() || seen[r])
      throw Error("vertex correspondence: not a permutation at entry " + std::to_string(i));
    seen[r] = true;
    result[r] = test[i];
  }
  return result;
}

void BoundingBox::extend(const std::vector<Vec3d>& points) {
  for (const Vec3d& p : points)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
}

double BoundingBox::diagonal() const {
  if (lo[0] > hi[0]) return 0;
  return std::sqrt(squaredLength(sub(hi, lo)));
}

// ---- Texture metrics ----

std::array<double, 3> rgbToYcbcr601(uint8_t r, uint8_t g, uint8_t b) {
  // E'_Y = K_R R + (1 − K_R − K_B) G + K_B B on 0..1; Cb = (B − E'_Y) / (2 (1 − K_B)),
  // Cr = (R − E'_Y) / (2 (1 − K_R)); 8-bit limited range: 16 + 219 E'_Y, 128 + 224 C.
  constexpr double kR = 0.299, kB = 0.114, kG = 1.0 - kR - kB;
  const double red = r / 255.0, green = g / 255.0, blue = b / 255.0;
  const double luma = kR * red + kG * green + kB * blue;
  return {16.0 + 219.0 * luma, 128.0 + 224.0 * (blue - luma) / (2.0 * (1.0 - kB)),
          128.0 + 224.0 * (red - luma) / (2.0 * (1.0 - kR))};
}

void PictureError::add(const PictureError& other) {
  pixels += other.pixels;
  for (int c = 0; c < 3; ++c)
    sumSquared[c] += other.sumSquared[c];
}

std::optional<double> PictureError::mse(int c) const {
  if (pixels == 0) return std::nullopt;
  return sumSquared[c] / static_cast<double>(pixels);
}

std::optional<double> PictureError::psnr(int c) const {
  const std::optional<double> m = mse(c);
  if (!m) return std::nullopt;
  if (*m <= 0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(255.0 * 255.0 / *m);
}

std::optional<double> PictureError::yuvPsnr() const {
  if (pixels == 0) return std::nullopt;
  return (6.0 * *psnr(0) + *psnr(1) + *psnr(2)) / 8.0;
}

namespace {

void checkComparable(const Image& reference, const Image& test) {
  check(reference.width == test.width && reference.height == test.height,
        "texture metrics: reference is " + std::to_string(reference.width) + "x" +
            std::to_string(reference.height) + ", test " + std::to_string(test.width) + "x" +
            std::to_string(test.height));
  check(reference.channels >= 3 && test.channels >= 3,
        "texture metrics: RGB or RGBA images expected");
}

void addPixel(const Image& reference, const Image& test, int x, int y, PictureError& error) {
  const std::array<double, 3> a =
      rgbToYcbcr601(reference.at(x, y, 0), reference.at(x, y, 1), reference.at(x, y, 2));
  const std::array<double, 3> b =
      rgbToYcbcr601(test.at(x, y, 0), test.at(x, y, 1), test.at(x, y, 2));
  for (int c = 0; c < 3; ++c)
    error.sumSquared[c] += (a[c] - b[c]) * (a[c] - b[c]);
  ++error.pixels;
}

}  // namespace

PictureError maskedPictureError(const Image& reference, const Image& test, const Image& mask) {
  checkComparable(reference, test);
  check(mask.width == reference.width && mask.height == reference.height && mask.channels == 1,
        "texture metrics: the mask must be one channel of the images' size");
  PictureError error;
  for (int y = 0; y < reference.height; ++y)
    for (int x = 0; x < reference.width; ++x)
      if (mask.at(x, y) != 0) addPixel(reference, test, x, y, error);
  return error;
}

PictureError regionPictureError(const Image& reference, const Image& test, int x0, int y0, int x1,
                                int y1) {
  checkComparable(reference, test);
  PictureError error;
  for (int y = std::max(y0, 0); y < std::min(y1, reference.height); ++y)
    for (int x = std::max(x0, 0); x < std::min(x1, reference.width); ++x)
      addPixel(reference, test, x, y, error);
  return error;
}

}  // namespace tdvo
