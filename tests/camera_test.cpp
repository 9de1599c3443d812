// The camera model: projection, back-projection, lens distortion, Rodrigues, OpenGL → CV.
#include "common/views/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/core/error.h"

using namespace tdvo;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A camera with the strong barrel distortion of the uu-4cam data set's first camera
// (k1 ≈ −0.37, values from its published calibration).
Camera strongDistortionCamera() {
  Camera c;
  c.name = "strong";
  c.width = 644;
  c.height = 486;
  c.fx = 490.756439;
  c.fy = 493.263580;
  c.cx = 334.690674;
  c.cy = 222.398880;
  c.distortion = {-0.368704915, 0.203186616, 3.26540467e-04, 1.78072587e-05, -0.0712014362};
  c.R = rotationFromRodrigues({-1.3729877816020433, 0.49613357894194315, 0.61391054843037529});
  c.t = {289.02691777857865, 1008.0364772390549, 5836.3675632258164};
  return c;
}

// A strong barrel distortion that stays invertible over its whole image.
Camera strongValidCamera() {
  Camera c = strongDistortionCamera();
  c.name = "valid";
  c.distortion = {-0.30, 0.09, 0.0008, -0.0005, -0.005};
  return c;
}

// Distance of a pixel from the principal point in normalised distorted coordinates.
double distortedRadius(const Camera& c, const Vec2d& pixel) {
  const Vec2d n = c.pixelToNormalised(pixel);
  return std::hypot(n[0], n[1]);
}

void expectMatrixNear(const Mat3d& a, const Mat3d& b, double tolerance) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(a[i][j], b[i][j], tolerance) << "entry (" << i << ", " << j << ")";
}

}  // namespace

TEST(Camera, ProjectBackProjectRoundTrip) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (bool distorted : {false, true}) {
    Camera c = strongDistortionCamera();
    if (!distorted) c = c.withoutDistortion();
    int tested = 0;
    for (int i = 0; i < 2000; ++i) {
      // A pixel inside the image and a depth: back-project, then project again.
      const Vec2d pixel = {(u(rng) * 0.5 + 0.5) * (c.width - 1),
                           (u(rng) * 0.5 + 0.5) * (c.height - 1)};
      // (The uu-4cam model folds back just before its image corners; those have no inverse.)
      if (distortedRadius(c, pixel) >= 0.99 * largestDistortedRadius(c.distortion)) continue;
      const double depth = 3000 + 2000 * u(rng);
      const Vec3d world = c.backProject(pixel, depth);
      EXPECT_NEAR(c.toCamera(world)[2], depth, 1e-9 * depth);
      Vec2d again;
      ASSERT_TRUE(c.project(world, again));
      EXPECT_NEAR(again[0], pixel[0], 1e-6);
      EXPECT_NEAR(again[1], pixel[1], 1e-6);
      // The ray through the pixel passes through the back-projected point.
      const Vec3d ray = c.rayDirection(pixel);
      const Vec3d toPoint = normalized(world - c.centre());
      EXPECT_NEAR(dot(ray, toPoint), 1.0, 1e-12);
      ++tested;
    }
    EXPECT_GT(tested, 1950);
  }
}

TEST(Camera, CentreAndViewingDirection) {
  const Camera c = strongDistortionCamera();
  const Vec3d centre = c.centre();
  const Vec3d atCentre = c.toCamera(centre);
  for (double v : atCentre)
    EXPECT_NEAR(v, 0.0, 1e-9);
  // A point on the optical axis lands on the principal point, distortion or not.
  Vec2d pixel;
  ASSERT_TRUE(c.project(centre + 1000.0 * c.viewingDirection(), pixel));
  EXPECT_NEAR(pixel[0], c.cx, 1e-9);
  EXPECT_NEAR(pixel[1], c.cy, 1e-9);
  EXPECT_NEAR(norm(c.viewingDirection()), 1.0, 1e-12);
  // Behind the camera: no projection.
  EXPECT_FALSE(c.project(centre - 1000.0 * c.viewingDirection(), pixel));
}

TEST(Camera, DistortionRoundTripOverTheImage) {
  // Every pixel of the image: undistort, distort again, compare.
  auto worstOverImage = [](const Camera& c, size_t& skipped) {
    const double reach = largestDistortedRadius(c.distortion);
    double worst = 0;
    skipped = 0;
    for (int y = 0; y < c.height; ++y)
      for (int x = 0; x < c.width; ++x) {
        const Vec2d distorted = {double(x), double(y)};
        if (distortedRadius(c, distorted) >= 0.999 * reach) {
          ++skipped;  // beyond the fold of the model: no undistorted point maps there
          continue;
        }
        const Vec2d back = c.distortPixel(c.undistortPixel(distorted));
        worst =
            std::max({worst, std::fabs(back[0] - distorted[0]), std::fabs(back[1] - distorted[1])});
      }
    return worst;
  };
  // A strong barrel lens (k1 = −0.30) that is invertible over the whole image.
  size_t skipped = 0;
  const Camera valid = strongValidCamera();
  const double worstValid = worstOverImage(valid, skipped);
  EXPECT_EQ(skipped, 0u);
  EXPECT_LT(worstValid, 0.01) << "largest |distort(undistort(p)) − p| over every pixel, pixels";
  // The uu-4cam calibration (k1 ≈ −0.37): its fitted model folds back just before the image
  // corners; every pixel short of the fold round-trips.
  const Camera uu = strongDistortionCamera();
  const double worstUu = worstOverImage(uu, skipped);
  EXPECT_LT(worstUu, 0.01);
  EXPECT_LT(skipped, size_t(uu.width * uu.height) / 200) << "pixels beyond the model's fold";
  std::printf(
      "distortion round trip, every pixel of 644x486: k1=-0.30 lens max error %.2g px; "
      "uu-4cam lens max error %.2g px (%zu corner pixels at or within 0.1%% of the model's fold "
      "skipped)\n",
      worstValid, worstUu, skipped);
  // The other way round, over the undistorted positions of the image.
  double worstInverse = 0;
  for (int y = 0; y < valid.height; y += 3)
    for (int x = 0; x < valid.width; x += 3) {
      const Vec2d undistorted = valid.undistortPixel({double(x), double(y)});
      const Vec2d back = valid.undistortPixel(valid.distortPixel(undistorted));
      worstInverse = std::max(
          {worstInverse, std::fabs(back[0] - undistorted[0]), std::fabs(back[1] - undistorted[1])});
    }
  EXPECT_LT(worstInverse, 0.01);
}

TEST(Camera, DistortionModelHandComputed) {
  // x' = x s + 2 p1 x y + p2 (r² + 2x²), y' = y s + p1 (r² + 2y²) + 2 p2 x y.
  const Distortion d{0.1, 0.01, 0.001, 0.002, 0.0005};
  const Vec2d p = distortNormalised(d, {0.5, -0.25});
  const double r2 = 0.3125;
  const double s = 1 + 0.1 * r2 + 0.01 * r2 * r2 + 0.0005 * r2 * r2 * r2;
  EXPECT_NEAR(p[0], 0.5 * s + 2 * 0.001 * 0.5 * -0.25 + 0.002 * (r2 + 2 * 0.25), 1e-15);
  EXPECT_NEAR(p[1], -0.25 * s + 0.001 * (r2 + 2 * 0.0625) + 2 * 0.002 * 0.5 * -0.25, 1e-15);
  // Where the radial part r·s(r) stops growing: d/dr = 1 + 3 k1 r² + 5 k2 r⁴ + 7 k3 r⁶ = 0.
  // For k1 = −0.25 alone: r² = 4/3, r·s = (2/√3)·(2/3).
  const Distortion barrel{-0.25, 0, 0, 0, 0};
  EXPECT_NEAR(monotonicRadius(barrel), 2 / std::sqrt(3.0), 1e-3);
  EXPECT_NEAR(largestDistortedRadius(barrel), 4 / (3 * std::sqrt(3.0)), 1e-6);
  EXPECT_TRUE(std::isinf(monotonicRadius(Distortion{})));
  // The valid strong lens reaches its image corners; the uu-4cam fit does not quite.
  const Camera valid = strongValidCamera(), uu = strongDistortionCamera();
  EXPECT_GT(largestDistortedRadius(valid.distortion), distortedRadius(valid, {0, 0}));
  EXPECT_LT(largestDistortedRadius(uu.distortion), distortedRadius(uu, {643, 485}));
  EXPECT_GT(largestDistortedRadius(uu.distortion), distortedRadius(uu, {0, 243}));
}

TEST(Camera, RodriguesHandComputedCases) {
  // 90° about z: x → y, y → −x.
  expectMatrixNear(rotationFromRodrigues({0, 0, kPi / 2}), {{{0, -1, 0}, {1, 0, 0}, {0, 0, 1}}},
                   1e-15);
  // 90° about x: y → z, z → −y.
  expectMatrixNear(rotationFromRodrigues({kPi / 2, 0, 0}), {{{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}},
                   1e-15);
  // 120° about (1,1,1): the cyclic permutation x → y → z → x.
  const double a = 2 * kPi / 3 / std::sqrt(3.0);
  expectMatrixNear(rotationFromRodrigues({a, a, a}), {{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}}, 1e-15);
  // 180° about x.
  expectMatrixNear(rotationFromRodrigues({kPi, 0, 0}), {{{1, 0, 0}, {0, -1, 0}, {0, 0, -1}}},
                   1e-15);
  expectMatrixNear(rotationFromRodrigues({0, 0, 0}), identity3(), 0);

  // And back, including the angle-π case whose axis sign is free.
  const Vec3d back = rodriguesFromRotation({{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}});
  for (double v : back)
    EXPECT_NEAR(v, a, 1e-14);
  const Vec3d half = rodriguesFromRotation({{{1, 0, 0}, {0, -1, 0}, {0, 0, -1}}});
  EXPECT_NEAR(std::fabs(half[0]), kPi, 1e-14);
  EXPECT_NEAR(half[1], 0, 1e-14);
  EXPECT_NEAR(half[2], 0, 1e-14);

  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 500; ++i) {
    Vec3d r = {u(rng), u(rng), u(rng)};
    r = (3.1 * std::fabs(u(rng)) / norm(r)) * r;  // angles up to 3.1 rad
    const Mat3d R = rotationFromRodrigues(r);
    EXPECT_TRUE(isRotation(R, 1e-12));
    const Vec3d r2 = rodriguesFromRotation(R);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(r2[k], r[k], 1e-9);
  }
}

TEST(Camera, NearestRotationCleansSinglePrecision) {
  const Mat3d R = rotationFromRodrigues({0.3, -0.8, 0.5});
  Mat3d noisy = R;
  for (auto& row : noisy)
    for (double& v : row)
      v = static_cast<float>(v);
  EXPECT_FALSE(isRotation(noisy, 1e-12));
  const Mat3d clean = nearestRotation(noisy);
  EXPECT_TRUE(isRotation(clean, 1e-14));
  expectMatrixNear(clean, R, 1e-7);
}

TEST(Camera, OpenGlToComputerVisionHandComputed) {
  // An OpenGL camera at (0, 0, 5) with identity rotation looks along −z at the origin, y up.
  Camera c;
  c.width = 100;
  c.height = 80;
  c.fx = c.fy = 100;
  c.cx = 49.5;
  c.cy = 39.5;
  setFromOpenGlCameraToWorld(c, {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 5}, {0, 0, 0, 1}}});
  expectMatrixNear(c.R, {{{1, 0, 0}, {0, -1, 0}, {0, 0, -1}}}, 0);
  EXPECT_EQ(c.t, (Vec3d{0, 0, 5}));
  EXPECT_EQ(c.centre(), (Vec3d{0, 0, 5}));
  Vec2d p;
  ASSERT_TRUE(c.project({0, 0, 0}, p));
  EXPECT_EQ(p, (Vec2d{49.5, 39.5}));
  ASSERT_TRUE(c.project({1, 0, 0}, p));  // world +x is to the right
  EXPECT_EQ(p, (Vec2d{69.5, 39.5}));
  ASSERT_TRUE(c.project({0, 1, 0}, p));  // world +y (OpenGL up) is up in the image
  EXPECT_EQ(p, (Vec2d{49.5, 19.5}));

  // A camera at (4, 0, 0) turned 90° about y (OpenGL −z then points along world −x).
  const double s = 1, z = 0;
  setFromOpenGlCameraToWorld(c, {{{z, 0, s, 4}, {0, 1, 0, 0}, {-s, 0, z, 0}, {0, 0, 0, 1}}});
  EXPECT_NEAR(norm(c.centre() - Vec3d{4, 0, 0}), 0, 1e-15);
  EXPECT_NEAR(norm(c.viewingDirection() - Vec3d{-1, 0, 0}), 0, 1e-15);
  ASSERT_TRUE(c.project({0, 0, -1}, p));  // seen from +x looking at −x, world −z is on the right
  EXPECT_NEAR(p[0], 49.5 + 25, 1e-12);
  EXPECT_NEAR(p[1], 39.5, 1e-12);
}

TEST(Camera, LookAt) {
  Camera c;
  c.width = 64;
  c.height = 48;
  c.fx = c.fy = 50;
  c.cx = 31.5;
  c.cy = 23.5;
  lookAt(c, {3, 1, 4}, {0, 0.5, 0}, {0, 1, 0});
  EXPECT_TRUE(isRotation(c.R, 1e-14));
  Vec2d p, above;
  ASSERT_TRUE(c.project({0, 0.5, 0}, p));
  EXPECT_NEAR(p[0], c.cx, 1e-12);
  EXPECT_NEAR(p[1], c.cy, 1e-12);
  ASSERT_TRUE(c.project({0, 0.6, 0}, above));
  EXPECT_LT(above[1], p[1]);  // up in the world is up in the image
  EXPECT_NEAR(above[0], p[0], 1e-9);
  EXPECT_THROW(lookAt(c, {0, 5, 0}, {0, 0, 0}, {0, 1, 0}), Error);
}

TEST(Camera, UndistortImageThenDistortRestoresIt) {
  const Camera c = strongValidCamera();
  Image image(c.width, c.height, 3);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      image.at(x, y, 0) = static_cast<uint8_t>(128 + 100 * std::sin(x * 0.05));
      image.at(x, y, 1) = static_cast<uint8_t>(128 + 100 * std::cos(y * 0.07));
      image.at(x, y, 2) = static_cast<uint8_t>((x + y) / 5);
    }
  const Image undistorted = undistortImage(image, c);
  // A straight line in the world is straight in the undistorted image: check with the model.
  Vec2d p;
  ASSERT_TRUE(c.withoutDistortion().project(c.backProject({600, 400}, 4000), p));
  EXPECT_NEAR(c.distortPixel(p)[0], 600, 1e-6);
  const Image back = distortImage(undistorted, c);
  double error = 0;
  int n = 0;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      // Only where the undistorted image holds the pixel (a barrel lens sees more than the
      // undistorted image of the same size keeps).
      const Vec2d u = c.undistortPixel({double(x), double(y)});
      if (u[0] < 1 || u[1] < 1 || u[0] > c.width - 2 || u[1] > c.height - 2) continue;
      for (int k = 0; k < 3; ++k, ++n)
        error += std::fabs(double(back.at(x, y, k)) - image.at(x, y, k));
    }
  EXPECT_GT(n, c.width * c.height * 3 / 2);
  EXPECT_LT(error / n, 1.0) << "mean absolute error after undistort + distort";
  EXPECT_THROW(undistortImage(Image(10, 10, 3), c), Error);
}
