#include "common/views/rasteriser.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

#include "common/core/error.h"

namespace tdvo {

namespace {

// A corner of a (clipped) triangle: camera coordinates and its barycentric coordinates in the
// original triangle, so that attributes can be interpolated over the original corners.
struct ClipVertex {
  Vec3d p;
  Vec3d bary;
};

// The clip volume: half-spaces a·X + b·Y + c·Z + d ≥ 0 in camera coordinates. Plane 0 is the
// near plane; for a lens with distortion, 32 planes follow: the sides of a regular 32-gon (in
// normalised coordinates x/z, y/z) inscribed in the circle of 0.999 × the model's monotonic
// radius, so that no clipped corner lies where the lens folds back; the last four bound the
// guard rectangle in normalised coordinates.
constexpr int kPolygonSides = 32;

struct ClipVolume {
  int count = 0;
  std::array<std::array<double, 4>, 40> planes;
  // The 32-gon's sides, when there are any: planes polygonFirst .. polygonFirst + 31, each at
  // distance polygonSide · Z from the axis.
  int polygonFirst = -1;
  double polygonSide = 0;
  void add(double a, double b, double c, double d) {
    planes[static_cast<size_t>(count++)] = {a, b, c, d};
  }
  double value(int plane, const Vec3d& p) const {
    const std::array<double, 4>& q = planes[static_cast<size_t>(plane)];
    return q[0] * p[0] + q[1] * p[1] + q[2] * p[2] + q[3];
  }
  // Whether no plane's value at p is negative (NaN counts as inside, as in clipPolygon): the
  // same answer as testing every plane, with a shortcut for the 32-gon. A point whose distance
  // from the axis is below the polygon's inscribed circle by a relative margin of 5e-6 is
  // inside all 32 sides, and that margin exceeds the rounding error of a side's computed value
  // (a few 1e-16 of the point's size) by ten orders of magnitude, so the shortcut never
  // accepts a point that a side's computed value rejects. Other points test every side.
  bool contains(const Vec3d& p) const {
    for (int plane = 0; plane < count; ++plane) {
      if (plane == polygonFirst) {  // the near plane came first: Z >= zNear > 0, or NaN
        const double radius = polygonSide * p[2];
        if (p[0] * p[0] + p[1] * p[1] <= radius * radius * (1 - 1e-5)) {
          plane += kPolygonSides - 1;
          continue;
        }
      }
      if (value(plane, p) < 0) return false;
    }
    return true;
  }
};

// cos and sin of 2π (k + ½) / 32, k = 0 … 31, as literals (no libm rounding differences).
constexpr double kPolygon[kPolygonSides][2] = {
    {0.99518472667219693, 0.098017140329560604},  {0.95694033573220882, 0.29028467725446233},
    {0.88192126434835505, 0.47139673682599764},   {0.77301045336273699, 0.63439328416364549},
    {0.63439328416364549, 0.77301045336273699},   {0.47139673682599781, 0.88192126434835494},
    {0.29028467725446233, 0.95694033573220894},   {0.09801714032956077, 0.99518472667219682},
    {-0.098017140329560645, 0.99518472667219693}, {-0.29028467725446216, 0.95694033573220894},
    {-0.4713967368259977, 0.88192126434835505},   {-0.63439328416364538, 0.7730104533627371},
    {-0.77301045336273699, 0.63439328416364549},  {-0.88192126434835494, 0.47139673682599786},
    {-0.95694033573220882, 0.29028467725446239},  {-0.99518472667219682, 0.098017140329560826},
    {-0.99518472667219693, -0.09801714032956059}, {-0.95694033573220894, -0.29028467725446211},
    {-0.88192126434835505, -0.47139673682599764}, {-0.7730104533627371, -0.63439328416364527},
    {-0.63439328416364593, -0.77301045336273666}, {-0.47139673682599786, -0.88192126434835494},
    {-0.29028467725446244, -0.95694033573220882}, {-0.098017140329560451, -0.99518472667219693},
    {0.09801714032956009, -0.99518472667219693},  {0.29028467725446205, -0.95694033573220894},
    {0.47139673682599759, -0.88192126434835505},  {0.6343932841636456, -0.77301045336273688},
    {0.77301045336273666, -0.63439328416364593},  {0.88192126434835483, -0.47139673682599792},
    {0.95694033573220882, -0.2902846772544625},   {0.99518472667219693, -0.098017140329560506},
};

ClipVolume clipVolume(const Camera& camera, double zNear) {
  ClipVolume v;
  v.add(0, 0, 1, -zNear);
  const double w = camera.width, h = camera.height;
  double xMin, xMax, yMin, yMax;
  if (camera.distortion.isZero()) {
    // The image enlarged by one image size on every side (pixel-centre coordinates).
    const Vec2d a = camera.pixelToNormalised({-w - 0.5, -h - 0.5});
    const Vec2d b = camera.pixelToNormalised({2 * w - 0.5, 2 * h - 0.5});
    xMin = std::min(a[0], b[0]), xMax = std::max(a[0], b[0]);
    yMin = std::min(a[1], b[1]), yMax = std::max(a[1], b[1]);
  } else {
    // The bounding box of the undistorted image border (sampled every 4 pixels and at the
    // corners; border points beyond the fold clamped to it), enlarged by half its size.
    const double limit = 0.999 * monotonicRadius(camera.distortion);
    const double inf = std::numeric_limits<double>::infinity();
    xMin = inf, xMax = -inf, yMin = inf, yMax = -inf;
    auto add = [&](double x, double y) {
      Vec2d n = undistortNormalised(camera.distortion, camera.pixelToNormalised({x, y}));
      const double r = std::sqrt(n[0] * n[0] + n[1] * n[1]);
      if (r > limit) n = {n[0] * limit / r, n[1] * limit / r};
      xMin = std::min(xMin, n[0]), xMax = std::max(xMax, n[0]);
      yMin = std::min(yMin, n[1]), yMax = std::max(yMax, n[1]);
    };
    const double x0 = -0.5, y0 = -0.5, x1 = w - 0.5, y1 = h - 0.5;
    for (double x = x0; x < x1; x += 4)
      add(x, y0), add(x, y1);
    for (double y = y0; y < y1; y += 4)
      add(x0, y), add(x1, y);
    add(x1, y1);
    const double gx = 0.5 * (xMax - xMin), gy = 0.5 * (yMax - yMin);
    xMin -= gx, xMax += gx, yMin -= gy, yMax += gy;
    if (std::isfinite(limit)) {
      // The 32-gon: each side at distance limit · cos(π/32) from the axis, normal at angle
      // 2π (k + ½) / 32: limit·cos(π/32)·Z − cos·X − sin·Y ≥ 0.
      const double side = limit * 0.99518472667219693;
      v.polygonFirst = v.count;
      v.polygonSide = side;
      for (const auto& direction : kPolygon)
        v.add(-direction[0], -direction[1], side, 0);
    }
  }
  v.add(1, 0, -xMin, 0);  // x/z ≥ xMin
  v.add(-1, 0, xMax, 0);  // x/z ≤ xMax
  v.add(0, 1, -yMin, 0);
  v.add(0, -1, yMax, 0);
  return v;
}

bool lexLess(const Vec3d& a, const Vec3d& b) {
  return a[0] != b[0] ? a[0] < b[0] : a[1] != b[1] ? a[1] < b[1] : a[2] < b[2];
}

// Sutherland–Hodgman clipping of a convex polygon against every plane of the clip volume.
// `poly` has room for 3 + 40 corners (each plane adds at most one).
int clipPolygon(ClipVertex* poly, int n, const ClipVolume& volume) {
  ClipVertex buffer[48];
  for (int plane = 0; plane < volume.count && n > 0; ++plane) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const ClipVertex& a = poly[i];
      const ClipVertex& b = poly[(i + 1) % n];
      const double da = volume.value(plane, a.p), db = volume.value(plane, b.p);
      if (da >= 0) buffer[m++] = a;
      if ((da >= 0) != (db >= 0)) {
        // Interpolate from the lexicographically smaller end, so that the two triangles sharing
        // this edge compute the very same crossing point (no cracks along a clipped edge).
        const bool swap = lexLess(b.p, a.p);
        const ClipVertex& u = swap ? b : a;
        const ClipVertex& v = swap ? a : b;
        const double du = swap ? db : da, dv = swap ? da : db;
        const double s = du / (du - dv);
        buffer[m++] = {u.p + s * (v.p - u.p), u.bary + s * (v.bary - u.bary)};
      }
    }
    std::copy(buffer, buffer + m, poly);
    n = m;
  }
  return n;
}

// The first pixel centre at or after, and the last at or before, fixed-point coordinate a:
// ⌈a / 2^kSubpixelBits⌉ and ⌊a / 2^kSubpixelBits⌋ (arithmetic shifts round toward −∞; no branch).
int64_t ceilToPixel(int64_t a) {
  return -((-a) >> kSubpixelBits);
}
int64_t floorToPixel(int64_t a) {
  return a >> kSubpixelBits;
}

struct ScreenVertex {
  int64_t x, y;       // fixed point, kSubpixelBits fraction bits
  double z;           // camera depth
  const Vec3d* bary;  // barycentric coordinates in the original triangle
};

// Calls fragment(x, y, depth, bary) for every pixel centre the triangle covers (top-left rule),
// or, without attributes, fragment(y, x0, x1) for every row whose pixel centres x0 .. x1 it
// covers. Always inlined into the per-triangle loop: most triangles of a fine mesh cost less
// than the call.
template <bool kNeedAttributes, class Fragment>
inline __attribute__((always_inline)) void rasteriseTriangle(const ScreenVertex& a,
                                                             const ScreenVertex& b,
                                                             const ScreenVertex& c, int width,
                                                             int height, Fragment& fragment) {
  // Most triangles of a fine mesh cover no pixel centre at all: the pixel bounds first.
  constexpr int64_t one = int64_t(1) << kSubpixelBits;
  const int64_t xMin = std::max<int64_t>(0, ceilToPixel(std::min({a.x, b.x, c.x})));
  const int64_t xMax = std::min<int64_t>(width - 1, floorToPixel(std::max({a.x, b.x, c.x})));
  const int64_t yMin = std::max<int64_t>(0, ceilToPixel(std::min({a.y, b.y, c.y})));
  const int64_t yMax = std::min<int64_t>(height - 1, floorToPixel(std::max({a.y, b.y, c.y})));
  if (xMin > xMax || yMin > yMax) return;
  // Corners by reference, swapped as pointers: copying three corners into a call's frame cost
  // as much as rasterising a small triangle (a store-forwarding stall).
  const ScreenVertex* v[3] = {&a, &b, &c};
  int64_t area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (area == 0) return;
  if (area < 0) {
    std::swap(v[1], v[2]);
    area = -area;
  }
  const ScreenVertex &v0 = *v[0], &v1 = *v[1], &v2 = *v[2];

  // Edge k runs between the two corners other than corner k; its function is positive inside.
  const ScreenVertex* corner[3] = {&v0, &v1, &v2};
  int64_t dx[3], dy[3], rowStart[3], bias[3];
  for (int k = 0; k < 3; ++k) {
    const ScreenVertex& a = *corner[(k + 1) % 3];
    const ScreenVertex& b = *corner[(k + 2) % 3];
    dx[k] = b.x - a.x;
    dy[k] = b.y - a.y;
    // Top-left rule: a top edge (horizontal, interior below) or a left edge (interior to the
    // right, i.e. going up in y-down image coordinates) owns the pixel centres on it.
    const bool owned = dy[k] < 0 || (dy[k] == 0 && dx[k] > 0);
    bias[k] = owned ? 0 : 1;
    rowStart[k] = dx[k] * (yMin * one - a.y) - dy[k] * (xMin * one - a.x);
  }
  if constexpr (!kNeedAttributes) {
    // Coverage only: the covered pixel centres of a row are one run (the row meets the
    // intersection of three half-planes in an interval), found in registers without a branch
    // per pixel (most triangles are a few pixels: the branches would be mispredicted) and
    // handed over at once (a store per pixel makes the loop reload whatever a byte may alias).
    for (int64_t y = yMin; y <= yMax; ++y) {
      int64_t e[3] = {rowStart[0], rowStart[1], rowStart[2]};
      int64_t first = -1, last = -1;
      for (int64_t x = xMin; x <= xMax; ++x) {
        const bool inside = (e[0] >= bias[0]) & (e[1] >= bias[1]) & (e[2] >= bias[2]);
        first = (inside & (first < 0)) ? x : first;
        last = inside ? x : last;
        for (int k = 0; k < 3; ++k)
          e[k] -= dy[k] * one;
      }
      if (first >= 0)
        fragment(static_cast<int>(y), static_cast<int>(first), static_cast<int>(last));
      for (int k = 0; k < 3; ++k)
        rowStart[k] += dx[k] * one;
    }
  } else {
    const double invArea = 1.0 / static_cast<double>(area);
    for (int64_t y = yMin; y <= yMax; ++y) {
      int64_t e[3] = {rowStart[0], rowStart[1], rowStart[2]};
      for (int64_t x = xMin; x <= xMax; ++x) {
        if (e[0] >= bias[0] && e[1] >= bias[1] && e[2] >= bias[2]) {
          // Screen-space weights, then perspective correction through 1/z.
          const double w0 = static_cast<double>(e[0]) * invArea / v0.z;
          const double w1 = static_cast<double>(e[1]) * invArea / v1.z;
          const double w2 = static_cast<double>(e[2]) * invArea / v2.z;
          const double sum = w0 + w1 + w2;
          const double depth = 1.0 / sum;
          const double b0 = w0 / sum, b1 = w1 / sum, b2 = w2 / sum;
          const Vec3d bary = {b0 * (*v0.bary)[0] + b1 * (*v1.bary)[0] + b2 * (*v2.bary)[0],
                              b0 * (*v0.bary)[1] + b1 * (*v1.bary)[1] + b2 * (*v2.bary)[1],
                              b0 * (*v0.bary)[2] + b1 * (*v1.bary)[2] + b2 * (*v2.bary)[2]};
          fragment(static_cast<int>(x), static_cast<int>(y), depth, bary);
        }
        for (int k = 0; k < 3; ++k)
          e[k] -= dy[k] * one;
      }
      for (int k = 0; k < 3; ++k)
        rowStart[k] += dx[k] * one;
    }
  }
}

// llround(ldexp(v, kSubpixelBits)) for a snappable |v| <= 2^21, without the two library
// calls: the scaling by a power of two is exact, the truncation and its remainder are exact
// below 2^52, and ties round away from zero as in llround.
int64_t snap(double v) {
  const double scaled = v * double(int64_t(1) << kSubpixelBits);
  int64_t i = static_cast<int64_t>(scaled);
  const double remainder = scaled - static_cast<double>(i);
  if (remainder >= 0.5) ++i;
  if (remainder <= -0.5) --i;
  return i;
}

// The largest |pixel coordinate| the integer stage takes: edge functions multiply differences
// of two fixed-point coordinates, which stay below 2^62 this way. The guard frustum keeps every
// corner within a few image sizes (<= 2^15 pixels); only a degenerate camera (e.g. decoded from
// a corrupt stream: cx = 1e300) projects beyond, and such a polygon covers nothing.
constexpr double kMaxPixelCoordinate = double(int64_t(1) << 21);

bool snappable(const Vec2d& pixel) {
  return std::fabs(pixel[0]) <= kMaxPixelCoordinate && std::fabs(pixel[1]) <= kMaxPixelCoordinate;
}

// A vertex's snapped pixel position (|x|, |y| <= 2^29), or kSlow in x (see rasteriseMesh).
constexpr int32_t kSlow = std::numeric_limits<int32_t>::min();
struct Snapped {
  int32_t x = kSlow, y = 0;
};

// Clips, projects and rasterises every triangle of the mesh; fragment(triangle, x, y, depth,
// bary) receives every covered pixel (without attributes: fragment(triangle, y, x0, x1) every
// covered run of a row), triangle by triangle in index order.
template <bool kNeedAttributes, class Fragment>
void rasteriseMesh(const Mesh& mesh, const Camera& camera, const RasterOptions& options,
                   const ClipVolume& volume, Fragment fragment) {
  // Per vertex, once: its camera coordinates and, for a "fast" vertex, its snapped pixel
  // position. A fast vertex is finite and below 1e300 in magnitude (so a triangle of three
  // passes the finiteness test below), inside every clip plane, and projects to a
  // representable pixel position. A triangle of three fast corners needs no clipping and
  // projects exactly these corners, so sharing them between the triangles around a vertex
  // (about six) gives the very fixed-point corners that projecting per triangle gives, at a
  // sixth of the cost; the loop over such triangles reads 8 bytes per corner. Every other
  // triangle takes the general path below.
  std::vector<Vec3d> cameraPoints(mesh.positions.size());
  std::vector<Snapped> snapped(mesh.positions.size());
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const Vec3d& p = cameraPoints[i] = camera.toCamera(mesh.positions[i]);
    const bool small =
        std::fabs(p[0]) < 1e300 && std::fabs(p[1]) < 1e300 && std::fabs(p[2]) < 1e300;
    if (!small || !volume.contains(p)) continue;
    const Vec2d pixel = camera.projectCameraPoint(p);
    if (snappable(pixel))
      snapped[i] = {static_cast<int32_t>(snap(pixel[0])), static_cast<int32_t>(snap(pixel[1]))};
  }
  static const Vec3d kCornerBary[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    for (uint32_t v : tri)
      if (v >= cameraPoints.size())
        throw Error("rasterise: triangle " + std::to_string(t) +
                    " has a vertex index out of range");
    // Per pixel (x, y, depth, bary), or per run of a row (y, x0, x1) without attributes.
    auto perPixel = [&](auto... where) { fragment(static_cast<int32_t>(t), where...); };
    auto backFacing = [&](const Vec3d& p0, const Vec3d& p1, const Vec3d& p2) {
      return options.cullBackFaces && dot(cross(p1 - p0, p2 - p0), p0) >= 0;
    };
    const Snapped& s0 = snapped[tri[0]];
    const Snapped& s1 = snapped[tri[1]];
    const Snapped& s2 = snapped[tri[2]];
    if (s0.x != kSlow && s1.x != kSlow && s2.x != kSlow) {
      // Three fast corners: finite, not clipped, projected above.
      double z[3] = {0, 0, 0};
      if (kNeedAttributes || options.cullBackFaces) {
        const Vec3d& p0 = cameraPoints[tri[0]];
        const Vec3d& p1 = cameraPoints[tri[1]];
        const Vec3d& p2 = cameraPoints[tri[2]];
        if (backFacing(p0, p1, p2)) continue;
        z[0] = p0[2], z[1] = p1[2], z[2] = p2[2];
      }
      rasteriseTriangle<kNeedAttributes>(ScreenVertex{s0.x, s0.y, z[0], &kCornerBary[0]},
                                         ScreenVertex{s1.x, s1.y, z[1], &kCornerBary[1]},
                                         ScreenVertex{s2.x, s2.y, z[2], &kCornerBary[2]},
                                         camera.width, camera.height, perPixel);
      continue;
    }
    const Vec3d& p0 = cameraPoints[tri[0]];
    const Vec3d& p1 = cameraPoints[tri[1]];
    const Vec3d& p2 = cameraPoints[tri[2]];
    // Non-finite corners (bad input) cover nothing rather than reach the integer stage.
    if (!std::isfinite(p0[0] + p0[1] + p0[2] + p1[0] + p1[1] + p1[2] + p2[0] + p2[1] + p2[2]))
      continue;
    if (backFacing(p0, p1, p2)) continue;
    ClipVertex poly[48] = {{p0, kCornerBary[0]}, {p1, kCornerBary[1]}, {p2, kCornerBary[2]}};
    int n = 3;
    if (!volume.contains(p0) || !volume.contains(p1) || !volume.contains(p2))
      n = clipPolygon(poly, n, volume);
    if (n < 3) continue;
    ScreenVertex screen[48];
    bool representable = true;
    for (int k = 0; k < n; ++k) {
      const Vec2d pixel = camera.projectCameraPoint(poly[k].p);
      representable = representable && snappable(pixel);
      if (representable) screen[k] = {snap(pixel[0]), snap(pixel[1]), poly[k].p[2], &poly[k].bary};
    }
    if (!representable) continue;
    for (int k = 1; k + 1 < n; ++k)
      rasteriseTriangle<kNeedAttributes>(screen[0], screen[k], screen[k + 1], camera.width,
                                         camera.height, perPixel);
  }
}

// The checks and the clip volume of a camera (throws Error on an invalid set-up).
ClipVolume prepareCamera(const Camera& camera, const RasterOptions& options) {
  check(camera.width > 0 && camera.height > 0 && camera.width <= (1 << 15) &&
            camera.height <= (1 << 15),
        "rasterise: camera '" + camera.name + "' has an invalid image size");
  check(options.zNear > 0, "rasterise: zNear must be positive");
  return clipVolume(camera, options.zNear);
}

}  // namespace

Fragments rasterise(const Mesh& mesh, const Camera& camera, const RasterOptions& options) {
  const ClipVolume volume = prepareCamera(camera, options);
  Fragments f;
  f.width = camera.width;
  f.height = camera.height;
  const size_t n = static_cast<size_t>(camera.width) * static_cast<size_t>(camera.height);
  f.triangle.assign(n, -1);
  f.barycentric.assign(n, {0.f, 0.f, 0.f});
  std::vector<double> zBuffer(n, std::numeric_limits<double>::infinity());
  rasteriseMesh<true>(
      mesh, camera, options, volume, [&](int32_t t, int x, int y, double depth, const Vec3d& bary) {
        const size_t i = f.index(x, y);
        if (!(depth < zBuffer[i])) return;
        zBuffer[i] = depth;
        f.triangle[i] = t;
        f.barycentric[i] = {static_cast<float>(bary[0]), static_cast<float>(bary[1]),
                            static_cast<float>(bary[2])};
      });
  f.depth.assign(zBuffer.begin(), zBuffer.end());
  return f;
}

Image renderMask(const Mesh& mesh, const Camera& camera, const RasterOptions& options) {
  return MaskRenderer(camera, options).render(mesh);
}

struct MaskRenderer::Setup {
  Camera camera;
  RasterOptions options;
  ClipVolume volume;
};

MaskRenderer::MaskRenderer(const Camera& camera, const RasterOptions& options) {
  check(camera.width > 0 && camera.height > 0,
        "renderMask: camera '" + camera.name + "' has an invalid image size");
  setup_ = std::make_unique<const Setup>(Setup{camera, options, prepareCamera(camera, options)});
}

MaskRenderer::~MaskRenderer() = default;
MaskRenderer::MaskRenderer(MaskRenderer&&) noexcept = default;
MaskRenderer& MaskRenderer::operator=(MaskRenderer&&) noexcept = default;

const Camera& MaskRenderer::camera() const {
  return setup_->camera;
}

Image MaskRenderer::render(const Mesh& mesh) const {
  const Camera& camera = setup_->camera;
  Image mask(camera.width, camera.height, 1, 0);
  uint8_t* pixels = mask.pixels.data();
  const size_t width = static_cast<size_t>(mask.width);
  rasteriseMesh<false>(mesh, camera, setup_->options, setup_->volume,
                       [pixels, width](int32_t, int y, int x0, int x1) {
                         std::memset(
                             pixels + static_cast<size_t>(y) * width + static_cast<size_t>(x0), 255,
                             static_cast<size_t>(x1 - x0 + 1));
                       });
  return mask;
}

std::vector<float> renderDepth(const Mesh& mesh, const Camera& camera,
                               const RasterOptions& options) {
  return rasterise(mesh, camera, options).depth;
}

}  // namespace tdvo
