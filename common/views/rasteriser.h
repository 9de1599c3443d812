// A CPU z-buffer triangle rasteriser: object masks, depth maps and per-pixel surface positions
// (triangle + perspective-correct barycentric coordinates) of a Mesh seen by a Camera.
//
// Encoder and decoder both derive texture shapes from it, so its coverage is defined exactly:
//
// 1. Each triangle is clipped in camera coordinates against the near plane z = zNear and a
//    guard frustum: the image enlarged by one image size on every side; for a camera with lens
//    distortion, the undistorted image's bounding box enlarged by half its size, intersected
//    with a regular 32-gon inscribed in 0.999 × the distortion model's monotonic radius, so that
//    no clipped corner can fold back into the image (image corners that a strong fitted
//    distortion cannot reach at all stay uncovered). The clipped polygon is split into a fan of
//    triangles around its first corner.
// 2. Every corner is projected with Camera::projectCameraPoint (distortion included; edges stay
//    straight between projected corners) and snapped to fixed point with kSubpixelBits fraction
//    bits: X = llround(x · 2^kSubpixelBits). A polygon with a corner beyond ±2^21 pixels, which
//    only a degenerate camera produces (the guard frustum keeps corners within a few image
//    sizes), covers nothing: the integer stage below cannot overflow.
// 3. Coverage is decided in 64-bit integers only: pixel (i, j), whose centre is (i, j) in pixel
//    coordinates (camera.h), is inside a triangle when all three edge functions are positive, or
//    zero on a "top" or "left" edge (the top-left rule). Triangles of zero area cover nothing.
//    Two triangles sharing an edge never both cover a pixel centre on it, and a closed fan leaves
//    no gap, so a watertight mesh covers each pixel centre of its silhouette exactly once per
//    layer.
//
// Guarantee: steps 1–2 use IEEE-754 double arithmetic in a fixed order (built without FMA
// contraction, see common/CMakeLists.txt) and step 3 is integer arithmetic, so renderMask gives
// the same mask for the same mesh and camera on every conforming build and platform. Depth,
// barycentric coordinates and the z-test are evaluated in double precision in a fixed order;
// the z-test keeps the nearer fragment and, on equal depth, the triangle drawn first (lower
// index).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "common/core/mesh.h"
#include "common/views/camera.h"
#include "common/views/image.h"

namespace tdvo {

constexpr int kSubpixelBits = 8;

struct RasterOptions {
  double zNear = 1e-9;         // near clipping plane (camera z, world units)
  bool cullBackFaces = false;  // drop triangles seen from behind (clockwise in the image)
};

// Per-pixel result of rasterising with the z-test: the visible triangle, its camera depth and
// the perspective-correct barycentric coordinates of the pixel centre in that triangle (weights
// of the triangle's corners 0, 1, 2 in the order of Mesh::triangles).
struct Fragments {
  int width = 0, height = 0;
  std::vector<int32_t> triangle;                  // −1 where no triangle covers the pixel
  std::vector<float> depth;                       // camera z; +infinity where empty
  std::vector<std::array<float, 3>> barycentric;  // zeros where empty
  size_t index(int x, int y) const {
    return static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
  }
};

// Rasterises every triangle of `mesh` into a width × height buffer of `camera` with a z-buffer.
Fragments rasterise(const Mesh& mesh, const Camera& camera, const RasterOptions& options = {});

// The object mask: a grey image, 255 where any triangle covers the pixel centre, 0 elsewhere
// (no z-test needed, so back faces and hidden triangles count too).
Image renderMask(const Mesh& mesh, const Camera& camera, const RasterOptions& options = {});

// renderMask for many meshes seen by one camera (e.g. an object's shape frame after frame): the
// checks and the camera's clip volume (for a distorting lens, the undistorted image border) are
// set up once, when it is made. render(mesh) == renderMask(mesh, camera, options); render may
// be called from several threads at once.
class MaskRenderer {
 public:
  explicit MaskRenderer(const Camera& camera, const RasterOptions& options = {});
  ~MaskRenderer();
  MaskRenderer(MaskRenderer&&) noexcept;
  MaskRenderer& operator=(MaskRenderer&&) noexcept;
  const Camera& camera() const;
  Image render(const Mesh& mesh) const;

 private:
  struct Setup;
  std::unique_ptr<const Setup> setup_;
};

// The depth map: camera z of the nearest surface per pixel, +infinity where empty.
std::vector<float> renderDepth(const Mesh& mesh, const Camera& camera,
                               const RasterOptions& options = {});

// Interpolates a per-vertex attribute at a pixel of `fragments` (perspective-correct through the
// stored barycentric coordinates). The pixel must be covered.
template <class T>
T interpolate(const Fragments& fragments, const Mesh& mesh, const std::vector<T>& attribute, int x,
              int y) {
  const size_t i = fragments.index(x, y);
  const Triangle& tri = mesh.triangles[static_cast<size_t>(fragments.triangle[i])];
  const std::array<float, 3>& b = fragments.barycentric[i];
  T out = attribute[tri[0]];
  for (size_t k = 0; k < out.size(); ++k)
    out[k] =
        b[0] * attribute[tri[0]][k] + b[1] * attribute[tri[1]][k] + b[2] * attribute[tri[2]][k];
  return out;
}

}  // namespace tdvo
