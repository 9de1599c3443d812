// Geometry metrics (tools/eval/metrics.h) against hand-computed cases, and the 3dvo-metrics app.
#include "tools/eval/metrics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <string>
#include <vector>

#include "common/core/error.h"
#include "common/core/grid.h"
#include "common/core/obj_io.h"
#include "test_support.h"

namespace tdvo {
namespace {

constexpr double kEps = 1e-12;

// The unit square in the z = `z` plane as two triangles (vertices 0 (0,0) 1 (1,0) 2 (0,1)
// 3 (1,1)); both triangles use vertex 3.
Mesh unitSquare(double z = 0) {
  Mesh m;
  m.positions = {{0, 0, z}, {1, 0, z}, {0, 1, z}, {1, 1, z}};
  m.triangles = {{0, 1, 3}, {0, 3, 2}};
  return m;
}

// An n x n grid of vertices over [0, size]^2 in the z = `z` plane.
Mesh planeGrid(int n, double size, double z) {
  Mesh m;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      m.positions.push_back({size * x / (n - 1), size * y / (n - 1), z});
  for (int y = 0; y + 1 < n; ++y)
    for (int x = 0; x + 1 < n; ++x) {
      const uint32_t a = static_cast<uint32_t>(y * n + x), b = a + 1;
      const uint32_t c = a + static_cast<uint32_t>(n), d = c + 1;
      m.triangles.push_back({a, b, d});
      m.triangles.push_back({a, d, c});
    }
  return m;
}

// A fixed pseudo-random permutation of 0..n-1 (LCG-driven Fisher-Yates).
std::vector<uint32_t> shuffled(size_t n, uint64_t seed) {
  std::vector<uint32_t> p(n);
  std::iota(p.begin(), p.end(), 0u);
  for (size_t i = n - 1; i > 0; --i) {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    std::swap(p[i], p[(seed >> 33) % (i + 1)]);
  }
  return p;
}

// `mesh` with its vertices renumbered: new vertex i is old vertex order[i]; same surface.
Mesh renumbered(const Mesh& mesh, const std::vector<uint32_t>& order) {
  Mesh out;
  std::vector<uint32_t> newIndex(order.size());
  for (size_t i = 0; i < order.size(); ++i) {
    out.positions.push_back(mesh.positions[order[i]]);
    newIndex[order[i]] = static_cast<uint32_t>(i);
  }
  for (const Triangle& t : mesh.triangles)
    out.triangles.push_back({newIndex[t[0]], newIndex[t[1]], newIndex[t[2]]});
  return out;
}

// ---- point to triangle ----

TEST(PointTriangleDistance, RegionsOfTheTriangle) {
  const Vec3d a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  EXPECT_NEAR(pointTriangleSquaredDistance({0.25, 0.25, 2}, a, b, c), 4.0, kEps);   // face
  EXPECT_NEAR(pointTriangleSquaredDistance({0.25, 0.25, -3}, a, b, c), 9.0, kEps);  // below
  EXPECT_NEAR(pointTriangleSquaredDistance({0.2, 0.3, 0}, a, b, c), 0.0, kEps);     // inside
  EXPECT_NEAR(pointTriangleSquaredDistance({-1, -1, 0}, a, b, c), 2.0, kEps);       // vertex a
  EXPECT_NEAR(pointTriangleSquaredDistance({3, -4, 0}, a, b, c), 4 + 16, kEps);     // vertex b
  EXPECT_NEAR(pointTriangleSquaredDistance({0.5, -2, 1}, a, b, c), 5.0, kEps);      // edge ab
  // Edge bc (x + y = 1): the point (1, 1, 0) is 1/sqrt(2) from it.
  EXPECT_NEAR(pointTriangleSquaredDistance({1, 1, 0}, a, b, c), 0.5, kEps);
}

// The distance scales with the triangle at every size 3dvo-metrics accepts (coordinates up to
// 1e150, meshes down to 1e-140 across): h² / |n|² overflowed from about 1e51 (inf) and
// underflowed below about 1e-54 (0), and beyond ~1e±77 the inside test failed (edge distances).
// An offset far from the origin costs no precision beyond the inputs' own.
TEST(PointTriangleDistance, AnySizeAndOffset) {
  for (const double s : {1e-140, 1e-80, 1e-55, 1.0, 1e52, 1e60, 1e76, 1e140}) {
    const Vec3d a{0, 0, 0}, b{s, 0, 0}, c{0, s, 0};
    const double d2 = pointTriangleSquaredDistance({0.25 * s, 0.25 * s, 0.1 * s}, a, b, c);
    EXPECT_NEAR(std::sqrt(d2) / s, 0.1, 1e-12) << "size " << s;
    const double e2 = pointTriangleSquaredDistance({2 * s, 2 * s, 0}, a, b, c);  // edge bc
    EXPECT_NEAR(std::sqrt(e2) / s, 1.5 * std::sqrt(2.0), 1e-12) << "size " << s;
    EXPECT_EQ(pointTriangleSquaredDistance(b, a, b, c), 0.0) << "size " << s;
  }
  const double o = 1e12;  // exactly representable inputs; the exact answers are 0.25 and 0.125
  const Vec3d a{o, o, o}, b{o + 1, o, o}, c{o, o + 1, o};
  EXPECT_EQ(pointTriangleSquaredDistance({o + 0.25, o + 0.25, o + 0.5}, a, b, c), 0.25);
  EXPECT_NEAR(pointTriangleSquaredDistance({o + 1.25, o - 0.25, o}, a, b, c), 0.125, 1e-15);
}

TEST(PointTriangleDistance, DegenerateTriangleIsItsEdges) {
  // Collinear corners: the closest point is on the segment from (0,0,0) to (2,0,0).
  EXPECT_NEAR(pointTriangleSquaredDistance({1, 1, 0}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}), 1.0, kEps);
  EXPECT_NEAR(pointTriangleSquaredDistance({3, 0, 0}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}), 1.0, kEps);
  // All three corners at one point.
  EXPECT_NEAR(pointTriangleSquaredDistance({0, 3, 4}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}), 25.0, kEps);
}

// ---- the spatial index ----

TEST(SurfaceIndex, MatchesBruteForceOnCurvedMeshes) {
  const std::vector<Mesh> meshes = test::wobblingSphere(3, 2);  // 642 vertices, 1280 triangles
  const SurfaceIndex index(meshes[0]);
  EXPECT_EQ(index.triangleCount(), meshes[0].triangles.size());
  // Query points: the other frame's vertices, scaled copies inside and outside the sphere.
  std::vector<Vec3d> queries;
  for (double scale : {0.3, 0.97, 1.0, 1.4, 3.0})
    for (const Vec3d& p : meshes[1].positions)
      queries.push_back({scale * p[0], scale * p[1], scale * p[2]});
  for (const Vec3d& q : queries) {
    double brute = std::numeric_limits<double>::infinity();
    for (const Triangle& t : meshes[0].triangles)
      brute = std::min(brute, pointTriangleSquaredDistance(q, meshes[0].positions[t[0]],
                                                           meshes[0].positions[t[1]],
                                                           meshes[0].positions[t[2]]));
    ASSERT_EQ(index.squaredDistance(q), brute);
  }
}

TEST(SurfaceIndex, RejectsMeshesWithoutTrianglesOrWithBadIndices) {
  Mesh empty;
  empty.positions = {{0, 0, 0}};
  EXPECT_THROW(SurfaceIndex{empty}, Error);
  Mesh bad = unitSquare();
  bad.triangles.push_back({0, 1, 4});
  EXPECT_THROW(SurfaceIndex{bad}, Error);
}

// ---- Hausdorff ----

TEST(SurfaceDistance, IdenticalMeshesAreAtZero) {
  const Mesh m = test::wobblingSphere(2, 1)[0];
  const SurfaceDistance d = surfaceDistance(m, m);
  EXPECT_EQ(d.hausdorff(), 0.0);
  EXPECT_EQ(d.mean(), 0.0);
  EXPECT_EQ(d.referenceToTest.samples, m.positions.size());
  EXPECT_EQ(d.testToReference.samples, m.positions.size());
  EXPECT_EQ(vertexRmse(m.positions, m.positions), 0.0);
}

TEST(SurfaceDistance, PlaneAgainstOffsetPlaneIsTheOffset) {
  // Different tessellations of the same square, 0.25 apart: every vertex of each projects
  // inside the other, so every sample is exactly 0.25 away.
  const Mesh reference = planeGrid(11, 1.0, 0.0);
  const Mesh test = planeGrid(4, 1.0, 0.25);
  const SurfaceDistance d = surfaceDistance(reference, test);
  EXPECT_NEAR(d.hausdorff(), 0.25, kEps);
  EXPECT_NEAR(d.mean(), 0.25, kEps);
  EXPECT_NEAR(d.referenceToTest.max, 0.25, kEps);
  EXPECT_NEAR(d.referenceToTest.mean, 0.25, kEps);
  EXPECT_NEAR(d.testToReference.max, 0.25, kEps);
  EXPECT_NEAR(d.testToReference.mean, 0.25, kEps);
  EXPECT_EQ(d.referenceToTest.samples, 121u);
  EXPECT_EQ(d.testToReference.samples, 16u);
}

TEST(SurfaceDistance, OneVertexMovedByAKnownOffset) {
  // Vertex 3 of the unit square lifted by h = 0.75. Test -> reference: that vertex is 0.75 above
  // the flat square, the others on it: max 0.75, mean 0.75 / 4. Reference -> test: the flat
  // corner (1,1,0) is nearest to the edge from (1,0,0) to (1,1,h) of both lifted triangles, at
  // h / sqrt(1 + h^2) = 0.6; the other corners lie on the lifted surface: max 0.6, mean 0.15.
  const Mesh reference = unitSquare();
  Mesh test = unitSquare();
  test.positions[3][2] = 0.75;
  const SurfaceDistance d = surfaceDistance(reference, test);
  EXPECT_NEAR(d.testToReference.max, 0.75, kEps);
  EXPECT_NEAR(d.testToReference.mean, 0.1875, kEps);
  EXPECT_NEAR(d.referenceToTest.max, 0.6, kEps);
  EXPECT_NEAR(d.referenceToTest.mean, 0.15, kEps);
  EXPECT_NEAR(d.hausdorff(), 0.75, kEps);
  EXPECT_NEAR(d.mean(), 0.1875, kEps);
  // RMSE = sqrt(0.75^2 / 4) = 0.375.
  EXPECT_NEAR(vertexRmse(reference.positions, test.positions), 0.375, kEps);
}

TEST(SurfaceDistance, AsymmetricWhenOneSurfaceCoversPartOfTheOther) {
  // The test is the corner [0, 0.1]^2 of the reference square: every test vertex lies on the
  // reference (test -> reference = 0), while the reference corners are 0, 0.9, 0.9 and
  // 0.9 sqrt(2) from the small square.
  const Mesh reference = unitSquare();
  Mesh test = unitSquare();
  for (Vec3d& p : test.positions)
    p = {0.1 * p[0], 0.1 * p[1], 0};
  const SurfaceDistance d = surfaceDistance(reference, test);
  EXPECT_NEAR(d.testToReference.max, 0.0, kEps);
  EXPECT_NEAR(d.testToReference.mean, 0.0, kEps);
  EXPECT_NEAR(d.referenceToTest.max, 0.9 * std::sqrt(2.0), kEps);
  EXPECT_NEAR(d.referenceToTest.mean, (0.9 + 0.9 + 0.9 * std::sqrt(2.0)) / 4, kEps);
  EXPECT_NEAR(d.hausdorff(), 0.9 * std::sqrt(2.0), kEps);
  // Swapping the roles swaps the directions.
  const SurfaceDistance swapped = surfaceDistance(test, reference);
  EXPECT_EQ(swapped.referenceToTest.max, d.testToReference.max);
  EXPECT_EQ(swapped.testToReference.max, d.referenceToTest.max);
  EXPECT_EQ(swapped.testToReference.mean, d.referenceToTest.mean);
}

TEST(SurfaceDistance, VerticesOutsideEveryTriangleAreNotSampled) {
  Mesh reference = unitSquare();
  Mesh test = unitSquare(0.5);
  test.positions.push_back({100, 100, 100});  // referenced by no triangle
  const SurfaceDistance d = surfaceDistance(reference, test);
  EXPECT_EQ(d.testToReference.samples, 4u);
  EXPECT_NEAR(d.testToReference.max, 0.5, kEps);
  EXPECT_NEAR(d.referenceToTest.max, 0.5, kEps);
}

// ---- D_A, KG, RMSE ----

// Two frames of two vertices. Reference frame 0: (0,0,0) (2,0,0), centroid (1,0,0), spread
// 1 + 1 = 2; frame 1: (0,0,0) (0,4,0), centroid (0,2,0), spread 4 + 4 = 8. Errors: frame 0
// vertex 0 by (3,4,0) (length 5), frame 1 vertex 1 by (0,0,1) (length 1), the others 0.
struct TinySequence {
  std::vector<std::vector<Vec3d>> reference{{{0, 0, 0}, {2, 0, 0}}, {{0, 0, 0}, {0, 4, 0}}};
  std::vector<std::vector<Vec3d>> test{{{3, 4, 0}, {2, 0, 0}}, {{0, 0, 0}, {0, 4, 1}}};
};

TEST(SequenceErrors, TemporalAverageErrorByHand) {
  const TinySequence s;
  // D_A = (5 + 0 + 0 + 1) / (2 frames * 2 vertices) = 1.5
  EXPECT_NEAR(temporalAverageError(s.reference, s.test), 1.5, kEps);
}

TEST(SequenceErrors, KgErrorByHand) {
  const TinySequence s;
  // KG = 100 sqrt(25 + 1) / sqrt(2 + 8)
  EXPECT_NEAR(kgError(s.reference, s.test), 100 * std::sqrt(26.0 / 10.0), 1e-10);
  SequenceErrorAccumulator a;
  a.addFrame(s.reference[0], s.test[0]);
  a.addFrame(s.reference[1], s.test[1]);
  EXPECT_EQ(a.frameCount(), 2);
  EXPECT_EQ(a.vertexCount(), 2u);
  EXPECT_NEAR(a.vertexRmse(), std::sqrt(26.0 / 4), kEps);
}

TEST(SequenceErrors, KgUsesEachFramesOwnCentroid) {
  // Moving a whole frame (reference and test alike) changes neither the errors nor the spread
  // about that frame's centroid; a centroid over all frames would see the move.
  TinySequence moved;
  for (auto* frames : {&moved.reference, &moved.test})
    for (Vec3d& p : (*frames)[1])
      p[0] += 100;
  const TinySequence s;
  EXPECT_NEAR(kgError(moved.reference, moved.test), kgError(s.reference, s.test), 1e-9);
  EXPECT_NEAR(temporalAverageError(moved.reference, moved.test), 1.5, kEps);
}

TEST(SequenceErrors, IdenticalSequencesAreAtZero) {
  const TinySequence s;
  EXPECT_EQ(kgError(s.reference, s.reference), 0.0);
  EXPECT_EQ(temporalAverageError(s.reference, s.reference), 0.0);
}

TEST(SequenceErrors, RejectsMismatchedOrDegenerateInput) {
  SequenceErrorAccumulator a;
  EXPECT_THROW(a.temporalAverageError(), Error);  // no frames
  EXPECT_THROW(a.addFrame({{0, 0, 0}}, {{0, 0, 0}, {1, 0, 0}}), Error);
  EXPECT_THROW(a.addFrame({}, {}), Error);
  a.addFrame({{0, 0, 0}, {1, 0, 0}}, {{0, 0, 0}, {1, 0, 0}});
  EXPECT_THROW(a.addFrame({{0, 0, 0}}, {{0, 0, 0}}), Error);  // vertex count changed
  SequenceErrorAccumulator point;
  point.addFrame({{1, 1, 1}, {1, 1, 1}}, {{1, 1, 2}, {1, 1, 1}});
  EXPECT_THROW(point.kgError(), Error);  // no spread: KG undefined
  EXPECT_THROW(temporalAverageError({{{0, 0, 0}}}, {}), Error);
}

// ---- STED ----

// Two equilateral triangles of side 1 sharing the edge 1-2 (a rhombus in z = 0): vertices
// 0 (0,0,0), 1 (1,0,0), 2 (1/2,√3/2,0), 3 (3/2,√3/2,0); edges 0-1, 0-2, 1-2, 1-3, 2-3, all of
// length 1. Bounding-box diagonal D = sqrt(1.5² + 3/4) = √3.
Mesh rhombus() {
  const double h = std::sqrt(3.0) / 2;
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, h, 0}, {1.5, h, 0}};
  m.triangles = {{0, 1, 2}, {1, 3, 2}};
  return m;
}

// The rhombus with vertex 3 lifted by √3: edges 1-3 and 2-3 become sqrt(1 + 3) = 2 long.
Mesh liftedRhombus() {
  Mesh m = rhombus();
  m.positions[3][2] = std::sqrt(3.0);
  return m;
}

// Reference: the rhombus, still, in frames 0 and 1. Test: frame 0 lifted, frame 1 exact.
// dt·D = 1 (dt = 1/√3), c = 2.
//
// Spatial, frame 0: relative edge differences |l' − l| / l: 1-3 and 2-3 are 1, the others 0;
// all weights (reference lengths) are 1, so each vertex's figure is the plain standard deviation
// over the edges among its 1-ring and itself:
//   vertex 0: {0,1,2}: edges 0-1, 0-2, 1-2: (0, 0, 0) -> 0
//   vertex 1: {0,1,2,3}: all five edges: (0, 0, 0, 1, 1), mean 0.4,
//             variance (3·0.16 + 2·0.36) / 5 = 0.24 -> √0.24
//   vertex 2: the same as vertex 1 -> √0.24
//   vertex 3: {1,2,3}: edges 1-2, 1-3, 2-3: (0, 1, 1), mean 2/3,
//             variance (4/9 + 1/9 + 1/9) / 3 = 2/9 -> √2 / 3
// Frame 1: every difference 0 -> 0 at every vertex.
// STED_s = (0 + 2√0.24 + √2/3 + 4·0) / 8 vertex-frames ≈ 0.181400.
//
// Temporal, frames 0 -> 1: the reference does not move, so its temporal edges have length
// sqrt(0 + (dt·D)²) = 1. In the test vertices 0-2 stay (length 1, difference 0) and vertex 3
// falls by √3 (length sqrt(3 + 1) = 2, difference |1 − 2| / 1 = 1).
// STED_t = (0 + 0 + 0 + 1) / 4 = 0.25; STED = sqrt(STED_s² + 2²·0.25²).
struct StedCase {
  std::vector<Mesh> reference{rhombus(), rhombus()};
  std::vector<Mesh> test{liftedRhombus(), rhombus()};
  StedParams params;
  StedCase() {
    params.timeStep = 1 / std::sqrt(3.0);
    params.temporalWeight = 2;
  }
};

const double kHandStedSpatial = (2 * std::sqrt(0.24) + std::sqrt(2.0) / 3) / 8;

TEST(Sted, HandComputedTwoTrianglesOverTwoFrames) {
  const StedCase c;
  const StedAccumulator s = sted(c.reference, c.test, c.params);
  EXPECT_EQ(s.frameCount(), 2);
  EXPECT_NEAR(s.spatial(), kHandStedSpatial, 1e-12);
  EXPECT_NEAR(s.spatial(), 0.181400, 1e-6);
  ASSERT_TRUE(s.temporal().has_value());
  EXPECT_NEAR(*s.temporal(), 0.25, 1e-12);
  EXPECT_NEAR(*s.combined(), std::sqrt(kHandStedSpatial * kHandStedSpatial + 4 * 0.0625), 1e-12);
  EXPECT_EQ(s.lastFrameSpatial(), 0.0);  // frame 1 is exact
}

TEST(Sted, NeighbourhoodWidthReachesAlongEdges) {
  // Along-edge distances from vertex 0: 1 to vertices 1 and 2, 2 to vertex 3; from vertex 3
  // the same mirrored. A radius w·D of 1.5 keeps the 1-ring; 2.5 takes in the whole rhombus,
  // so every vertex sees all five edges (√0.24 in frame 0): STED_s = 4·√0.24 / 8.
  StedCase c;
  c.params.width = 1.5 / std::sqrt(3.0);
  EXPECT_NEAR(sted(c.reference, c.test, c.params).spatial(), kHandStedSpatial, 1e-12);
  c.params.width = 2.5 / std::sqrt(3.0);
  EXPECT_NEAR(sted(c.reference, c.test, c.params).spatial(), std::sqrt(0.24) / 2, 1e-12);
}

// The neighbourhoods, kept for every frame, are bounded: beyond maxNeighbourhoodEdges in all (a
// wide w on a large mesh needs up to the square of its size) an Error, not gigabytes.
TEST(Sted, NeighbourhoodsAreBounded) {
  StedCase c;
  c.params.width = 2.5 / std::sqrt(3.0);  // every vertex sees all five edges: 20 in all
  c.params.maxNeighbourhoodEdges = 20;
  EXPECT_NEAR(sted(c.reference, c.test, c.params).spatial(), std::sqrt(0.24) / 2, 1e-12);
  c.params.maxNeighbourhoodEdges = 19;
  try {
    sted(c.reference, c.test, c.params);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("hold more than 19 edges in all"), std::string::npos)
        << e.what();
  }
}

TEST(Sted, OneFrameHasNoTemporalPart) {
  const StedCase c;
  const StedAccumulator s = sted({c.reference[0]}, {c.test[0]}, c.params);
  EXPECT_NEAR(s.spatial(), (2 * std::sqrt(0.24) + std::sqrt(2.0) / 3) / 4, 1e-12);
  EXPECT_FALSE(s.temporal().has_value());
  EXPECT_FALSE(s.combined().has_value());
}

// `mesh` rotated by `angle` about the z axis, scaled by `scale` and moved by `shift`.
Mesh similarity(Mesh mesh, double angle, double scale, const Vec3d& shift) {
  const double c = std::cos(angle), s = std::sin(angle);
  for (Vec3d& p : mesh.positions)
    p = {scale * (c * p[0] - s * p[1]) + shift[0], scale * (s * p[0] + c * p[1]) + shift[1],
         scale * p[2] + shift[2]};
  return mesh;
}

// A wobbling sphere and a copy with a deterministic per-vertex perturbation.
struct NoisySphere {
  std::vector<Mesh> reference = test::wobblingSphere(2, 4), test;
  NoisySphere() {
    test = reference;
    for (size_t f = 0; f < test.size(); ++f)
      for (size_t i = 0; i < test[f].positions.size(); ++i)
        for (int k = 0; k < 3; ++k)
          test[f].positions[i][k] += 0.01 * std::sin(1.7 * i + 2.3 * k + 0.9 * f);
  }
};

TEST(Sted, IdenticalSequencesAreAtZero) {
  const NoisySphere s;
  const StedAccumulator a = sted(s.reference, s.reference);
  EXPECT_EQ(a.spatial(), 0.0);
  EXPECT_EQ(*a.temporal(), 0.0);
  EXPECT_EQ(*a.combined(), 0.0);
}

TEST(Sted, InvariantToOneSimilarityOfBothSequences) {
  // Rotating, scaling and moving both sequences alike changes no relative length (w and dt are
  // fractions of the diagonal, which scales too). A quarter turn about z keeps the axis-aligned
  // box's diagonal; other angles change it, and with it the scale of w and dt.
  const NoisySphere s;
  StedParams params;
  params.width = 0.2;
  std::vector<Mesh> reference, test;
  for (size_t f = 0; f < s.reference.size(); ++f) {
    reference.push_back(similarity(s.reference[f], std::acos(0.0), 3.0, {5, -2, 1}));
    test.push_back(similarity(s.test[f], std::acos(0.0), 3.0, {5, -2, 1}));
  }
  const StedAccumulator a = sted(s.reference, s.test, params);
  const StedAccumulator b = sted(reference, test, params);
  EXPECT_GT(a.spatial(), 1e-3);
  EXPECT_NEAR(b.spatial(), a.spatial(), 1e-9);
  EXPECT_NEAR(*b.temporal(), *a.temporal(), 1e-9);
}

TEST(Sted, RigidOrScaledTestFramesHaveNoSpatialPart) {
  // Each test frame a rigid motion of its reference frame (a different one per frame), or a
  // uniform scaling of it: every edge changes by the same ratio, so the local deviations are
  // 0. The motion between frames is an error the temporal part sees.
  const NoisySphere s;
  std::vector<Mesh> moved, scaled;
  for (size_t f = 0; f < s.reference.size(); ++f) {
    moved.push_back(similarity(s.reference[f], 0.1 * f, 1.0, {0.05 * f, 0, 0}));
    scaled.push_back(similarity(s.reference[f], 0, 1.1, {0, 0, 0}));
  }
  const StedAccumulator rigid = sted(s.reference, moved);
  EXPECT_NEAR(rigid.spatial(), 0.0, 1e-12);
  EXPECT_GT(*rigid.temporal(), 1e-3);
  EXPECT_NEAR(sted(s.reference, scaled).spatial(), 0.0, 1e-12);
}

TEST(Sted, RefusesDifferentConnectivityOrVertices) {
  const StedCase c;
  auto message = [](const std::vector<Mesh>& reference, const std::vector<Mesh>& test) {
    return test::errorOf([&] { sted(reference, test); });
  };
  Mesh flipped = c.test[0];
  flipped.triangles = {{0, 1, 3}, {0, 3, 2}};  // the other diagonal
  EXPECT_NE(message({c.reference[0]}, {flipped}).find("connectivity"), std::string::npos);
  Mesh extra = c.test[0];
  extra.positions.push_back({0, 0, 1});
  EXPECT_NE(message({c.reference[0]}, {extra}).find("vertices"), std::string::npos);
  // The reference's own connectivity must stay the same over the sequence.
  EXPECT_NE(message({c.reference[0], flipped}, {c.test[0], flipped}).find("first frame"),
            std::string::npos);
  Mesh bad = c.reference[0];
  bad.triangles.push_back({0, 1, 9});
  EXPECT_NE(message({bad}, {bad}).find("vertex"), std::string::npos);
  EXPECT_NE(message({c.reference[0]}, {}).find("frames"), std::string::npos);
  StedParams zeroTime;
  zeroTime.timeStep = 0;
  EXPECT_THROW(StedAccumulator{zeroTime}, Error);
  EXPECT_THROW(StedAccumulator{}.spatial(), Error);  // no frames
}

// ---- vertex correspondence ----

TEST(NearestCorrespondence, RecoversAShuffledOrder) {
  const Mesh m = test::wobblingSphere(3, 1)[0];
  const std::vector<uint32_t> order = shuffled(m.positions.size(), 7);
  std::vector<Vec3d> test;
  for (uint32_t i : order)  // test vertex i is reference vertex order[i], slightly moved
    test.push_back({m.positions[i][0] + 1e-4, m.positions[i][1], m.positions[i][2] - 1e-4});
  const std::vector<uint32_t> c = nearestVertexCorrespondence(m.positions, test);
  EXPECT_EQ(c, order);
  const std::vector<Vec3d> aligned = inReferenceOrder(test, c);
  EXPECT_NEAR(vertexRmse(m.positions, aligned), std::sqrt(2.0) * 1e-4, 1e-12);
  // Without it, the errors are those of unrelated vertices.
  EXPECT_GT(vertexRmse(m.positions, test), 0.1);
}

TEST(NearestCorrespondence, SharedNearestVertexGoesToTheCloserTestVertex) {
  const std::vector<Vec3d> reference{{0, 0, 0}, {1, 0, 0}};
  // Both test vertices are nearest to reference 0; the closer one (distance 0.1) keeps it.
  EXPECT_EQ(nearestVertexCorrespondence(reference, {{0.1, 0, 0}, {0.2, 0, 0}}),
            (std::vector<uint32_t>{0, 1}));
  EXPECT_EQ(nearestVertexCorrespondence(reference, {{0.3, 0, 0}, {0.2, 0, 0}}),
            (std::vector<uint32_t>{1, 0}));
}

TEST(NearestCorrespondence, TiesGoToLowerIndices) {
  // Coincident vertices on both sides: lower test index takes the lower reference index.
  const std::vector<Vec3d> reference{{5, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  const std::vector<Vec3d> test{{0, 0, 0}, {0, 0, 0}, {5, 0, 0}, {0, 0, 0}};
  EXPECT_EQ(nearestVertexCorrespondence(reference, test), (std::vector<uint32_t>{1, 2, 0, 3}));
}

// Many coincident vertices (a collapsed region) and a test vertex nearer to one of them than to
// the rest: the same matching as the definition (each coincident reference vertex in index
// order), with coincident references searched as one point (their number no longer multiplies
// the search; 3dvo-metrics on 32,000 coincident vertices took 94 s).
TEST(NearestCorrespondence, ManyCoincidentVertices) {
  const size_t n = 20000;
  std::vector<Vec3d> reference(n, Vec3d{0, 0, 0}), test(n, Vec3d{0, 0, 0});
  reference[7] = {3, 0, 0};
  test[5] = {2.9, 0, 0};  // nearest to reference 7
  test[9] = {0.1, 0, 0};  // coincident references: the lowest free index, after the exact ones
  const std::vector<uint32_t> c = nearestVertexCorrespondence(reference, test);
  EXPECT_EQ(c[5], 7u);
  // The exact matches (distance 0) come first, in test index order, taking references 0, 1,
  // ... skipping 7; test 9 then takes the last free one.
  uint32_t next = 0;
  for (size_t i = 0; i < n; ++i) {
    if (i == 5 || i == 9) continue;
    if (next == 7) ++next;
    EXPECT_EQ(c[i], next++) << i;
  }
  EXPECT_EQ(c[9], n - 1);
}

TEST(NearestCorrespondence, RejectsMismatchedInput) {
  EXPECT_THROW(nearestVertexCorrespondence({{0, 0, 0}}, {{0, 0, 0}, {1, 1, 1}}), Error);
  EXPECT_THROW(nearestVertexCorrespondence({}, {}), Error);
  EXPECT_THROW(inReferenceOrder({{0, 0, 0}, {1, 1, 1}}, {0, 0}), Error);
  EXPECT_THROW(inReferenceOrder({{0, 0, 0}, {1, 1, 1}}, {0, 2}), Error);
  EXPECT_THROW(inReferenceOrder({{0, 0, 0}}, {0, 1}), Error);
}

TEST(NearestCorrespondence, QuantisedRealMeshStaysWithinHalfAGridCell) {
  // A real mesh quantised to the 3DVO grid and shuffled, as a decoded I mesh is: the matched
  // vertex errors must stay within the quantisation error (half a cell diagonal) except where
  // quantisation made reference vertices indistinguishable.
  const std::string path = std::string(TDVO_SHARED_DATA_DIR) + "/meshseq/horse-gallop/0001.obj.gz";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data not found: " << path;
  const Mesh reference = readObj(path);
  Vec3d lo, hi;
  boundingBox({reference}, lo, hi);
  const Grid grid = Grid::fromBounds(lo, hi, 12);
  const Mesh decoded = renumbered(grid.dequantise(grid.quantise(reference)),
                                  shuffled(reference.positions.size(), 99));
  const std::vector<Vec3d> aligned = inReferenceOrder(
      decoded.positions, nearestVertexCorrespondence(reference.positions, decoded.positions));
  const double bound = grid.step * std::sqrt(3.0) / 2 * (1 + 1e-9);
  size_t within = 0;
  for (size_t i = 0; i < aligned.size(); ++i) {
    const double dx = aligned[i][0] - reference.positions[i][0];
    const double dy = aligned[i][1] - reference.positions[i][1];
    const double dz = aligned[i][2] - reference.positions[i][2];
    within += std::sqrt(dx * dx + dy * dy + dz * dz) <= bound;
  }
  EXPECT_EQ(within, aligned.size());
  // And the surface distances see only the quantisation.
  EXPECT_LE(surfaceDistance(reference, decoded).hausdorff(), bound);
}

// ---- bounding box ----

TEST(BoundingBox, DiagonalOfExtendedBox) {
  BoundingBox box;
  EXPECT_EQ(box.diagonal(), 0.0);
  box.extend({{0, 0, 0}, {1, 2, 0}});
  box.extend({{0, 0, 2}});
  EXPECT_NEAR(box.diagonal(), 3.0, kEps);  // extent (1, 2, 2): sqrt(1 + 4 + 4)
}

// ---- the 3dvo-metrics app ----

const std::string kApp = std::string(TDVO_BIN_DIR) + "/3dvo-metrics";

// CSV rows as cells.
std::vector<std::vector<std::string>> readCsv(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  for (const std::string& line : test::lines(test::readText(path))) {
    std::vector<std::string> cells(1);
    for (char c : line) {
      if (c == ',')
        cells.emplace_back();
      else
        cells.back() += c;
    }
    rows.push_back(cells);
  }
  return rows;
}

size_t column(const std::vector<std::string>& header, const std::string& name) {
  const auto it = std::find(header.begin(), header.end(), name);
  if (it == header.end()) throw std::runtime_error("no CSV column " + name);
  return static_cast<size_t>(it - header.begin());
}

// A reference sequence (gzip OBJ, frames numbered from 1) and a "decoded" one (plain OBJ from
// 0) whose vertices are shuffled differently in each frame and moved by a constant offset.
struct AppFixture {
  test::TempDir dir{"metrics"};
  std::vector<Mesh> reference = test::wobblingSphere(2, 3);  // 162 vertices
  std::vector<Mesh> decoded;
  const Vec3d offset{0.001, -0.002, 0.002};  // length 0.003

  AppFixture() {
    std::filesystem::create_directories(dir.path() / "out");
    for (size_t f = 0; f < reference.size(); ++f) {
      Mesh d = renumbered(reference[f], shuffled(reference[f].positions.size(), 11 + f));
      for (Vec3d& p : d.positions)
        for (int k = 0; k < 3; ++k)
          p[k] += offset[k];
      test::writeGz(dir.file("ref_" + std::to_string(f + 1) + ".obj.gz"), formatObj(reference[f]));
      test::writeText(dir.file("out/000" + std::to_string(f) + ".obj"), formatObj(d));
      decoded.push_back(std::move(d));
    }
  }
};

TEST(MetricsApp, SequenceWithNearestCorrespondenceMatchesTheLibrary) {
  AppFixture fx;
  const test::CommandResult r =
      test::run(fx.dir, kApp,
                {"-r", "ref_%d.obj.gz", "--ReferenceFirstFrame=1", "-t", "out/%04d.obj",
                 "--Correspondence=nearest", "--CsvFile=m.csv"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto rows = readCsv(fx.dir.file("m.csv"));
  ASSERT_EQ(rows.size(), 1u + 3u + 1u);  // header, 3 frames (counted from the files), summary
  const auto& h = rows[0];
  EXPECT_EQ(rows[4][column(h, "frame")], "all");
  // Every vertex error is the offset: RMSE = D_A = |offset|; KG from the library.
  std::vector<std::vector<Vec3d>> refPositions, alignedPositions;
  for (size_t f = 0; f < 3; ++f) {
    refPositions.push_back(fx.reference[f].positions);
    alignedPositions.push_back(inReferenceOrder(
        fx.decoded[f].positions,
        nearestVertexCorrespondence(fx.reference[f].positions, fx.decoded[f].positions)));
  }
  EXPECT_NEAR(std::stod(rows[4][column(h, "vertex_rmse")]), 0.003, 1e-9);
  EXPECT_NEAR(std::stod(rows[4][column(h, "vertex_mean_error")]), 0.003, 1e-9);
  EXPECT_NEAR(std::stod(rows[4][column(h, "kg_error")]), kgError(refPositions, alignedPositions),
              1e-6);
  double hausdorffMax = 0;
  for (size_t f = 0; f < 3; ++f) {
    const SurfaceDistance d = surfaceDistance(fx.reference[f], fx.decoded[f]);
    hausdorffMax = std::max(hausdorffMax, d.hausdorff());
    EXPECT_EQ(rows[1 + f][column(h, "reference_frame")], std::to_string(f + 1));
    EXPECT_EQ(rows[1 + f][column(h, "test_frame")], std::to_string(f));
    EXPECT_NEAR(std::stod(rows[1 + f][column(h, "hausdorff_max")]), d.hausdorff(), 1e-9);
    EXPECT_NEAR(std::stod(rows[1 + f][column(h, "test_to_reference_mean")]), d.testToReference.mean,
                1e-9);
  }
  EXPECT_NEAR(std::stod(rows[4][column(h, "hausdorff_max")]), hausdorffMax, 1e-9);
  EXPECT_EQ(rows[4][column(h, "unit")], "absolute");
  // The text report carries the same summary.
  EXPECT_EQ(test::linesStartingWith(r.out, "D_A").size(), 1u);
  EXPECT_NE(r.out.find("KG error"), std::string::npos);
}

// A sequence whose first frame is missing on one side: the error names that side's file and
// the key that chose its number, not "A or B does not exist" (here ref_1.obj.gz exists and
// out/0001.obj does not: the test side starts at 0000).
TEST(MetricsApp, NoFramesToCompareNamesTheMissingSide) {
  AppFixture fx;
  test::CommandResult r = test::run(fx.dir, kApp,
                                    {"-r", "ref_%d.obj.gz", "--ReferenceFirstFrame=1", "-t",
                                     "out/%04d.obj", "--TestFirstFrame=3", "--CsvFile=m.csv"});
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("no frames to compare: 'out/0003.obj' (TestFirstFrame 3) does not exist"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("ref_1.obj.gz"), std::string::npos) << r.err;
  r = test::run(fx.dir, kApp, {"-r", "ref_%d.obj.gz", "-t", "out/%04d.obj", "--TestFirstFrame=7"});
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("'ref_0.obj.gz' (ReferenceFirstFrame 0) and 'out/0007.obj' "
                       "(TestFirstFrame 7) do not exist"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(fx.dir.file("m.csv")));
}

// Coordinates beyond 1e150 in magnitude would overflow the squared distances (infinite D_A, NaN
// KG error): an error naming the file and vertex. Up to there the figures are finite.
TEST(MetricsApp, CoordinatesWhereDistancesOverflowAreAnError) {
  test::TempDir dir("metrics-huge");
  for (const char* x : {"1e100", "2e100", "1e200", "2e200"})
    test::writeText(dir.file(std::string(x) + ".obj"),
                    std::string("v ") + x + " 0 0\nv 0 0 0\nv 0 1 0\nf 1 2 3\n");
  test::CommandResult r = test::run(dir, kApp, {"-r", "1e100.obj", "-t", "2e100.obj"});
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("Hausdorff max         : 1e+100"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("inf"), std::string::npos) << r.out;
  r = test::run(dir, kApp, {"-r", "1e100.obj", "-t", "2e200.obj", "--CsvFile=m.csv"});
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("2e200.obj: vertex 1 has a coordinate (2e+200) beyond 1e150 in magnitude"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("m.csv")));
  // And meshes so small that squared distances underflow: all figures were 0, exit 0.
  for (const char* s : {"1e-160", "1.01e-160"})
    test::writeText(dir.file(std::string(s) + ".obj"),
                    std::string("v 0 0 0\nv ") + s + " 0 0\nv 0 " + s + " 0\nf 1 2 3\n");
  r = test::run(dir, kApp, {"-r", "1e-160.obj", "-t", "1.01e-160.obj"});
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("1e-160.obj: the mesh is 1e-160 across, below 1e-140"), std::string::npos)
      << r.err;
}

// --CsvFile naming an input (a compared mesh, the GroupStarts file, a cfg file; under another
// name or a link) is refused before anything is written, and the input is left as it was: the
// CSV table replaced the reference mesh.
TEST(MetricsApp, CsvFileThatIsAnInputIsRefused) {
  AppFixture fx;
  test::writeText(fx.dir.file("starts.txt"), "0\n");
  test::writeText(fx.dir.file("m.cfg"), "Relative : false\n");
  std::filesystem::create_symlink("out/0001.obj", fx.dir.file("link.csv"));
  const std::vector<std::vector<std::string>> runs = {
      {"-r", "ref_%d.obj.gz", "--ReferenceFirstFrame=1", "-t", "out/%04d.obj",
       "--CsvFile=ref_2.obj.gz"},
      {"-r", "ref_%d.obj.gz", "--ReferenceFirstFrame=1", "-t", "out/%04d.obj",
       "--CsvFile=./out/../out/0002.obj"},
      {"-r", "ref_%d.obj.gz", "--ReferenceFirstFrame=1", "-t", "out/%04d.obj",
       "--CsvFile=link.csv"},
      {"-r", "ref_%d.obj.gz", "--ReferenceFirstFrame=1", "-t", "out/%04d.obj",
       "--Correspondence=nearest", "--GroupStarts=starts.txt", "--CsvFile=starts.txt"},
      {"-c", "m.cfg", "-r", "ref_1.obj.gz", "-t", "out/0000.obj", "--CsvFile=m.cfg"},
      {"-r", "ref_1.obj.gz", "-t", "out/0000.obj", "--CsvFile=out/0000.obj"}};
  for (const std::vector<std::string>& args : runs) {
    const std::string csv = args.back().substr(std::string("--CsvFile=").size());
    const std::string target = csv == "link.csv" ? "out/0001.obj" : csv;
    const std::string before = test::readText(fx.dir.file(target));
    const test::CommandResult r = test::run(fx.dir, kApp, args);
    EXPECT_EQ(r.exitCode, 1) << csv;
    EXPECT_NE(r.err.find(csv + ": is the input "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("refusing to overwrite it"), std::string::npos) << r.err;
    EXPECT_EQ(test::readText(fx.dir.file(target)), before) << csv;
  }
}

TEST(MetricsApp, IdentityCorrespondenceSeesTheShuffle) {
  AppFixture fx;
  const test::CommandResult r = test::run(fx.dir, kApp,
                                          {"-r", "ref_%d.obj.gz", "--ReferenceFirstFrame=1", "-t",
                                           "out/%04d.obj", "--FrameCount=2", "--CsvFile=m.csv"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto rows = readCsv(fx.dir.file("m.csv"));
  ASSERT_EQ(rows.size(), 1u + 2u + 1u);
  EXPECT_GT(std::stod(rows[3][column(rows[0], "vertex_rmse")]), 0.1);
}

TEST(MetricsApp, GroupCorrespondenceIsMadeAtTheFirstFrameOnly) {
  // With one group for all three frames, frames 1 and 2 reuse frame 0's matching; their own
  // shuffles differ, so their vertex errors are large, while frame 0's is the offset.
  AppFixture fx;
  const test::CommandResult r =
      test::run(fx.dir, kApp,
                {"-r", "ref_%d.obj.gz", "--ReferenceFirstFrame=1", "-t", "out/%04d.obj",
                 "--Correspondence=nearest", "--GroupSize=3", "--CsvFile=m.csv"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto rows = readCsv(fx.dir.file("m.csv"));
  const size_t rmse = column(rows[0], "vertex_rmse");
  EXPECT_NEAR(std::stod(rows[1][rmse]), 0.003, 1e-9);
  EXPECT_GT(std::stod(rows[2][rmse]), 0.1);
}

TEST(MetricsApp, GroupStartsFromAFileMakeTheMatchingAtEachListedFrame) {
  // Groups of different lengths, as 3dvo-dec's gom_starts.txt gives them: frames 0-1 and 2.
  // Frames 0 and 2 are matched on their own (the offset only), frame 1 reuses frame 0's.
  AppFixture fx;
  test::writeText(fx.dir.file("out/gom_starts.txt"), "# first frame of each GOM\n0\n2\n");
  // The comparison of the fixture's sequences, matched as `groups` say.
  auto compare = [&fx](std::vector<std::string> groups) {
    std::vector<std::string> args = {"-r",
                                     "ref_%d.obj.gz",
                                     "--ReferenceFirstFrame=1",
                                     "-t",
                                     "out/%04d.obj",
                                     "--Correspondence=nearest",
                                     "--CsvFile=m.csv"};
    args.insert(args.end(), groups.begin(), groups.end());
    return test::run(fx.dir, kApp, args);
  };
  const test::CommandResult r = compare({"--GroupStarts=out/gom_starts.txt"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto rows = readCsv(fx.dir.file("m.csv"));
  const size_t rmse = column(rows[0], "vertex_rmse");
  EXPECT_NEAR(std::stod(rows[1][rmse]), 0.003, 1e-9);
  EXPECT_GT(std::stod(rows[2][rmse]), 0.1);
  EXPECT_NEAR(std::stod(rows[3][rmse]), 0.003, 1e-9);
  EXPECT_NE(r.out.find("2 groups"), std::string::npos) << r.out;

  // Both ways of giving groups, or a bad line, is an error naming the cause; no CSV is left.
  std::filesystem::remove(fx.dir.file("m.csv"));
  const test::CommandResult both = compare({"--GroupSize=2", "--GroupStarts=out/gom_starts.txt"});
  EXPECT_EQ(both.exitCode, 1);
  EXPECT_NE(both.err.find("not both"), std::string::npos) << both.err;
  test::writeText(fx.dir.file("bad.txt"), "0\n2 x\n");
  const test::CommandResult bad = compare({"--GroupStarts=bad.txt"});
  EXPECT_EQ(bad.exitCode, 1);
  EXPECT_NE(bad.err.find("bad.txt:2"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(fx.dir.file("m.csv")));
}

TEST(MetricsApp, RelativeDistancesAreDividedByTheReferenceDiagonal) {
  AppFixture fx;
  const test::CommandResult r =
      test::run(fx.dir, kApp,
                {"-r", "ref_1.obj.gz", "-t", "out/0000.obj", "--Correspondence=nearest",
                 "--Relative", "--CsvFile=m.csv"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto rows = readCsv(fx.dir.file("m.csv"));
  ASSERT_EQ(rows.size(), 3u);  // header, the one pair, summary
  BoundingBox box;
  box.extend(fx.reference[0].positions);
  const auto& h = rows[0];
  EXPECT_EQ(rows[2][column(h, "unit")], "diagonal");
  EXPECT_NEAR(std::stod(rows[2][column(h, "diagonal")]), box.diagonal(), 1e-9);
  EXPECT_NEAR(std::stod(rows[2][column(h, "vertex_rmse")]), 0.003 / box.diagonal(), 1e-9);
  EXPECT_NEAR(std::stod(rows[2][column(h, "hausdorff_max")]),
              surfaceDistance(fx.reference[0], fx.decoded[0]).hausdorff() / box.diagonal(), 1e-9);
}

TEST(MetricsApp, DifferentVertexCountsGiveSurfaceDistancesOnly) {
  test::TempDir dir("metrics");
  test::writeText(dir.file("a.obj"), formatObj(planeGrid(5, 1.0, 0.0)));
  test::writeText(dir.file("b.obj"), formatObj(planeGrid(3, 1.0, 0.5)));
  const test::CommandResult r =
      test::run(dir, kApp, {"-r", "a.obj", "-t", "b.obj", "--CsvFile=m.csv"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto rows = readCsv(dir.file("m.csv"));
  const auto& h = rows[0];
  EXPECT_NEAR(std::stod(rows[2][column(h, "hausdorff_max")]), 0.5, 1e-12);
  EXPECT_EQ(rows[2][column(h, "vertex_rmse")], "");
  EXPECT_EQ(rows[2][column(h, "kg_error")], "");
  EXPECT_EQ(rows[2][column(h, "sted_s")], "");
  EXPECT_NE(r.out.find("no vertex errors"), std::string::npos);
  EXPECT_NE(r.out.find("no STED"), std::string::npos);
}

TEST(MetricsApp, StedOfASequenceInTheInputsOrderMatchesTheLibrary) {
  test::TempDir dir("metrics");
  const NoisySphere s;
  std::vector<Mesh> reference, decoded;  // as read back from the files
  for (size_t f = 0; f < s.reference.size(); ++f) {
    test::writeText(dir.file("ref_" + std::to_string(f) + ".obj"), formatObj(s.reference[f]));
    test::writeText(dir.file("dec_" + std::to_string(f) + ".obj"), formatObj(s.test[f]));
    reference.push_back(readObj(dir.file("ref_" + std::to_string(f) + ".obj")));
    decoded.push_back(readObj(dir.file("dec_" + std::to_string(f) + ".obj")));
  }
  StedParams params;
  params.width = 0.1;
  params.timeStep = 0.5;
  params.temporalWeight = 3;
  const StedAccumulator expected = sted(reference, decoded, params);
  const test::CommandResult r =
      test::run(dir, kApp,
                {"-r", "ref_%d.obj", "-t", "dec_%d.obj", "--StedWidth=0.1", "--StedTimeStep=0.5",
                 "--StedWeight=3", "--CsvFile=m.csv"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto rows = readCsv(dir.file("m.csv"));
  ASSERT_EQ(rows.size(), 1u + 4u + 1u);
  const auto& h = rows[0];
  EXPECT_NEAR(std::stod(rows[5][column(h, "sted_s")]), expected.spatial(), 1e-9);
  EXPECT_NEAR(std::stod(rows[5][column(h, "sted_t")]), *expected.temporal(), 1e-9);
  EXPECT_NEAR(std::stod(rows[5][column(h, "sted")]), *expected.combined(), 1e-9);
  EXPECT_EQ(rows[1][column(h, "sted")], "");  // summary only
  EXPECT_EQ(test::linesStartingWith(r.out, "STED_s").size(), 1u);
  EXPECT_NE(r.out.find("w 0.1, dt 0.5, c 3"), std::string::npos) << r.out;

  // Matched by nearest vertices the order is not the input's: no STED, and the report says why.
  const test::CommandResult nearest = test::run(
      dir, kApp,
      {"-r", "ref_%d.obj", "-t", "dec_%d.obj", "--Correspondence=nearest", "--CsvFile=n.csv"});
  ASSERT_EQ(nearest.exitCode, 0) << nearest.err;
  EXPECT_EQ(readCsv(dir.file("n.csv"))[5][column(h, "sted")], "");
  EXPECT_NE(nearest.out.find("no STED"), std::string::npos) << nearest.out;
}

TEST(MetricsApp, MissingFrameIsAnErrorNamingTheFileAndLeavesNoCsv) {
  AppFixture fx;
  const test::CommandResult r = test::run(fx.dir, kApp,
                                          {"-r", "ref_%d.obj.gz", "--ReferenceFirstFrame=1", "-t",
                                           "out/%04d.obj", "--FrameCount=4", "--CsvFile=m.csv"});
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("ref_4.obj.gz"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(fx.dir.file("m.csv")));
}

TEST(MetricsApp, MixingAFileAndAPatternIsAnError) {
  AppFixture fx;
  const test::CommandResult r =
      test::run(fx.dir, kApp, {"-r", "ref_1.obj.gz", "-t", "out/%04d.obj"});
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("both"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace tdvo
