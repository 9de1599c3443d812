// Reconstruction: marching cubes table, octree carving, surface clean-up, tracking, and the
// synthetic-rig acceptance (ground truth known).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <random>

#include "common/core/config.h"
#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/obj_io.h"
#include "common/core/sequence.h"
#include "common/views/rasteriser.h"
#include "tests/test_support.h"
#include "tools/eval/metrics.h"
#include "tools/eval/sample_mesh.h"
#include "tools/multiview/synth_rig.h"
#include "tools/recon/carving_view.h"
#include "tools/recon/closest_point.h"
#include "tools/recon/gom_builder.h"
#include "tools/recon/marching_cubes.h"
#include "tools/recon/recon_pipeline.h"
#include "tools/recon/silhouettes.h"
#include "tools/recon/surface_processing.h"
#include "tools/recon/tracking.h"
#include "tools/recon/visual_hull.h"

using namespace tdvo;

namespace {

// Checks that a mesh is closed and consistently oriented: every directed edge appears exactly
// once and its reverse exactly once.
void expectClosedOriented(const Mesh& mesh) {
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (const Triangle& t : mesh.triangles)
    for (size_t k = 0; k < 3; ++k)
      ++edges[{t[k], t[(k + 1) % 3]}];
  size_t bad = 0;
  for (const auto& [e, n] : edges)
    if (n != 1 || edges.count({e.second, e.first}) != 1) ++bad;
  EXPECT_EQ(bad, 0u) << "directed edges used twice or without their reverse";
}

// A sphere of radius `r` at `c` as a fine icosphere.
Mesh sphere(const Vec3d& c, double r, int subdivisions = 4) {
  Mesh m = icosphere(subdivisions);
  for (Vec3d& p : m.positions)
    p = c + r * p;
  return m;
}

// `count` cameras on a ring around `centre` (the synthetic rig's layout), `width` × `height`.
std::vector<Camera> ringCameras(int count, const Vec3d& centre, double radius, int width = 320,
                                int height = 240) {
  SynthParams p;
  p.cameras = count;
  p.width = width;
  p.height = height;
  return makeRigCameras(p, centre, radius);
}

std::vector<CarvingView> viewsOf(const Mesh& mesh, const std::vector<Camera>& cameras,
                                 std::vector<Image>* masks = nullptr) {
  std::vector<CarvingView> views;
  for (const Camera& c : cameras) {
    const Image mask = renderMask(mesh, c);
    views.emplace_back(CanvasMap::build(c), mask);
    if (masks) masks->push_back(mask);
  }
  return views;
}

// The smallest IoU of a mesh's reprojection with the given masks.
double worstIoU(const Mesh& mesh, const std::vector<Camera>& cameras,
                const std::vector<Image>& masks) {
  double worst = 1;
  for (size_t c = 0; c < cameras.size(); ++c)
    worst = std::min(worst, maskIoU(renderMask(mesh, cameras[c]), masks[c]));
  return worst;
}

// Marching cubes over a dense grid of values (corners on the grid's faces must be negative for
// a closed result).
Mesh denseMarchingCubes(const std::vector<float>& value, int corners, double step) {
  MarchingCubesMesher mesher({0, 0, 0}, step, corners);
  auto at = [&](int i, int j, int k) {
    return value[static_cast<size_t>((k * corners + j) * corners + i)];
  };
  for (int k = 0; k + 1 < corners; ++k)
    for (int j = 0; j + 1 < corners; ++j)
      for (int i = 0; i + 1 < corners; ++i) {
        std::array<float, 8> v;
        for (int c = 0; c < 8; ++c)
          v[static_cast<size_t>(c)] = at(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
        mesher.addCube(i, j, k, v);
      }
  return mesher.mesh();
}

}  // namespace

TEST(MarchingCubes, TableCases) {
  const auto& table = marchingCubesTable();
  EXPECT_TRUE(table[0].empty());
  EXPECT_TRUE(table[255].empty());
  // One corner inside: one triangle; an edge's two corners: a quad; a face's four: a quad.
  EXPECT_EQ(table[1].size(), 1u);
  EXPECT_EQ(table[0x80].size(), 1u);
  EXPECT_EQ(table[0x03].size(), 2u);
  EXPECT_EQ(table[0x0f].size(), 2u);
  // Two diagonal corners of a face (0 and 3): an ambiguous face, separated: two triangles.
  EXPECT_EQ(table[0x09].size(), 2u);
  // Every triangle of every case uses crossed edges only.
  for (int c = 0; c < 256; ++c)
    for (const auto& t : table[static_cast<size_t>(c)])
      for (uint8_t e : t) {
        const bool a = (c >> kCubeEdgeCorners[e][0]) & 1, b = (c >> kCubeEdgeCorners[e][1]) & 1;
        EXPECT_NE(a, b) << "case " << c << " edge " << int(e);
      }
}

TEST(MarchingCubes, RandomFieldsGiveClosedOrientedSurfaces) {
  // Random signs exercise every case and every ambiguous face next to every other.
  std::mt19937 random(7);
  std::uniform_real_distribution<float> uniform(-1, 1);
  const int corners = 12;
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<float> value(static_cast<size_t>(corners * corners * corners));
    for (int k = 0; k < corners; ++k)
      for (int j = 0; j < corners; ++j)
        for (int i = 0; i < corners; ++i) {
          const bool border = i == 0 || j == 0 || k == 0 || i == corners - 1 || j == corners - 1 ||
                              k == corners - 1;
          value[static_cast<size_t>((k * corners + j) * corners + i)] =
              border ? -1.0f : uniform(random);
        }
    const Mesh mesh = denseMarchingCubes(value, corners, 1.0);
    ASSERT_GT(mesh.triangles.size(), 100u);
    expectClosedOriented(mesh);
  }
}

TEST(MarchingCubes, SphereVolumeAndOutwardNormals) {
  const int corners = 41;
  const double step = 0.1, r = 1.5, c = 2.0;
  std::vector<float> value(static_cast<size_t>(corners * corners * corners));
  for (int k = 0; k < corners; ++k)
    for (int j = 0; j < corners; ++j)
      for (int i = 0; i < corners; ++i)
        value[static_cast<size_t>((k * corners + j) * corners + i)] =
            static_cast<float>(r - std::sqrt(std::pow(i * step - c, 2) + std::pow(j * step - c, 2) +
                                             std::pow(k * step - c, 2)));
  const Mesh mesh = denseMarchingCubes(value, corners, step);
  expectClosedOriented(mesh);
  const double exact = 4.0 / 3.0 * M_PI * r * r * r;
  EXPECT_NEAR(enclosedVolume(mesh), exact, 0.01 * exact);  // positive: normals point out
  for (const Vec3d& p : mesh.positions)
    EXPECT_NEAR(norm(p - Vec3d{c, c, c}), r, 0.01);
}

// ---- Carving views ----

TEST(CarvingView, VerdictsAgreeWithSignedDistances) {
  // Every point of a box judged outside has a negative distance, inside-seen positive, unseen
  // none; checked at random points of random boxes of all sizes.
  // The camera is close enough for the sphere to leave its image at the top.
  const Mesh object = sphere({0, 0, 0}, 1);
  Camera camera = ringCameras(1, {0, 0, 0}, 1.2)[0];
  lookAt(camera, {0, 0, 2.2}, {0, -0.8, 0}, {0, 1, 0});
  const Image mask = renderMask(object, camera);
  const CarvingView view(CanvasMap::build(camera), mask);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> centre(-3, 3), size(0.001, 1.0), unit(0, 1);
  std::map<ViewVerdict, int> seen;
  for (int trial = 0; trial < 4000; ++trial) {
    const Vec3d lo = {centre(random), centre(random), centre(random)};
    const double s = size(random);
    const Vec3d hi = lo + Vec3d{s, s, s};
    const ViewVerdict verdict = view.judgeBox(lo, hi);
    ++seen[verdict];
    for (int k = 0; k < 20; ++k) {
      const Vec3d p = lo + Vec3d{s * unit(random), s * unit(random), s * unit(random)};
      double d = 0;
      const bool visible = view.signedDistance(p, d);
      if (verdict == ViewVerdict::outside) {
        EXPECT_TRUE(visible && d < 0);
      } else if (verdict == ViewVerdict::insideSeen) {
        EXPECT_TRUE(visible && d > 0);
      } else if (verdict == ViewVerdict::insideClipped && visible) {
        EXPECT_GT(d, 0);
      } else if (verdict == ViewVerdict::unseen) {
        EXPECT_FALSE(visible);
      }
    }
  }
  for (ViewVerdict v : {ViewVerdict::outside, ViewVerdict::insideSeen, ViewVerdict::unseen,
                        ViewVerdict::partial, ViewVerdict::insideClipped})
    EXPECT_GT(seen[v], 0) << "verdict " << int(v) << " never reached";
}

// A box whose projection lies far beyond any int (a focal length of 1e12 pixels, a box just in
// front of the camera) is judged without overflowing: 3dvo-recon crashed on such cameras.
TEST(CarvingView, BoxesProjectedFarOutsideTheImageAreJudged) {
  const Mesh object = sphere({0, 0, 0}, 1);
  for (const double focal : {1e12, 1e300}) {
    Camera camera = ringCameras(1, {0, 0, 0}, 1.2)[0];
    lookAt(camera, {0, 0, 4}, {0, 0, 0}, {0, 1, 0});
    camera.fx = camera.fy = focal;
    const Image mask = renderMask(object, camera);
    const CarvingView view(CanvasMap::build(camera), mask);
    // Straddling the optical axis: corners to both sides of the image, far outside, so the
    // box is clipped (never judged wholly outside or unseen).
    const ViewVerdict straddling = view.judgeBox({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5});
    EXPECT_TRUE(straddling == ViewVerdict::insideClipped || straddling == ViewVerdict::partial)
        << focal << ": " << int(straddling);
    // Off the axis: wholly beyond the image.
    EXPECT_EQ(view.judgeBox({1, 1, -0.5}, {1.5, 1.5, 0.5}), ViewVerdict::unseen) << focal;
    // Just in front of the camera plane.
    EXPECT_NE(view.judgeBox({-1e-9, -1e-9, 3.999}, {1e-9, 1e-9, 3.9999}), ViewVerdict::outside)
        << focal;
  }
}

TEST(CarvingView, DistortedCameraCanvasHoldsTheWholeFieldOfView) {
  Camera camera = ringCameras(1, {0, 0, 0}, 1.2, 200, 150)[0];
  camera.distortion.k1 = -0.3;  // barrel: the undistorted field is larger than the image
  const CanvasMap map = CanvasMap::build(camera);
  EXPECT_GT(map.pinhole.width, camera.width);
  EXPECT_GT(map.pinhole.height, camera.height);
  // An all-background mask: pixels the camera saw are background, the rest unknown (object);
  // a point projecting into an unknown corner of the canvas is not seen.
  const CarvingView view(map, Image(camera.width, camera.height, 1, 0));
  size_t known = 0, object = 0;
  for (size_t i = 0; i < view.knownPixels().size(); ++i) {
    known += view.knownPixels()[i];
    object += view.objectPixels()[i];
    if (view.knownPixels()[i]) {
      EXPECT_EQ(view.objectPixels()[i], 0);
    }
  }
  EXPECT_GT(known, size_t(0.9 * camera.width * camera.height));
  EXPECT_EQ(known + object, view.knownPixels().size());
  const Camera& pinhole = view.pinhole();
  const Vec3d cornerRay = pinhole.backProject({0.5, 0.5}, 2.0);  // canvas corner: unknown
  double d;
  EXPECT_FALSE(view.signedDistance(cornerRay, d));
  const Vec3d centreRay =
      pinhole.backProject({0.5 * (pinhole.width - 1), 0.5 * (pinhole.height - 1)}, 2.0);
  ASSERT_TRUE(view.signedDistance(centreRay, d));
  EXPECT_LT(d, 0);
}

// ---- Visual hull ----

TEST(VisualHull, SphereFromARingReprojectsOntoItsSilhouettes) {
  const Vec3d c = {0.3, -0.2, 0.1};
  const Mesh object = sphere(c, 1.0);
  const std::vector<Camera> cameras = ringCameras(8, c, 1.0);
  std::vector<Image> masks;
  const std::vector<CarvingView> views = viewsOf(object, cameras, &masks);
  HullOptions options;
  options.depth = 7;
  options.minViews = 6;
  const CaptureCube cube = estimateCaptureCube(views, options, 0.05);
  EXPECT_LT(cube.size, 4.5);  // shrunk from the first guess (5.4) to the hull plus margins
  const HullResult hull = carveVisualHull(views, cube, options);
  expectClosedOriented(hull.surface);
  EXPECT_GT(hull.insideCells, 0u);
  EXPECT_GT(hull.surfaceVoxels, 0u);
  // The hull contains the sphere and reprojects onto every silhouette.
  const double sphereVolume = 4.0 / 3.0 * M_PI;
  EXPECT_GT(enclosedVolume(hull.surface), 0.99 * sphereVolume);
  EXPECT_LT(enclosedVolume(hull.surface), 1.25 * sphereVolume);
  EXPECT_GE(worstIoU(hull.surface, cameras, masks), 0.97);
}

TEST(VisualHull, PartsOutsideAViewAreNotCarvedByIt) {
  // Camera 0 is moved close, so the top of the sphere leaves its image; the other views keep
  // that part, and the hull still covers the whole sphere.
  const Mesh object = sphere({0, 0, 0}, 1.0);
  std::vector<Camera> cameras = ringCameras(6, {0, 0, 0}, 1.0);
  lookAt(cameras[0], {0, 0, 2.2}, {0, -0.8, 0}, {0, 1, 0});
  std::vector<Image> masks;
  const std::vector<CarvingView> views = viewsOf(object, cameras, &masks);
  bool touchesBorder = false;
  for (int x = 0; x < masks[0].width; ++x)
    touchesBorder = touchesBorder || masks[0].at(x, 0) == 255;
  ASSERT_TRUE(touchesBorder) << "the test needs the object to leave camera 0's image";
  HullOptions options;
  options.depth = 7;
  options.minViews = 5;
  const HullResult hull =
      carveVisualHull(views, estimateCaptureCube(views, options, 0.05), options);
  const SurfaceIndex index(hull.surface);
  double top = -1e9;
  for (const Vec3d& p : hull.surface.positions)
    top = std::max(top, p[1]);
  EXPECT_GT(top, 0.99);  // the sphere's top (y = 1) survives
  EXPECT_GE(worstIoU(hull.surface, cameras, masks), 0.95);
}

TEST(VisualHull, ClipBoxCutsTheHullAndKeepsItClosed) {
  const Mesh object = sphere({0, 0, 0}, 1.0);
  const std::vector<Camera> cameras = ringCameras(8, {0, 0, 0}, 1.0);
  const std::vector<CarvingView> views = viewsOf(object, cameras);
  HullOptions options;
  options.depth = 6;
  options.minViews = 6;
  options.clip = true;
  options.clipLo = {-2, -0.5, -2};  // a floor at y = -0.5
  options.clipHi = {2, 2, 2};
  const HullResult hull =
      carveVisualHull(views, estimateCaptureCube(views, options, 0.05), options);
  expectClosedOriented(hull.surface);
  double bottom = 1e9;
  for (const Vec3d& p : hull.surface.positions)
    bottom = std::min(bottom, p[1]);
  EXPECT_GE(bottom, -0.5 - 1e-6);
  EXPECT_LT(bottom, -0.5 + hull.voxelSize);
}

TEST(VisualHull, NoAgreementIsAnError) {
  const std::vector<Camera> cameras = ringCameras(4, {0, 0, 0}, 1.0);
  std::vector<CarvingView> views;
  for (const Camera& c : cameras)
    views.emplace_back(CanvasMap::build(c), Image(c.width, c.height, 1, 0));
  HullOptions options;
  options.minViews = 3;
  EXPECT_THROW(estimateCaptureCube(views, options, 0.05), Error);
}

// ---- Surface clean-up ----

TEST(Surface, WeldLargestComponentSmoothDecimate) {
  // Two spheres, one split along a seam (duplicated vertices): welding joins it, the largest
  // component is the bigger sphere, smoothing and decimation keep it closed.
  Mesh big = sphere({0, 0, 0}, 1.0, 4), small = sphere({3, 0, 0}, 0.3, 2);
  Mesh both = big;
  const uint32_t offset = static_cast<uint32_t>(both.positions.size());
  both.positions.insert(both.positions.end(), small.positions.begin(), small.positions.end());
  for (Triangle t : small.triangles)
    both.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  // Duplicate the corners of the big sphere's first 100 triangles.
  for (size_t f = 0; f < 100; ++f)
    for (uint32_t& v : both.triangles[f]) {
      both.positions.push_back(both.positions[v]);
      v = static_cast<uint32_t>(both.positions.size() - 1);
    }
  EXPECT_EQ(weldVertices(both), 300u);
  EXPECT_EQ(both.positions.size(), big.positions.size() + small.positions.size());
  EXPECT_EQ(keepLargestComponent(both), 2u);
  EXPECT_EQ(both.triangles.size(), big.triangles.size());
  expectClosedOriented(both);

  SmoothingOptions smoothing;
  smoothing.iterations = 5;
  smoothing.maxDisplacement = 0.01;
  const Mesh before = both;
  smoothMesh(both, smoothing);
  EXPECT_EQ(lastDroppedTriangles(), 0u);
  // The bound holds along each vertex's normal (radial on a sphere, to about 1e-3).
  for (size_t v = 0; v < both.positions.size(); ++v)
    EXPECT_LE(
        std::abs(dot(both.positions[v] - before.positions[v], normalized(before.positions[v]))),
        0.0101);

  DecimationOptions decimation;
  decimation.targetFaces = 2000;
  decimation.maxNormalDeviation = 45;
  EXPECT_GT(decimateMesh(both, decimation), 0u);
  EXPECT_LE(both.triangles.size(), 2000u);
  expectClosedOriented(both);
  EXPECT_LT(surfaceDistance(before, both).hausdorff(), 0.05);
}

TEST(Surface, DecimationStopsAtTheNormalDeviationBound) {
  Mesh m = sphere({0, 0, 0}, 1.0, 4);
  DecimationOptions decimation;
  decimation.targetFaces = 10;
  decimation.maxNormalDeviation = 10;
  decimateMesh(m, decimation);
  EXPECT_GT(m.triangles.size(), 200u);  // a sphere cannot be covered by few 10° cones
  expectClosedOriented(m);
}

// ---- Closest points ----

TEST(ClosestPoint, MatchesBruteForce) {
  const Mesh m = sphere({0, 0, 0}, 1.0, 3);
  const TriangleBvh bvh(m);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int k = 0; k < 300; ++k) {
    const Vec3d p = {u(random), u(random), u(random)};
    double best = 1e300;
    for (const Triangle& t : m.triangles)
      best = std::min(best, pointTriangleSquaredDistance(p, m.positions[t[0]], m.positions[t[1]],
                                                         m.positions[t[2]]));
    const ClosestPoint c = bvh.closest(p);
    EXPECT_NEAR(c.squaredDistance, best, 1e-12);
    // The barycentric coordinates give the point.
    const Triangle& t = m.triangles[c.triangle];
    Vec3d q = {0, 0, 0};
    for (size_t i = 0; i < 3; ++i)
      q = q + c.barycentric[i] * m.positions[t[i]];
    EXPECT_NEAR(norm(q - c.point), 0, 1e-12);
    // Facing queries only take triangles facing the given way.
    const ClosestPoint f = bvh.closestFacing(p, {0, 1, 0}, 0.5);
    ASSERT_NE(f.triangle, UINT32_MAX);
    EXPECT_GE(dot(bvh.normal(f.triangle), {0, 1, 0}), 0.5);
    EXPECT_GE(f.squaredDistance, c.squaredDistance);
  }
  // Degenerate triangles are handled as their edges.
  const ClosestPoint d = closestPointOnTriangle({0, 1, 0}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0});
  EXPECT_NEAR(d.squaredDistance, 1.0, 1e-12);
}

// ---- Tracking ----

// A bumpy ball (no symmetry for vertices to slide along) as an icosphere of `subdivisions`.
Mesh bumpyBall(int subdivisions) {
  Mesh m = icosphere(subdivisions);
  for (Vec3d& p : m.positions)
    p = (1 + 0.2 * std::sin(3 * p[0]) * std::cos(2 * p[1]) + 0.1 * p[2] * p[2]) * p;
  return m;
}

TEST(Tracking, RigidMotionIsFollowedVertexByVertex) {
  // Template: level-3 icosphere; targets: level-4 (other vertices and triangles) turning and
  // moving. The vertices must follow the motion itself, not only reach the surface.
  auto move = [](const Mesh& m, int f) {
    Mesh out = m;
    const Mat3d r = rotationFromRodrigues((0.08 * f) * normalized({1, 1, 0.3}));
    for (Vec3d& p : out.positions)
      p = r * p + Vec3d{0.05 * f, -0.02 * f, 0.03 * f};
    return out;
  };
  const Mesh rest = bumpyBall(3);
  MeshTracker tracker(rest, TrackingOptions());
  for (int f = 1; f <= 6; ++f) {
    const Mesh target = move(bumpyBall(4), f);
    const FitStats stats = tracker.fit(target);
    EXPECT_EQ(stats.vertexPairs, rest.positions.size());
    const Mesh& pose = tracker.current();
    ASSERT_EQ(pose.triangles, rest.triangles);
    EXPECT_LT(surfaceDistance(target, pose).hausdorff(), 0.02) << "frame " << f;
    const Mesh exact = move(rest, f);
    EXPECT_LT(vertexRmse(exact.positions, pose.positions),
              0.05 * vertexRmse(exact.positions, rest.positions))
        << "frame " << f;
  }
}

TEST(Tracking, BendingSurfaceIsFitted) {
  // The same ball bending (rotation about z growing with height) and stretching: the surface
  // is fitted closely. (Vertices may slide along a smooth surface: closest-point fitting does
  // not see tangential motion, docs/reconstruction.md.)
  auto bend = [](const Mesh& m, int f) {
    Mesh out = m;
    for (Vec3d& p : out.positions) {
      const double a = 0.06 * f * p[1];
      p = {std::cos(a) * p[0] - std::sin(a) * p[1] + 0.04 * f,
           std::sin(a) * p[0] + std::cos(a) * p[1], (1 + 0.02 * f) * p[2]};
    }
    return out;
  };
  const Mesh rest = bumpyBall(3);
  MeshTracker tracker(rest, TrackingOptions());
  for (int f = 1; f <= 6; ++f) {
    const Mesh target = bend(bumpyBall(4), f);
    tracker.fit(target);
    const double fitted = surfaceDistance(target, tracker.current()).hausdorff();
    EXPECT_LT(fitted, 0.02) << "frame " << f;
    EXPECT_LT(fitted, 0.2 * surfaceDistance(target, rest).hausdorff()) << "frame " << f;
  }
}

TEST(GomBuilder, AdaptiveGomsRestartWhenTheFitFails) {
  ReconParams params;
  params.decimationFaces = 0;
  params.trackMaxError = 0.01;
  params.gomSize = 4;
  GomBuilder builder(params);
  const Mesh ball = sphere({0, 0, 0}, 1.0, 3);
  std::vector<Mesh> frames;
  for (int f = 0; f < 6; ++f)
    frames.push_back(sphere({0.02 * f, 0, 0}, 1.0, f % 2 ? 3 : 2));  // connectivity changes
  // A jump: a different object.
  Mesh box = sphere({0, 0, 0}, 1.0, 1);
  for (Vec3d& p : box.positions)
    p = {2 * p[0], 0.5 * p[1], p[2]};
  frames.push_back(box);
  std::vector<GomStep> steps;
  for (const Mesh& m : frames)
    steps.push_back(builder.add(m, 0));
  // Frames 0-3 one GOM (GOMSize 4), 4-5 the next, the jump a third.
  const std::vector<std::pair<int, int>> expected = {{0, 4}, {4, 2}, {6, 1}};
  EXPECT_EQ(builder.goms(), expected);
  EXPECT_TRUE(steps[6].rejectedFit);
  for (size_t f = 0; f < steps.size(); ++f) {
    const auto& gom = builder.goms()[static_cast<size_t>(steps[f].gom)];
    EXPECT_EQ(steps[f].iMesh, static_cast<int>(f) == gom.first);
    EXPECT_EQ(steps[f].mesh.triangles, steps[static_cast<size_t>(gom.first)].mesh.triangles);
    EXPECT_LE(steps[f].fitHausdorff, params.trackMaxError * steps[f].diagonal);
  }

  // Fixed mode: GOMs of GOMSize frames whatever the error.
  params.gomMode = GomMode::fixed;
  params.gomSize = 3;
  GomBuilder fixed(params);
  for (const Mesh& m : frames)
    fixed.add(m, 0);
  const std::vector<std::pair<int, int>> fixedGoms = {{0, 3}, {3, 3}, {6, 1}};
  EXPECT_EQ(fixed.goms(), fixedGoms);
}

// ---- Silhouettes ----

TEST(Silhouettes, ThresholdRecipeGrowsByDilateMinusErode) {
  // A bright disc of radius 40 on black; the dino's recipe (dilate 10, erode 7) grows it by
  // about 3 pixels.
  Image image(200, 200, 3, 0);
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 200; ++x)
      if (std::hypot(x - 100, y - 100) <= 40)
        for (int c = 0; c < 3; ++c)
          image.at(x, y, c) = 120;
  const Image mask = thresholdSilhouette(image, ThresholdRecipe());
  size_t area = 0;
  for (uint8_t v : mask.pixels)
    area += v == 255;
  const double radius = std::sqrt(area / M_PI);
  EXPECT_NEAR(radius, 43, 1.0);
  // Below the threshold (0.19 · 255 = 48.45) nothing is object.
  Image dark(50, 50, 1, 48);
  for (uint8_t v : thresholdSilhouette(dark, ThresholdRecipe()).pixels)
    EXPECT_EQ(v, 0);
}

TEST(Silhouettes, BackgroundSubtractionTracksTheObjectAndIgnoresClutter) {
  // A textured, noisy background; an object (a bright square) that moves, then stands still
  // for 40 frames (it must not fade into the background), while a spurious blob blinks in a
  // corner after the object has been found (it must not enter the silhouette).
  const int w = 160, h = 120;
  std::mt19937 random(5);
  std::normal_distribution<double> noise(0, 2);
  Image background(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        background.at(x, y, c) = static_cast<uint8_t>(60 + 40 * ((x / 8 + y / 8 + c) % 3));
  auto frameWith = [&](int ox, int oy, bool clutter) {
    Image f = background;
    for (uint8_t& v : f.pixels)
      v = static_cast<uint8_t>(std::clamp(v + noise(random), 0.0, 255.0));
    for (int y = std::max(oy, 0); y < std::min(oy + 30, h); ++y)  // (-100, -100): no object
      for (int x = std::max(ox, 0); x < std::min(ox + 20, w); ++x)
        for (int c = 0; c < 3; ++c)
          f.at(x, y, c) = static_cast<uint8_t>(220 - 30 * c);
    if (clutter)
      for (int y = 2; y < 14; ++y)
        for (int x = 2; x < 14; ++x)
          f.at(x, y, 0) = 255;
    return f;
  };
  BackgroundSegmenter segmenter{BackgroundOptions()};
  for (int k = 0; k < 30; ++k)
    segmenter.learnBackground(frameWith(-100, -100, false));  // no object
  for (int f = 0; f < 70; ++f) {
    const int ox = 30 + std::min(f, 30) * 2, oy = 40;  // moves 60 px, then stands still
    const Image frame = frameWith(ox, oy, f > 5 && f % 3 == 0);
    const Image mask = segmenter.segment(frame);
    Image truth(w, h, 1, 0);
    for (int y = oy; y < oy + 30; ++y)
      for (int x = ox; x < ox + 20; ++x)
        truth.at(x, y) = 255;
    EXPECT_GE(maskIoU(mask, truth), 0.9) << "frame " << f;
    EXPECT_EQ(mask.at(8, 8), 0) << "frame " << f << ": clutter in the silhouette";
    const auto region = segmenter.region();
    EXPECT_NEAR(region[0], ox - 0.5, 4) << "frame " << f;
    EXPECT_NEAR(region[2], ox + 19.5, 4) << "frame " << f;
  }
}

// ---- Acceptance on the synthetic rig (ground truth known) ----

TEST(ReconSynth, DefaultRigReprojectsOntoEveryTruthMask) {
  test::TempDir dir("recon-synth");
  SynthParams rig;
  rig.output = dir.file("synth");
  const Dataset dataset = writeSyntheticDataset(rig);  // 8 cameras, 320 x 240, 10 frames
  ReconParams params;                                  // defaults: OctreeDepth 8
  params.input = rig.output;
  params.output = dir.file("out");
  const ReconResult result = runReconstruction(params, stdout);
  ASSERT_EQ(result.frames.size(), 10u);
  ASSERT_EQ(result.cameras.size(), 8u);

  for (const FrameRecord& r : result.frames) {
    // Mean point-to-surface distance to the ground truth: reported, and small against the
    // object (the visual hull of a ring of views is larger than the object at top and bottom).
    ASSERT_GE(r.truthMean, 0) << "frame " << r.frame;
    EXPECT_LT(r.truthMean, 0.01 * r.truthDiagonal) << "frame " << r.frame;
    std::printf("frame %d: truth mean distance %.5f (%.3f %% of the diagonal), IoU worst %.4f\n",
                r.frame, r.truthMean, 100 * r.truthMean / r.truthDiagonal, r.iouMin);
  }
  // The reprojection of each written frame covers each ground-truth mask with IoU >= 0.95
  // (recomputed here from the files, independently of the report).
  for (size_t c = 0; c < dataset.cameras.size(); ++c) {
    CameraFrames frames(dataset, c);
    for (int f = 0; f < dataset.frameCount; ++f) {
      const Mesh mesh = readObj(params.output + "/" + framePath("%04d.obj", f));
      const double iou = maskIoU(renderMask(mesh, dataset.cameras[c].camera), frames.mask(f));
      EXPECT_GE(iou, 0.95) << "frame " << f << " camera " << c;
      EXPECT_NEAR(iou, result.iou[static_cast<size_t>(f)][c], 1e-12);
    }
  }
  // GOMs: constant connectivity inside each, as listed in goms.txt.
  const auto goms = parseGomList(test::readText(params.output + "/goms.txt"), "goms.txt");
  EXPECT_EQ(goms, result.goms);
  for (const auto& [first, count] : goms) {
    const Mesh i = readObj(params.output + "/" + framePath("%04d.obj", first));
    for (int f = first + 1; f < first + count; ++f)
      EXPECT_EQ(readObj(params.output + "/" + framePath("%04d.obj", f)).triangles, i.triangles);
  }
  EXPECT_EQ(test::lines(test::readText(params.output + "/frames.csv")).size(), 11u);
}

// ---- The app ----

namespace {

std::string app(const char* name) {
  return std::string(TDVO_BIN_DIR) + "/" + name;
}

// A deforming ball whose connectivity changes every frame (alternating icosphere levels).
void writeVaryingSequence(const test::TempDir& dir, int frames) {
  std::filesystem::create_directories(dir.file("in"));
  for (int f = 0; f < frames; ++f) {
    Mesh m = icosphere(f % 2 ? 3 : 4);
    for (Vec3d& p : m.positions)
      p = (1 + 0.15 * std::sin(3 * p[0] + 0.3 * f) * std::cos(2 * p[1])) * p +
          Vec3d{0.03 * f, 0, 0};
    writeObj(dir.file("in/" + framePath("%04d.obj", f)), m);
  }
}

}  // namespace

// A frame whose fit error overflows (coordinates near 1e300: the distances are infinite) is a
// rejected fit, a new GOM (I*), not a tracked frame: inf <= TrackMaxError * inf accepted it,
// and the report's mean fit error was NaN.
TEST(ReconApp, AFitWithAnInfiniteErrorIsRejected) {
  test::TempDir dir("recon-inf");
  writeVaryingSequence(dir, 3);
  test::writeText(dir.file("in/" + framePath("%04d.obj", 1)),
                  "v 0 0 0\nv 1e300 0 0\nv 0 1e300 0\nf 1 2 3\n");
  const test::CommandResult recon = test::run(
      dir, app("3dvo-recon"), {"--InputMeshPattern=in/%04d.obj", "--FrameCount=3", "-o", "out"});
  ASSERT_EQ(recon.exitCode, 0) << recon.err;
  const std::vector<std::string> rows = test::lines(test::readText(dir.file("out/frames.csv")));
  ASSERT_GE(rows.size(), 3u);
  EXPECT_EQ(rows[2].rfind("1,1,1,I*,", 0), 0u) << rows[2];
  const std::string report = test::readText(dir.file("out/report.txt"));
  EXPECT_EQ(report.find("nan"), std::string::npos) << report;
}

TEST(ReconApp, TrackedGomsEncodeAndDecodeBitExactly) {
  test::TempDir dir("recon-app");
  writeVaryingSequence(dir, 8);
  // Frame 2 jumps to a ball three times the size elsewhere: no fit, so the GOMs differ in
  // length (frames 0-1, 2, 3-7 at least).
  Mesh jump = icosphere(3);
  for (Vec3d& p : jump.positions)
    p = 3.0 * p + Vec3d{4, 0, 0};
  writeObj(dir.file("in/" + framePath("%04d.obj", 2)), jump);
  const test::CommandResult recon = test::run(
      dir, app("3dvo-recon"),
      {"--InputMeshPattern=in/%04d.obj", "--FrameCount=8", "-o", "out", "--DecimationFaces=2000"});
  ASSERT_EQ(recon.exitCode, 0) << recon.err;
  EXPECT_NE(recon.out.find("# 3dvo-recon effective configuration"), std::string::npos);
  const auto goms = parseGomList(test::readText(dir.file("out/goms.txt")), "goms.txt");
  int frames = 0;
  for (size_t g = 0; g < goms.size(); ++g) {
    frames += goms[g].second;
    const std::string cfg = dir.file("out/encode/" + framePath("gom_%04d.cfg", int(g)));
    const std::string stream = dir.file("gom" + std::to_string(g) + ".3dvo");
    const test::CommandResult enc =
        test::run(dir, app("3dvo-enc"), {"-c", cfg, "--BitstreamFile=" + stream});
    ASSERT_EQ(enc.exitCode, 0) << enc.err;
    test::writeText(dir.file("enc.log"), enc.out);
    const test::CommandResult dec =
        test::run(dir, app("3dvo-dec"), {"-i", stream, "--verify", dir.file("enc.log")});
    EXPECT_EQ(dec.exitCode, 0) << dec.out << dec.err;
    EXPECT_EQ(test::linesStartingWith(dec.out, "MD5 frame=").size(),
              static_cast<size_t>(goms[g].second));
  }
  EXPECT_EQ(frames, 8);

  // The tracked GOMs as one stream through encode.cfg, which names goms.txt (GOMListFile) as
  // the GOMs differ in length.
  ASSERT_GE(goms.size(), 3u);
  EXPECT_EQ(goms[1], (std::pair<int, int>{2, 1}));
  const std::string encodeCfg = test::readText(dir.file("out/encode.cfg"));
  EXPECT_NE(encodeCfg.find("GOMListFile      : " + dir.file("out/goms.txt")), std::string::npos)
      << encodeCfg;
  EXPECT_EQ(encodeCfg.find("GOMSize"), std::string::npos) << encodeCfg;
  const test::CommandResult whole = test::run(
      dir, app("3dvo-enc"), {"-c", dir.file("out/encode.cfg"), "--BitstreamFile=whole.3dvo"});
  ASSERT_EQ(whole.exitCode, 0) << whole.err;
  test::writeText(dir.file("whole.log"), whole.out);
  const test::CommandResult wholeDec =
      test::run(dir, app("3dvo-dec"), {"-i", "whole.3dvo", "--verify", dir.file("whole.log")});
  EXPECT_EQ(wholeDec.exitCode, 0) << wholeDec.out << wholeDec.err;
  EXPECT_EQ(test::linesStartingWith(wholeDec.out, "MD5 frame=").size(), 8u);

  // Fixed GOMs: one stream for the whole sequence through encode.cfg.
  const test::CommandResult fixed =
      test::run(dir, app("3dvo-recon"),
                {"--InputMeshPattern=in/%04d.obj", "--FrameCount=8", "-o", "fixed",
                 "--DecimationFaces=2000", "--GOMMode=fixed", "--GOMSize=4"});
  ASSERT_EQ(fixed.exitCode, 0) << fixed.err;
  EXPECT_NE(test::readText(dir.file("fixed/encode.cfg")).find("GOMSize          : 4"),
            std::string::npos);
  const test::CommandResult enc = test::run(
      dir, app("3dvo-enc"), {"-c", dir.file("fixed/encode.cfg"), "--BitstreamFile=fixed.3dvo"});
  ASSERT_EQ(enc.exitCode, 0) << enc.err;
  test::writeText(dir.file("fixed.log"), enc.out);
  const test::CommandResult dec =
      test::run(dir, app("3dvo-dec"), {"-i", "fixed.3dvo", "--verify", dir.file("fixed.log")});
  EXPECT_EQ(dec.exitCode, 0) << dec.out << dec.err;
}

TEST(ReconApp, BadInputIsOneErrorLineAndNoOutput) {
  test::TempDir dir("recon-errors");
  auto error = [&](const std::vector<std::string>& args) {
    const test::CommandResult r = test::run(dir, app("3dvo-recon"), args);
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(test::lines(r.err).size(), 1u) << r.err;
    return r.err;
  };
  EXPECT_NE(error({"-o", "out"}).find("give exactly one of Input (-i) and InputMeshPattern"),
            std::string::npos);
  EXPECT_NE(error({"-i", "missing", "-o", "out"}).find("3dvo-recon: error:"), std::string::npos);
  EXPECT_NE(error({"--InputMeshPattern=in/%04d.obj", "-o", "out"}).find("needs FrameCount"),
            std::string::npos);
  EXPECT_NE(error({"-i", "x", "-o", "out", "--OctreeDepth=30"}).find("OctreeDepth"),
            std::string::npos);
  // A missing mesh file: the error names it, and nothing is left under a final name.
  writeVaryingSequence(dir, 3);
  EXPECT_NE(
      error({"--InputMeshPattern=in/%04d.obj", "--FrameCount=4", "-o", "out"}).find("in/0003.obj"),
      std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir.file("out/0000.obj")));
  EXPECT_FALSE(std::filesystem::exists(dir.file("out/goms.txt")));
  const test::CommandResult help = test::run(dir, app("3dvo-recon"), {"--help"});
  EXPECT_EQ(help.exitCode, 0);
  EXPECT_NE(help.out.find("OctreeDepth"), std::string::npos);
}

TEST(ReconApp, EveryKeyIsDocumented) {
  ReconParams params;
  OptionTable table("3dvo-recon", "");
  addReconOptions(table, params);
  const std::string docs = test::readText(std::string(TDVO_SOURCE_DIR) + "/docs/reconstruction.md");
  for (const std::string& line : test::lines(table.effectiveConfig())) {
    const std::string key = line.substr(0, line.find(' '));
    EXPECT_NE(docs.find("`" + key + "`"), std::string::npos) << key << " is not in the docs";
  }
}
