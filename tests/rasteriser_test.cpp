// The rasteriser: exact coverage (top-left rule, no gaps or double coverage on shared edges),
// clipping, z-buffer, perspective-correct interpolation, distortion.
#include "common/views/rasteriser.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/core/error.h"

using namespace tdvo;

namespace {

// A pinhole camera at the origin looking along +z (R = I, t = 0).
Camera frontCamera(int width = 64, int height = 48, double f = 50) {
  Camera c;
  c.name = "front";
  c.width = width;
  c.height = height;
  c.fx = c.fy = f;
  c.cx = 0.5 * (width - 1);
  c.cy = 0.5 * (height - 1);
  return c;
}

// The world point at camera depth z that projects to pixel coordinates (x, y) of `c` (R = I).
Vec3d atPixel(const Camera& c, double x, double y, double z) {
  return {(x - c.cx) / c.fx * z, (y - c.cy) / c.fy * z, z};
}

// How many triangles of `mesh` cover each pixel (each triangle rasterised on its own).
std::vector<int> coverageCount(const Mesh& mesh, const Camera& c) {
  std::vector<int> count(static_cast<size_t>(c.width * c.height), 0);
  for (const Triangle& t : mesh.triangles) {
    Mesh one;
    one.positions = mesh.positions;
    one.triangles = {t};
    const Image m = renderMask(one, c);
    for (size_t i = 0; i < count.size(); ++i)
      count[i] += m.pixels[i] ? 1 : 0;
  }
  return count;
}

// An axis-aligned box as 12 triangles, counter-clockwise seen from outside.
Mesh box(const Vec3d& lo, const Vec3d& hi) {
  Mesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.push_back(
        {(i & 1) ? hi[0] : lo[0], (i & 2) ? hi[1] : lo[1], (i & 4) ? hi[2] : lo[2]});
  m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return m;
}

}  // namespace

TEST(Rasteriser, TopLeftRuleOnPixelCentres) {
  const Camera c = frontCamera();
  // A right triangle whose corners lie exactly on pixel centres (2,2), (10,2), (2,10).
  Mesh m;
  m.positions = {atPixel(c, 2, 2, 5), atPixel(c, 10, 2, 5), atPixel(c, 2, 10, 5)};
  m.triangles = {{0, 1, 2}};
  const Image mask = renderMask(m, c);
  // Left edge x = 2 and top edge y = 2 are owned; the hypotenuse x + y = 12 (a right/bottom
  // edge) is not. Covered: x ≥ 2, y ≥ 2, x + y < 12.
  int covered = 0;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      const bool expected = x >= 2 && y >= 2 && x + y < 12;
      EXPECT_EQ(mask.at(x, y) != 0, expected) << "pixel " << x << "," << y;
      covered += mask.at(x, y) != 0;
    }
  EXPECT_EQ(covered, 36);
  // The same triangle listed clockwise covers the same pixels (both sides are drawn).
  m.triangles = {{0, 2, 1}};
  EXPECT_EQ(renderMask(m, c), mask);
}

TEST(Rasteriser, SharedEdgesCoverEachPixelOnce) {
  const Camera c = frontCamera(80, 60);
  // A jittered grid of quads, each split in two, filling a rectangle; corners snapped to pixel
  // centres on purpose in half of the rows so that many centres lie exactly on edges.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.45, 0.45);
  Mesh m;
  const int nx = 9, ny = 7;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      double x = 5 + i * 7.0, y = 4 + j * 7.0;
      if (i > 0 && i < nx && j > 0 && j < ny && (j % 2)) x += jitter(rng), y += jitter(rng);
      m.positions.push_back(atPixel(c, x, y, 3 + 0.05 * i));
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const uint32_t a = j * (nx + 1) + i, b = a + 1, d = a + (nx + 1), e = d + 1;
      if ((i + j) % 2) {
        m.triangles.push_back({a, b, e});
        m.triangles.push_back({a, e, d});
      } else {
        m.triangles.push_back({a, b, d});
        m.triangles.push_back({b, e, d});
      }
    }
  const std::vector<int> count = coverageCount(m, c);
  // Inside the rectangle spanned by the outer corners (pixel centres 5..68 × 4..53), every
  // centre is covered exactly once; outside, none. Outer edges: left/top owned, right/bottom not.
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      const bool inside = x >= 5 && x < 68 && y >= 4 && y < 53;
      EXPECT_EQ(count[static_cast<size_t>(y * c.width + x)], inside ? 1 : 0)
          << "pixel " << x << "," << y;
    }
}

TEST(Rasteriser, FanAroundAVertexHasNoGapsOrOverlaps) {
  const Camera c = frontCamera(64, 64, 60);
  Mesh m;
  m.positions.push_back(atPixel(c, 31, 31, 4));  // centre exactly on a pixel centre
  const int n = 17;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * 3.14159265358979 * k / n;
    m.positions.push_back(atPixel(c, 31 + 25 * std::cos(a), 31 + 25 * std::sin(a), 4));
  }
  for (int k = 0; k < n; ++k)
    m.triangles.push_back(
        {0, static_cast<uint32_t>(1 + k), static_cast<uint32_t>(1 + (k + 1) % n)});
  const std::vector<int> count = coverageCount(m, c);
  const Image mask = renderMask(m, c);
  for (size_t i = 0; i < count.size(); ++i) {
    EXPECT_LE(count[i], 1);
    EXPECT_EQ(count[i] == 1, mask.pixels[i] != 0);
  }
  EXPECT_EQ(count[31 * 64 + 31], 1);  // the shared vertex's pixel belongs to exactly one triangle
}

TEST(Rasteriser, CoveredAreaMatchesGeometry) {
  const Camera c = frontCamera(200, 200, 100);
  Mesh m;
  m.positions = {atPixel(c, 10.3, 20.7, 2), atPixel(c, 180.2, 40.1, 2), atPixel(c, 60.6, 190.9, 2)};
  m.triangles = {{0, 1, 2}};
  const Image mask = renderMask(m, c);
  size_t covered = 0;
  for (uint8_t v : mask.pixels)
    covered += v != 0;
  const double area =
      0.5 * std::fabs((180.2 - 10.3) * (190.9 - 20.7) - (40.1 - 20.7) * (60.6 - 10.3));
  EXPECT_NEAR(static_cast<double>(covered), area, 0.01 * area);
}

TEST(Rasteriser, PerspectiveCorrectInterpolation) {
  // A quad strongly inclined in depth: the interpolated world position must lie on each pixel's
  // ray (screen-space interpolation would not).
  const Camera c = frontCamera(96, 72, 70);
  Mesh m;
  m.positions = {{-3, -1, 2}, {3, -1, 2}, {3, 1, 14}, {-3, 1, 14}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  const Fragments f = rasterise(m, c);
  int covered = 0;
  double worst = 0;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      if (f.triangle[f.index(x, y)] < 0) continue;
      ++covered;
      const Vec3d p = interpolate(f, m, m.positions, x, y);
      Vec2d pixel;
      ASSERT_TRUE(c.project(p, pixel));
      worst = std::max({worst, std::fabs(pixel[0] - x), std::fabs(pixel[1] - y)});
      EXPECT_NEAR(f.depth[f.index(x, y)], p[2], 1e-4 * p[2]);
      const auto& b = f.barycentric[f.index(x, y)];
      EXPECT_NEAR(b[0] + b[1] + b[2], 1.0, 1e-6);
    }
  EXPECT_GT(covered, 1000);
  EXPECT_LT(worst, 0.01) << "interpolated points must project back onto their pixel";
}

TEST(Rasteriser, DepthTestKeepsTheNearestSurface) {
  const Camera c = frontCamera();
  Mesh m;
  // Triangle 0 far (z = 8), triangle 1 near (z = 4), overlapping in the image.
  m.positions = {atPixel(c, 5, 5, 8),   atPixel(c, 50, 5, 8),  atPixel(c, 5, 40, 8),
                 atPixel(c, 10, 10, 4), atPixel(c, 60, 10, 4), atPixel(c, 10, 45, 4)};
  m.triangles = {{0, 1, 2}, {3, 4, 5}};
  for (int order = 0; order < 2; ++order) {
    const Fragments f = rasterise(m, c);
    const size_t overlap = f.index(15, 15), farOnly = f.index(6, 6), none = f.index(62, 46);
    EXPECT_EQ(f.triangle[overlap], order == 0 ? 1 : 0);
    EXPECT_NEAR(f.depth[overlap], 4, 1e-9);
    EXPECT_NEAR(f.depth[farOnly], 8, 1e-9);
    EXPECT_EQ(f.triangle[none], -1);
    EXPECT_TRUE(std::isinf(f.depth[none]));
    std::swap(m.triangles[0], m.triangles[1]);  // drawing order must not matter
  }
  const std::vector<float> depth = renderDepth(m, c);
  EXPECT_NEAR(depth[static_cast<size_t>(15 * c.width + 15)], 4, 1e-9);
}

TEST(Rasteriser, NearPlaneClippingOfAGroundPlane) {
  // A huge floor one unit below the camera (camera y points down), extending behind it: it
  // covers exactly the pixel rows below the horizon (y > cy).
  const Camera c = frontCamera(64, 48, 40);
  Mesh m;
  m.positions = {{-1e4, 1, -1e4}, {1e4, 1, -1e4}, {1e4, 1, 1e4}, {-1e4, 1, 1e4}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  const Image mask = renderMask(m, c);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x)
      EXPECT_EQ(mask.at(x, y) != 0, y > c.cy) << "pixel " << x << "," << y;
  // Everything behind the camera: nothing drawn.
  Mesh behind = box({-1, -1, -5}, {1, 1, -3});
  const Image empty = renderMask(behind, c);
  for (uint8_t v : empty.pixels)
    EXPECT_EQ(v, 0);
}

TEST(Rasteriser, BackFaceCullingOnAClosedBox) {
  Camera c = frontCamera(64, 48, 40);
  lookAt(c, {3, 2, -4}, {0, 0, 0}, {0, -1, 0});
  const Mesh m = box({-1, -1, -1}, {1, 1, 1});
  RasterOptions cull;
  cull.cullBackFaces = true;
  // From outside a closed convex box, the front faces alone give the same silhouette.
  EXPECT_EQ(renderMask(m, c, cull), renderMask(m, c));
  // From inside, every face is a back face.
  lookAt(c, {0.1, 0.2, 0.3}, {0, 0, 1}, {0, -1, 0});
  const Image inside = renderMask(m, c, cull);
  for (uint8_t v : inside.pixels)
    EXPECT_EQ(v, 0);
  const Image insideBoth = renderMask(m, c);
  for (uint8_t v : insideBoth.pixels)
    EXPECT_EQ(v, 255);
}

TEST(Rasteriser, DistortedCameraMatchesResampledPinholeRender) {
  Camera c;
  c.name = "distorted";
  c.width = 160;
  c.height = 120;
  c.fx = c.fy = 120;
  c.cx = 79.5;
  c.cy = 59.5;
  c.distortion = {-0.3, 0.1, 0.001, -0.001, 0};
  lookAt(c, {0.5, -0.4, -3}, {0, 0, 0}, {0, -1, 0});
  // A finely tessellated box (each face 8×8 quads) so that straight edges follow the lens.
  Mesh m;
  const Mesh coarse = box({-0.9, -0.6, -0.7}, {0.9, 0.6, 0.7});
  for (const Triangle& t : coarse.triangles) {
    const Vec3d a = coarse.positions[t[0]], b = coarse.positions[t[1]], d = coarse.positions[t[2]];
    const int n = 8;
    const uint32_t base = static_cast<uint32_t>(m.positions.size());
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n - i; ++j)
        m.positions.push_back(a + (double(i) / n) * (b - a) + (double(j) / n) * (d - a));
    auto id = [&](int i, int j) {
      return base + static_cast<uint32_t>(i * (n + 1) - i * (i - 1) / 2 + j);
    };
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n - i; ++j) {
        m.triangles.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
        if (j + 1 < n - i) m.triangles.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
  }
  const Image direct = renderMask(m, c);
  const Image resampled = distortImage(renderMask(m, c.withoutDistortion()), c);
  size_t both = 0, either = 0;
  for (size_t i = 0; i < direct.pixels.size(); ++i) {
    const bool a = direct.pixels[i] != 0, b = resampled.pixels[i] >= 128;
    both += a && b;
    either += a || b;
  }
  ASSERT_GT(either, 1000u);
  EXPECT_GT(double(both) / double(either), 0.98) << "IoU of direct vs resampled render";
}

TEST(Rasteriser, SameInputSameMaskAndNoCracksWhenClipped) {
  // Triangles crossing the near plane share their clipped edges exactly: a closed box around
  // the camera's near plane renders without holes along the clipped edges.
  Camera c = frontCamera(64, 48, 40);
  const Mesh floor = [] {
    Mesh m;
    for (int j = 0; j <= 6; ++j)
      for (int i = 0; i <= 6; ++i)
        m.positions.push_back({-30 + 10.0 * i + 0.3 * j, 1, -30 + 10.0 * j + 0.2 * i});
    for (uint32_t j = 0; j < 6; ++j)
      for (uint32_t i = 0; i < 6; ++i) {
        const uint32_t a = j * 7 + i;
        m.triangles.push_back({a, a + 1, a + 8});
        m.triangles.push_back({a, a + 8, a + 7});
      }
    return m;
  }();
  const Image a = renderMask(floor, c), b = renderMask(floor, c);
  EXPECT_EQ(a, b);
  const std::vector<int> count = coverageCount(floor, c);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      const int n = count[static_cast<size_t>(y * c.width + x)];
      if (y > c.cy + 1) {
        EXPECT_EQ(n, 1) << "pixel " << x << "," << y;
      } else if (y < c.cy) {
        EXPECT_EQ(n, 0) << "pixel " << x << "," << y;
      }
    }
}

TEST(Rasteriser, LensThatFoldsBeforeTheImageCorners) {
  // The uu-4cam calibration of camera 1: its distortion folds back just before the image
  // corners. A plane filling the view covers every pixel the model reaches and none beyond.
  Camera c;
  c.name = "uu1";
  c.width = 644;
  c.height = 486;
  c.fx = 490.756439;
  c.fy = 493.263580;
  c.cx = 334.690674;
  c.cy = 222.398880;
  c.distortion = {-0.368704915, 0.203186616, 3.26540467e-04, 1.78072587e-05, -0.0712014362};
  Mesh wall;
  wall.positions = {{-1e4, -1e4, 1000}, {1e4, -1e4, 1000}, {1e4, 1e4, 1000}, {-1e4, 1e4, 1000}};
  wall.triangles = {{0, 1, 2}, {0, 2, 3}};
  const Image mask = renderMask(wall, c);
  const double reach = largestDistortedRadius(c.distortion);
  size_t beyond = 0, uncoveredInside = 0;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      const Vec2d n = c.pixelToNormalised({double(x), double(y)});
      const double r = std::sqrt(n[0] * n[0] + n[1] * n[1]);
      // (The radial estimate of the fold ignores the small tangential terms: a band of 0.2 %
      // around it is left unchecked.)
      if (r >= 1.002 * reach) {
        ++beyond;
        EXPECT_EQ(mask.at(x, y), 0) << "pixel " << x << "," << y << " is beyond the lens's fold";
      } else if (r < 0.99 * reach) {
        uncoveredInside += mask.at(x, y) == 0;
      }
    }
  EXPECT_GT(beyond, 0u);
  EXPECT_EQ(uncoveredInside, 0u);
}

TEST(Rasteriser, NonFiniteCornersCoverNothing) {
  const Camera c = frontCamera();
  Mesh m;
  m.positions = {
      atPixel(c, 2, 2, 5), atPixel(c, 10, 2, 5), atPixel(c, 2, 10, 5), {std::nan(""), 0, 5}};
  m.triangles = {{0, 1, 3}, {0, 1, 2}};
  const Image mask = renderMask(m, c);
  size_t covered = 0;
  for (uint8_t v : mask.pixels)
    covered += v != 0;
  EXPECT_EQ(covered, 36u);  // only the finite triangle
  m.triangles.push_back({0, 1, 7});
  EXPECT_THROW(renderMask(m, c), Error);
}
