// The integer geometry grid (common/core/grid.h): construction from bounds, quantisation error,
// clamping, degenerate boxes and the range of bit depths.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "common/core/error.h"
#include "common/core/grid.h"

namespace tdvo {
namespace {

TEST(Grid, FromBounds) {
  const Grid g = Grid::fromBounds({-1, 2, 10}, {3, 4, 11}, 12);
  EXPECT_EQ(g.bits, 12);
  EXPECT_EQ(g.origin, (Vec3d{-1, 2, 10}));
  EXPECT_EQ(g.step, 4.0 / 4095);  // the largest extent spans the full range
  EXPECT_EQ(g.maxCoordinate(), 4095);
  EXPECT_EQ(g.quantise(Vec3d{-1, 2, 10}), (Vec3i{0, 0, 0}));
  EXPECT_EQ(g.quantise(Vec3d{3, 4, 11}), (Vec3i{4095, 2048, 1024}));
  EXPECT_EQ(g.quantise(Vec3d{1, 3, 10.5}), (Vec3i{2048, 1024, 512}));
}

TEST(Grid, BitsRange) {
  for (int bits = Grid::kMinBits; bits <= Grid::kMaxBits; ++bits) {
    const Grid g = Grid::fromBounds({0, 0, 0}, {1, 1, 1}, bits);
    EXPECT_EQ(g.maxCoordinate(), (1 << bits) - 1);
    EXPECT_EQ(g.quantise(Vec3d{1, 1, 1}),
              (Vec3i{(1 << bits) - 1, (1 << bits) - 1, (1 << bits) - 1}));
  }
  EXPECT_EQ(Grid::kMinBits, 8);
  EXPECT_EQ(Grid::kMaxBits, 20);
  for (int bits : {-1, 0, 7, 21, 32})
    try {
      Grid::fromBounds({0, 0, 0}, {1, 1, 1}, bits);
      ADD_FAILURE() << bits;
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()), "grid bits must be in [8, 20]");
    }
}

// Every point inside the box comes back within half a step per axis.
TEST(Grid, QuantisationErrorIsAtMostHalfAStep) {
  std::mt19937_64 random(12345);
  for (int bits : {8, 10, 12, 16, 20}) {
    const Vec3d lo{-3.5, 0.25, 100}, hi{2.0, 1.0, 104.5};
    const Grid g = Grid::fromBounds(lo, hi, bits);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    double worst = 0;
    for (int i = 0; i < 20000; ++i) {
      Vec3d p;
      for (int a = 0; a < 3; ++a)
        p[a] = lo[a] + u(random) * (hi[a] - lo[a]);
      const Vec3i q = g.quantise(p);
      const Vec3d back = g.dequantise(q);
      for (int a = 0; a < 3; ++a) {
        ASSERT_GE(q[a], 0);
        ASSERT_LE(q[a], g.maxCoordinate());
        const double error = std::fabs(back[a] - p[a]);
        worst = std::max(worst, error / g.step);
        // A rounding error of a few ulps of the coordinates is all that is allowed on top.
        ASSERT_LE(error, g.step / 2 + 1e-12 * (1 + std::fabs(p[a])))
            << "bits " << bits << " axis " << a << " p " << p[a];
      }
      // Quantising the dequantised point gives the same integers (idempotent on the grid).
      ASSERT_EQ(g.quantise(back), q);
    }
    // The bound is tight: random points come close to half a step.
    EXPECT_GT(worst, 0.49) << bits;
  }
}

TEST(Grid, NearestGridPoint) {
  const Grid g = Grid::fromBounds({0, 0, 0}, {255, 1, 1}, 8);  // step exactly 1
  ASSERT_EQ(g.step, 1.0);
  EXPECT_EQ(g.quantise(Vec3d{0.49, 1.51, 2.2}), (Vec3i{0, 2, 2}));
  EXPECT_EQ(g.quantise(Vec3d{0.5, 1.5, 254.5}), (Vec3i{1, 2, 255}));  // halves round up
  EXPECT_EQ(g.dequantise(Vec3i{7, 8, 9}), (Vec3d{7, 8, 9}));
}

TEST(Grid, ClampsOutsideTheGrid) {
  const Grid g = Grid::fromBounds({0, 0, 0}, {10, 1, 1}, 8);
  const int32_t m = g.maxCoordinate();
  EXPECT_EQ(g.quantise(Vec3d{-5, -0.1, -1e300}), (Vec3i{0, 0, 0}));
  EXPECT_EQ(g.quantise(Vec3d{10.5, 20, 1e300}), (Vec3i{m, m, m}));
  // The grid is a cube of the largest extent: a point outside the box on a short axis but
  // inside the cube is not clamped.
  EXPECT_EQ(g.quantise(Vec3d{0, 5, 10}), (Vec3i{0, 128, m}));
}

TEST(Grid, DegenerateBox) {
  const Grid g = Grid::fromBounds({1, 2, 3}, {1, 2, 3}, 12);
  EXPECT_EQ(g.step, 1.0);
  EXPECT_EQ(g.origin, (Vec3d{1, 2, 3}));
  EXPECT_EQ(g.quantise(Vec3d{1, 2, 3}), (Vec3i{0, 0, 0}));
  EXPECT_EQ(g.quantise(Vec3d{1.4, 2.6, 0}), (Vec3i{0, 1, 0}));
  EXPECT_EQ(g.dequantise(Vec3i{0, 0, 0}), (Vec3d{1, 2, 3}));
  // Flat in two axes only: the third axis sets the step.
  const Grid flat = Grid::fromBounds({0, 0, 0}, {0, 0, 2}, 8);
  EXPECT_EQ(flat.step, 2.0 / 255);
  EXPECT_EQ(flat.quantise(Vec3d{0, 0, 2}), (Vec3i{0, 0, 255}));
}

TEST(Grid, MeshQuantisationKeepsConnectivity) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0.5}};
  m.triangles = {{0, 1, 2}};
  const Grid g = Grid::fromBounds({0, 0, 0}, {1, 1, 1}, 8);
  const IntMesh q = g.quantise(m);
  EXPECT_EQ(q.positions, (std::vector<Vec3i>{{0, 0, 0}, {255, 0, 0}, {0, 255, 128}}));
  EXPECT_EQ(q.triangles, m.triangles);
  const Mesh back = g.dequantise(q);
  EXPECT_EQ(back.triangles, m.triangles);
  EXPECT_EQ(back.positions[1], (Vec3d{1, 0, 0}));
  EXPECT_EQ(back.positions[2][2], 128.0 / 255);
}

TEST(Grid, BoundingBox) {
  Mesh a, b;
  a.positions = {{1, 5, -2}, {3, 4, 0}};
  b.positions = {{-1, 6, 1}};
  Vec3d lo, hi;
  boundingBox({a, b}, lo, hi);
  EXPECT_EQ(lo, (Vec3d{-1, 4, -2}));
  EXPECT_EQ(hi, (Vec3d{3, 6, 1}));
  EXPECT_THROW(boundingBox({Mesh(), Mesh()}, lo, hi), Error);
  EXPECT_THROW(boundingBox({}, lo, hi), Error);
}

}  // namespace
}  // namespace tdvo
