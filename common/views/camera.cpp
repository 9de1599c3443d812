#include "common/views/camera.h"

#include <cmath>
#include <limits>

#include "common/core/error.h"

namespace tdvo {

Vec3d operator+(const Vec3d& a, const Vec3d& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
Vec3d operator-(const Vec3d& a, const Vec3d& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
Vec3d operator*(double s, const Vec3d& a) {
  return {s * a[0], s * a[1], s * a[2]};
}
double dot(const Vec3d& a, const Vec3d& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec3d& a) {
  return std::sqrt(dot(a, a));
}
Vec3d normalized(const Vec3d& a) {
  return (1.0 / norm(a)) * a;
}
Mat3d identity3() {
  return {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
}
Mat3d transpose(const Mat3d& m) {
  Mat3d r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r[i][j] = m[j][i];
  return r;
}
Mat3d operator*(const Mat3d& a, const Mat3d& b) {
  Mat3d r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
  return r;
}
Vec3d operator*(const Mat3d& m, const Vec3d& v) {
  return {dot(m[0], v), dot(m[1], v), dot(m[2], v)};
}
double determinant(const Mat3d& m) {
  return dot(m[0], cross(m[1], m[2]));
}

Mat3d rotationFromRodrigues(const Vec3d& r) {
  const double theta = norm(r);
  if (theta < 1e-12) {
    // First-order expansion R ≈ I + [r]×, exact enough for |r| this small.
    return {{{1, -r[2], r[1]}, {r[2], 1, -r[0]}, {-r[1], r[0], 1}}};
  }
  const Vec3d k = (1.0 / theta) * r;
  const double c = std::cos(theta), s = std::sin(theta), v = 1 - c;
  // R = c I + (1 − c) k kᵀ + s [k]×
  return {{{c + v * k[0] * k[0], v * k[0] * k[1] - s * k[2], v * k[0] * k[2] + s * k[1]},
           {v * k[1] * k[0] + s * k[2], c + v * k[1] * k[1], v * k[1] * k[2] - s * k[0]},
           {v * k[2] * k[0] - s * k[1], v * k[2] * k[1] + s * k[0], c + v * k[2] * k[2]}}};
}

Vec3d rodriguesFromRotation(const Mat3d& R) {
  // sin θ · k from the antisymmetric part, cos θ from the trace.
  const Vec3d a = {0.5 * (R[2][1] - R[1][2]), 0.5 * (R[0][2] - R[2][0]), 0.5 * (R[1][0] - R[0][1])};
  const double s = norm(a);
  const double c = std::max(-1.0, std::min(1.0, 0.5 * (R[0][0] + R[1][1] + R[2][2] - 1)));
  const double theta = std::atan2(s, c);
  if (s > 1e-6) return (theta / s) * a;
  if (c > 0) return a;  // θ ≈ 0: sin θ ≈ θ
  // θ ≈ π: R ≈ 2 k kᵀ − I; take k from the largest diagonal entry of (R + I) / 2.
  int i = 0;
  for (int j = 1; j < 3; ++j)
    if (R[j][j] > R[i][i]) i = j;
  Vec3d k;
  for (int j = 0; j < 3; ++j)
    k[j] = 0.5 * (R[i][j] + R[j][i]) + (i == j ? 1.0 : 0.0);
  k = normalized(k);
  // The sign of k is free at θ = π; near it, the antisymmetric part fixes it.
  if (dot(k, a) < 0) k = -1.0 * k;
  return theta * k;
}

Mat3d nearestRotation(const Mat3d& m) {
  // Polar decomposition by the iteration X ← (X + X⁻ᵀ) / 2, which converges to the orthogonal
  // factor; for the near-rotations it is used on, a few steps reach double precision.
  Mat3d x = m;
  for (int iteration = 0; iteration < 20; ++iteration) {
    const double det = determinant(x);
    check(std::fabs(det) > 1e-12, "nearestRotation: singular matrix");
    // X⁻ᵀ = cofactor(X) / det X.
    const Mat3d cof = {cross(x[1], x[2]), cross(x[2], x[0]), cross(x[0], x[1])};
    Mat3d next;
    double change = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        next[i][j] = 0.5 * (x[i][j] + cof[i][j] / det);
        change = std::max(change, std::fabs(next[i][j] - x[i][j]));
      }
    x = next;
    if (change < 1e-15) break;
  }
  return x;
}

bool isRotation(const Mat3d& R, double tolerance) {
  const Mat3d p = R * transpose(R);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (!(std::fabs(p[i][j] - (i == j ? 1.0 : 0.0)) <= tolerance)) return false;
  return std::fabs(determinant(R) - 1) <= tolerance;
}

Vec2d distortNormalised(const Distortion& d, const Vec2d& u) {
  const double x = u[0], y = u[1];
  const double r2 = x * x + y * y;
  const double s = 1 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  return {x * s + 2 * d.p1 * x * y + d.p2 * (r2 + 2 * x * x),
          y * s + d.p1 * (r2 + 2 * y * y) + 2 * d.p2 * x * y};
}

Vec2d undistortNormalised(const Distortion& d, const Vec2d& target) {
  if (d.isZero()) return target;
  // 1. The radial part alone, along the target's ray: solve g(r) = r·s(r) = |target| by Newton's
  //    method from r = |target|. For the usual barrel (g concave) and pincushion (g convex)
  //    models the iterates approach the first root monotonically and never jump past the fold;
  //    when there is no root (the model folds before reaching the target), they stop at the
  //    fold, where g' reaches zero.
  const double rd = std::sqrt(target[0] * target[0] + target[1] * target[1]);
  Vec2d u = target;
  if (rd > 0) {
    double r = rd;
    for (int iteration = 0; iteration < 100; ++iteration) {
      const double r2 = r * r;
      const double g = r * (1 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3)));
      const double slope = 1 + r2 * (3 * d.k1 + r2 * (5 * d.k2 + r2 * 7 * d.k3));
      if (!(slope > 1e-9)) break;
      const double step = (rd - g) / slope;
      const double next = r + step;
      if (!(next > 0)) break;
      r = next;
      if (std::fabs(step) < 1e-15 * (1 + r)) break;
    }
    u = {target[0] * (r / rd), target[1] * (r / rd)};
  }
  // 2. Newton's method on the full model (tangential terms included) with the analytic Jacobian,
  //    accepting only steps that reduce the residual and stay where the model is one-to-one.
  auto residual = [&](const Vec2d& v) {
    const Vec2d f = distortNormalised(d, v);
    const double ex = f[0] - target[0], ey = f[1] - target[1];
    return std::sqrt(ex * ex + ey * ey);
  };
  double error = residual(u);
  for (int iteration = 0; iteration < 50 && error > 1e-16; ++iteration) {
    const double x = u[0], y = u[1];
    const double r2 = x * x + y * y;
    const double s = 1 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
    const double ds = d.k1 + r2 * (2 * d.k2 + 3 * d.k3 * r2);  // ∂s/∂(r²)
    const Vec2d f = distortNormalised(d, u);
    const double ex = f[0] - target[0], ey = f[1] - target[1];
    // ∂x'/∂x, ∂x'/∂y, ∂y'/∂x, ∂y'/∂y
    const double a = s + 2 * x * x * ds + 2 * d.p1 * y + 6 * d.p2 * x;
    const double b = 2 * x * y * ds + 2 * d.p1 * x + 2 * d.p2 * y;
    const double c = b;
    const double e = s + 2 * y * y * ds + 6 * d.p1 * y + 2 * d.p2 * x;
    const double det = a * e - b * c;
    if (!(det > 1e-12)) break;  // at or beyond the fold: keep the best point found
    Vec2d step = {(e * ex - b * ey) / det, (a * ey - c * ex) / det};
    bool improved = false;
    for (int halving = 0; halving < 30 && !improved; ++halving) {
      const Vec2d candidate = {x - step[0], y - step[1]};
      const double candidateError = residual(candidate);
      if (candidateError < error) {
        u = candidate;
        error = candidateError;
        improved = true;
      }
      step = {0.5 * step[0], 0.5 * step[1]};
    }
    if (!improved) break;
  }
  return u;
}

double monotonicRadius(const Distortion& d) {
  // d/dr [r s(r)] = 1 + 3 k1 r² + 5 k2 r⁴ + 7 k3 r⁶; scan for its first non-positive value.
  const int steps = 10000;
  const double rMax = 10.0;
  for (int i = 1; i <= steps; ++i) {
    const double r = rMax * i / steps, r2 = r * r;
    if (1 + r2 * (3 * d.k1 + r2 * (5 * d.k2 + r2 * 7 * d.k3)) <= 0) return rMax * (i - 1) / steps;
  }
  return std::numeric_limits<double>::infinity();
}

double largestDistortedRadius(const Distortion& d) {
  const double r = monotonicRadius(d);
  if (std::isinf(r)) return r;
  const double r2 = r * r;
  return r * (1 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3)));
}

Vec3d Camera::toCamera(const Vec3d& world) const {
  return R * world + t;
}

Vec3d Camera::toWorld(const Vec3d& p) const {
  return transpose(R) * (p - t);
}

Vec3d Camera::centre() const {
  return -1.0 * (transpose(R) * t);
}

Vec3d Camera::viewingDirection() const {
  return R[2];  // Rᵀ (0, 0, 1) is the third row of R
}

Vec2d Camera::projectCameraPoint(const Vec3d& p) const {
  const Vec2d d = distortNormalised(distortion, {p[0] / p[2], p[1] / p[2]});
  return normalisedToPixel(d);
}

bool Camera::project(const Vec3d& world, Vec2d& pixel) const {
  const Vec3d p = toCamera(world);
  if (!(p[2] > 0)) return false;
  pixel = projectCameraPoint(p);
  return true;
}

Vec2d Camera::pixelToNormalised(const Vec2d& pixel) const {
  return {(pixel[0] - cx) / fx, (pixel[1] - cy) / fy};
}

Vec2d Camera::normalisedToPixel(const Vec2d& n) const {
  return {fx * n[0] + cx, fy * n[1] + cy};
}

Vec3d Camera::backProject(const Vec2d& pixel, double depth) const {
  const Vec2d n = undistortNormalised(distortion, pixelToNormalised(pixel));
  return toWorld({n[0] * depth, n[1] * depth, depth});
}

Vec3d Camera::rayDirection(const Vec2d& pixel) const {
  const Vec2d n = undistortNormalised(distortion, pixelToNormalised(pixel));
  return normalized(transpose(R) * Vec3d{n[0], n[1], 1});
}

Vec2d Camera::distortPixel(const Vec2d& undistortedPixel) const {
  return normalisedToPixel(distortNormalised(distortion, pixelToNormalised(undistortedPixel)));
}

Vec2d Camera::undistortPixel(const Vec2d& distortedPixel) const {
  return normalisedToPixel(undistortNormalised(distortion, pixelToNormalised(distortedPixel)));
}

Camera Camera::withoutDistortion() const {
  Camera c = *this;
  c.distortion = Distortion();
  return c;
}

namespace {

// A computed pose's zeros are +0 (−1 · 0 is −0): a dataset.json keeps the sign of what it is
// given, and "-0.0" in a pose made here would only be noise.
void positiveZeros(Camera& camera) {
  for (Vec3d& row : camera.R)
    for (double& x : row)
      x += 0.0;
  for (double& x : camera.t)
    x += 0.0;
}

}  // namespace

void lookAt(Camera& camera, const Vec3d& eye, const Vec3d& target, const Vec3d& up) {
  const Vec3d z = normalized(target - eye);
  const Vec3d xAxis = cross(z, up);
  check(norm(xAxis) > 1e-12 * norm(up), "lookAt: up direction is parallel to the view direction");
  const Vec3d x = normalized(xAxis);
  const Vec3d y = cross(z, x);  // image down
  camera.R = {x, y, z};
  camera.t = -1.0 * (camera.R * eye);
  positiveZeros(camera);
}

void setFromOpenGlCameraToWorld(Camera& camera, const Mat4d& m) {
  Mat3d rotation;  // camera → world rotation, OpenGL axes
  Vec3d position;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      rotation[i][j] = m[i][j];
    position[i] = m[i][3];
  }
  const Mat3d worldToGl = transpose(nearestRotation(rotation));
  // diag(1, −1, −1): flip y and z to go from OpenGL's camera axes to the CV ones.
  camera.R = {worldToGl[0], -1.0 * worldToGl[1], -1.0 * worldToGl[2]};
  camera.t = -1.0 * (camera.R * position);
  positiveZeros(camera);
}

namespace {

// Bilinear sample at (x, y) in pixel-centre coordinates; 0 outside the image.
void sampleBilinear(const Image& image, double x, double y, uint8_t* out) {
  const int c = image.channels;
  if (!(x > -1 && y > -1 && x < image.width && y < image.height)) {
    for (int k = 0; k < c; ++k)
      out[k] = 0;
    return;
  }
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double ax = x - x0, ay = y - y0;
  double sum[4] = {0, 0, 0, 0};
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx) {
      const int xi = x0 + dx, yi = y0 + dy;
      if (xi < 0 || yi < 0 || xi >= image.width || yi >= image.height) continue;
      const double w = (dx ? ax : 1 - ax) * (dy ? ay : 1 - ay);
      for (int k = 0; k < c; ++k)
        sum[k] += w * image.at(xi, yi, k);
    }
  for (int k = 0; k < c; ++k)
    out[k] = static_cast<uint8_t>(std::min(255.0, std::floor(sum[k] + 0.5)));
}

template <class Map>
Image resample(const Image& in, Map map) {
  Image out(in.width, in.height, in.channels);
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) {
      const Vec2d source = map(Vec2d{double(x), double(y)});
      sampleBilinear(in, source[0], source[1], &out.pixels[out.index(x, y)]);
    }
  return out;
}

}  // namespace

Image undistortImage(const Image& image, const Camera& camera) {
  check(image.width == camera.width && image.height == camera.height,
        "undistortImage: camera '" + camera.name + "' is " + std::to_string(camera.width) + "x" +
            std::to_string(camera.height) + " but the image is " + std::to_string(image.width) +
            "x" + std::to_string(image.height));
  if (camera.distortion.isZero()) return image;
  return resample(image, [&](const Vec2d& p) { return camera.distortPixel(p); });
}

Image distortImage(const Image& undistorted, const Camera& camera) {
  check(undistorted.width == camera.width && undistorted.height == camera.height,
        "distortImage: camera '" + camera.name + "' is " + std::to_string(camera.width) + "x" +
            std::to_string(camera.height) + " but the image is " +
            std::to_string(undistorted.width) + "x" + std::to_string(undistorted.height));
  if (camera.distortion.isZero()) return undistorted;
  return resample(undistorted, [&](const Vec2d& p) { return camera.undistortPixel(p); });
}

}  // namespace tdvo
