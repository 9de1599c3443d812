// The camera model of 3DVO: one place that defines how a world point lands on a pixel.
//
// Conventions (docs/cameras.md states them with figures and formulas):
// - World → camera is the computer-vision convention: X_cam = R · X_world + t. The camera looks
//   along its +z axis, x points right in the image and y points down.
// - Pixel coordinates: origin at the top-left image corner's pixel *centre*. Pixel (i, j) (column
//   i, row j) has its centre at (x, y) = (i, j) and covers [i − ½, i + ½) × [j − ½, j + ½). This
//   is OpenCV's convention; the Middlebury and NeRF calibrations are read with it unchanged.
// - Intrinsics fx, fy, cx, cy (pixels, no skew). Lens distortion is OpenCV's five-coefficient
//   model (k1 k2 p1 p2 k3) applied to normalised coordinates (x, y) = (X/Z, Y/Z):
//     r² = x² + y²,  s = 1 + k1 r² + k2 r⁴ + k3 r⁶
//     x' = x s + 2 p1 x y + p2 (r² + 2 x²),   y' = y s + p1 (r² + 2 y²) + 2 p2 x y
//   and pixel = (fx x' + cx, fy y' + cy).
#pragma once

#include <array>
#include <string>

#include "common/core/mesh.h"
#include "common/views/image.h"

namespace tdvo {

using Vec2d = std::array<double, 2>;
// A 3×3 matrix as three rows.
using Mat3d = std::array<Vec3d, 3>;
// A 4×4 matrix as four rows (homogeneous transforms).
using Mat4d = std::array<std::array<double, 4>, 4>;

// Small vector/matrix helpers used with the camera model (plain double arithmetic in a fixed
// order, so results do not depend on the build as long as it is IEEE-754 without contraction).
Vec3d operator+(const Vec3d& a, const Vec3d& b);
Vec3d operator-(const Vec3d& a, const Vec3d& b);
Vec3d operator*(double s, const Vec3d& a);
double dot(const Vec3d& a, const Vec3d& b);
Vec3d cross(const Vec3d& a, const Vec3d& b);
double norm(const Vec3d& a);
Vec3d normalized(const Vec3d& a);  // a / |a|; a must not be zero
Mat3d identity3();
Mat3d transpose(const Mat3d& m);
Mat3d operator*(const Mat3d& a, const Mat3d& b);
Vec3d operator*(const Mat3d& m, const Vec3d& v);
double determinant(const Mat3d& m);

// Rodrigues' formula: the rotation by angle |r| about the axis r / |r| (OpenCV's cv::Rodrigues).
Mat3d rotationFromRodrigues(const Vec3d& r);
// The inverse: the rotation vector of a rotation matrix, angle in [0, π].
Vec3d rodriguesFromRotation(const Mat3d& R);
// The rotation matrix nearest to an almost-orthonormal `m` (polar decomposition by iteration);
// used to clean up rotations that were stored in single precision.
Mat3d nearestRotation(const Mat3d& m);
// True when `R` is a rotation within `tolerance` (R Rᵀ = I and det R = +1).
bool isRotation(const Mat3d& R, double tolerance);

// Lens distortion, OpenCV's model (see the top of this file). All zero means none.
struct Distortion {
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
  bool isZero() const { return k1 == 0 && k2 == 0 && p1 == 0 && p2 == 0 && k3 == 0; }
};

// Applies the distortion to normalised coordinates.
Vec2d distortNormalised(const Distortion& d, const Vec2d& undistorted);
// Inverts distortNormalised: a radial Newton solve along the ray, then Newton's method on the
// full model. Exact to ~1e-12 where the model is invertible. Strong fitted distortions may fold
// back (r·s(r) stops growing) before reaching the image corners; a point beyond the fold has no
// inverse, and the result is then the point at the fold on its ray (best effort).
Vec2d undistortNormalised(const Distortion& d, const Vec2d& distorted);
// The largest normalised radius up to which the radial part r·s(r) still grows with r (the model
// folds back beyond it); infinity when it grows everywhere up to r = 10.
double monotonicRadius(const Distortion& d);
// The largest distorted radius the radial model reaches, r·s(r) at monotonicRadius (infinity
// when unbounded): distorted points farther from the principal point have no undistorted
// pre-image.
double largestDistortedRadius(const Distortion& d);

struct Camera {
  std::string name;
  int width = 0, height = 0;  // image size in pixels
  double fx = 1, fy = 1, cx = 0, cy = 0;
  Distortion distortion;
  Mat3d R = identity3();  // world → camera rotation
  Vec3d t = {0, 0, 0};    // world → camera translation

  // World point to camera coordinates: R X + t.
  Vec3d toCamera(const Vec3d& world) const;
  // Camera coordinates back to the world: Rᵀ (X − t).
  Vec3d toWorld(const Vec3d& cameraPoint) const;
  // The camera centre in world coordinates, −Rᵀ t.
  Vec3d centre() const;
  // The unit viewing direction (the optical axis, camera +z) in world coordinates.
  Vec3d viewingDirection() const;

  // Projects a world point to pixel coordinates, distortion included. Returns false (and leaves
  // `pixel` unchanged) when the point is not in front of the camera (camera z ≤ 0).
  bool project(const Vec3d& world, Vec2d& pixel) const;
  // The pixel of a camera-coordinate point with z > 0.
  Vec2d projectCameraPoint(const Vec3d& cameraPoint) const;
  // The world point seen at `pixel` (distorted image coordinates) at camera depth `depth`
  // (its camera z coordinate).
  Vec3d backProject(const Vec2d& pixel, double depth) const;
  // The unit world direction of the ray through `pixel` (distorted image coordinates).
  Vec3d rayDirection(const Vec2d& pixel) const;

  // Pixel ↔ normalised coordinates without distortion: (x − cx)/fx, (y − cy)/fy and back.
  Vec2d pixelToNormalised(const Vec2d& pixel) const;
  Vec2d normalisedToPixel(const Vec2d& normalised) const;
  // Where a pixel of the undistorted image (same fx, fy, cx, cy, no distortion) lies in the
  // distorted image, and the inverse.
  Vec2d distortPixel(const Vec2d& undistortedPixel) const;
  Vec2d undistortPixel(const Vec2d& distortedPixel) const;

  // The same camera without lens distortion: the camera of undistortImage's output.
  Camera withoutDistortion() const;
};

// Builds R, t for a camera at `eye` looking at `target`, with the image's up direction (−y)
// as close to `up` as possible. `up` must not be parallel to the viewing direction.
void lookAt(Camera& camera, const Vec3d& eye, const Vec3d& target, const Vec3d& up);

// Converts a camera-to-world matrix in the OpenGL convention (camera looks along −z, y up, as in
// NeRF's transform_matrix) to this model's world → camera R, t:
//   [R | t] = diag(1, −1, −1) · inverse(cameraToWorld)   (top three rows).
// The rotation part is cleaned with nearestRotation first.
void setFromOpenGlCameraToWorld(Camera& camera, const Mat4d& cameraToWorld);

// Resamples an image taken by `camera` into the image of camera.withoutDistortion() (same size
// and intrinsics): each output pixel centre is distorted and the input sampled bilinearly there;
// samples outside the input are 0.
Image undistortImage(const Image& image, const Camera& camera);
// The inverse resampling: an undistorted image to the distorted camera's image.
Image distortImage(const Image& undistorted, const Camera& camera);

}  // namespace tdvo
