#include "tools/recon/visual_hull.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include "common/core/error.h"
#include "tools/recon/marching_cubes.h"

namespace tdvo {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The octree walk. Cells are addressed by their lowest voxel (i, j, k) and their edge in
// voxels (a power of two).
class Carver {
 public:
  Carver(const std::vector<CarvingView>& views, const CaptureCube& cube, int depth, int minViews,
         const HullOptions* clip = nullptr)
      : n_(1 << depth),
        views_(views),
        cube_(cube),
        voxel_(cube.size / (1 << depth)),
        minViews_(minViews),
        clip_(clip && clip->clip ? clip : nullptr) {}

  void run() {
    std::vector<uint16_t> active(views_.size());
    for (size_t v = 0; v < views_.size(); ++v)
      active[v] = static_cast<uint16_t>(v);
    carve(0, 0, 0, n_, active, 0);
  }

  Vec3d corner(int64_t i, int64_t j, int64_t k) const {
    return {cube_.origin[0] + voxel_ * static_cast<double>(i),
            cube_.origin[1] + voxel_ * static_cast<double>(j),
            cube_.origin[2] + voxel_ * static_cast<double>(k)};
  }

  int n_;  // voxels per axis
  std::vector<std::array<int32_t, 3>> partialVoxels;
  size_t cellsJudged = 0, insideCells = 0;
  double insideVolume = 0;
  Vec3d insideLo = {1e300, 1e300, 1e300}, insideHi = {-1e300, -1e300, -1e300};

 private:
  void keepInside(const Vec3d& lo, const Vec3d& hi) {
    for (int a = 0; a < 3; ++a) {
      insideLo[a] = std::min(insideLo[a], lo[a]);
      insideHi[a] = std::max(insideHi[a], hi[a]);
    }
  }

  void carve(int i, int j, int k, int span, const std::vector<uint16_t>& active, int seenInside) {
    ++cellsJudged;
    const Vec3d lo = corner(i, j, k), hi = corner(i + span, j + span, k + span);
    bool partial = false;
    if (clip_) {
      for (int a = 0; a < 3; ++a) {
        if (hi[a] <= clip_->clipLo[a] || lo[a] >= clip_->clipHi[a]) return;
        // Strictly inside, so that no corner of an inside cell lies on the box.
        if (lo[a] <= clip_->clipLo[a] || hi[a] >= clip_->clipHi[a]) partial = true;
      }
    }
    std::vector<uint16_t> still;
    still.reserve(active.size());
    for (uint16_t v : active) {
      switch (views_[v].judgeBox(lo, hi)) {
        case ViewVerdict::outside:
          return;
        case ViewVerdict::unseen:
          break;
        case ViewVerdict::insideSeen:
          ++seenInside;
          break;
        case ViewVerdict::insideClipped:
          still.push_back(v);
          break;
        case ViewVerdict::partial:
          still.push_back(v);
          partial = true;
          break;
      }
    }
    if (seenInside + static_cast<int>(still.size()) < minViews_) return;
    if (!partial && seenInside >= minViews_) {
      ++insideCells;
      insideVolume += std::pow(voxel_ * span, 3);
      keepInside(lo, hi);
      return;
    }
    if (span == 1) {
      partialVoxels.push_back({i, j, k});
      return;
    }
    const int h = span / 2;
    for (int c = 0; c < 8; ++c)
      carve(i + (c & 1 ? h : 0), j + (c & 2 ? h : 0), k + (c & 4 ? h : 0), h, still, seenInside);
  }

  const std::vector<CarvingView>& views_;
  CaptureCube cube_;
  double voxel_;
  int minViews_;
  const HullOptions* clip_;
};

// First guess of the capture cube without a clip box: around the point nearest (least squares)
// to every optical axis, reaching three quarters of the way to the nearest camera.
CaptureCube axesGuess(const std::vector<CarvingView>& views) {
  // Σ (I − d dᵀ) x = Σ (I − d dᵀ) c.
  double a[3][3] = {}, b[3] = {};
  for (const CarvingView& view : views) {
    const Vec3d c = view.pinhole().centre(), d = view.pinhole().viewingDirection();
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s < 3; ++s) {
        const double m = (r == s ? 1.0 : 0.0) - d[r] * d[s];
        a[r][s] += m;
        b[r] += m * c[s];
      }
  }
  const Mat3d m = {Vec3d{a[0][0], a[0][1], a[0][2]}, Vec3d{a[1][0], a[1][1], a[1][2]},
                   Vec3d{a[2][0], a[2][1], a[2][2]}};
  Vec3d centre;
  double nearest = 1e300;
  if (std::abs(determinant(m)) > 1e-6 * std::pow(static_cast<double>(views.size()), 3)) {
    // Cramer's rule on the 3 × 3 system.
    const double det = determinant(m);
    for (int col = 0; col < 3; ++col) {
      Mat3d mc = m;
      for (int r = 0; r < 3; ++r)
        mc[r][col] = b[r];
      centre[col] = determinant(mc) / det;
    }
  } else {
    // Parallel axes: a point in front of the cameras, at their mean distance apart.
    Vec3d mean = {0, 0, 0}, dir = {0, 0, 0};
    for (const CarvingView& view : views) {
      mean = mean + (1.0 / views.size()) * view.pinhole().centre();
      dir = dir + view.pinhole().viewingDirection();
    }
    double spread = 0;
    for (const CarvingView& view : views)
      spread = std::max(spread, norm(view.pinhole().centre() - mean));
    centre = mean + std::max(spread, 1.0) * normalized(dir);
  }
  for (const CarvingView& view : views)
    nearest = std::min(nearest, norm(view.pinhole().centre() - centre));
  const double half = 0.75 * nearest;
  return CaptureCube{centre - Vec3d{half, half, half}, 2 * half};
}

// The hull's signed distance at a point: the smallest of the views' signed distances, limited
// by the clip box; `outside` when fewer than minViews views see the point.
float hullValue(const std::vector<CarvingView>& views, const Vec3d& p, const HullOptions& options,
                float outside) {
  double smallest = 1e300;
  int seen = 0;
  for (const CarvingView& view : views) {
    double d;
    if (!view.signedDistance(p, d)) continue;
    ++seen;
    smallest = std::min(smallest, d);
  }
  float v = seen >= options.minViews ? static_cast<float>(smallest) : outside;
  if (options.clip)
    for (int a = 0; a < 3; ++a)
      v = std::min({v, static_cast<float>(p[a] - options.clipLo[a]),
                    static_cast<float>(options.clipHi[a] - p[a])});
  return v;
}

}  // namespace

HullResult carveVisualHull(const std::vector<CarvingView>& views, const CaptureCube& cube,
                           const HullOptions& options) {
  check(!views.empty(), "no views to carve from");
  check(options.depth >= 1 && options.depth <= 12, "OctreeDepth must be in 1 .. 12");
  check(views.size() < 65536, "too many views");
  const auto start = std::chrono::steady_clock::now();
  Carver carver(views, cube, options.depth, options.minViews, &options);
  carver.run();
  HullResult result;
  result.voxelSize = cube.size / carver.n_;
  result.cellsJudged = carver.cellsJudged;
  result.insideCells = carver.insideCells;
  result.insideVolume = carver.insideVolume;
  result.surfaceVoxels = carver.partialVoxels.size();
  result.carvingSeconds = secondsSince(start);

  // The hull's signed distance at the corners of the partial voxels.
  const auto surfaceStart = std::chrono::steady_clock::now();
  const int64_t n = carver.n_, stride = n + 1;
  auto cornerKey = [stride](int64_t i, int64_t j, int64_t k) {
    return static_cast<uint64_t>((k * stride + j) * stride + i);
  };
  const float outsideValue = static_cast<float>(-result.voxelSize);
  std::unordered_map<uint64_t, float> values;
  values.reserve(carver.partialVoxels.size() * 2);
  auto value = [&](int64_t i, int64_t j, int64_t k) {
    const uint64_t key = cornerKey(i, j, k);
    auto it = values.find(key);
    if (it != values.end()) return it->second;
    float v = outsideValue;
    if (i > 0 && j > 0 && k > 0 && i < n && j < n && k < n) {
      v = hullValue(views, carver.corner(i, j, k), options, outsideValue);
    }
    values.emplace(key, v);
    return v;
  };

  // Marching cubes over the partial voxels.
  MarchingCubesMesher mesher(cube.origin, result.voxelSize, stride);
  for (const auto& voxel : carver.partialVoxels) {
    std::array<float, 8> corner;
    for (int c = 0; c < 8; ++c)
      corner[static_cast<size_t>(c)] =
          value(voxel[0] + (c & 1), voxel[1] + ((c >> 1) & 1), voxel[2] + ((c >> 2) & 1));
    mesher.addCube(voxel[0], voxel[1], voxel[2], corner);
  }
  result.surface = std::move(mesher.mesh());
  result.surfaceSeconds = secondsSince(surfaceStart);
  return result;
}

void occupiedBounds(const std::vector<CarvingView>& views, const CaptureCube& cube,
                    const HullOptions& options, Vec3d& lo, Vec3d& hi) {
  Carver carver(views, cube, options.depth, options.minViews, &options);
  carver.run();
  lo = carver.insideLo;
  hi = carver.insideHi;
  // A partial voxel counts when the hull reaches into it at one of its corners or its centre:
  // voxels across an image border, for example, are partial without holding any hull.
  const double h = cube.size / carver.n_;
  for (const auto& voxel : carver.partialVoxels) {
    const Vec3d base = carver.corner(voxel[0], voxel[1], voxel[2]);
    bool occupied = hullValue(views, base + Vec3d{h / 2, h / 2, h / 2}, options, -1) > 0;
    for (int c = 0; c < 8 && !occupied; ++c)
      occupied = hullValue(views, base + Vec3d{c & 1 ? h : 0, c & 2 ? h : 0, c & 4 ? h : 0},
                           options, -1) > 0;
    if (!occupied) continue;
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], base[a]);
      hi[a] = std::max(hi[a], base[a] + h);
    }
  }
}

CaptureCube estimateCaptureCube(const std::vector<CarvingView>& views, const HullOptions& options,
                                double margin) {
  check(!views.empty(), "no views to carve from");
  HullOptions coarse = options;
  coarse.depth = 6;
  CaptureCube cube;
  if (options.clip) {
    for (int k = 0; k < 3; ++k)
      cube.size = std::max(cube.size, options.clipHi[k] - options.clipLo[k]);
    cube.size *= 1.02;
    for (int k = 0; k < 3; ++k)
      cube.origin[k] = 0.5 * (options.clipLo[k] + options.clipHi[k]) - 0.5 * cube.size;
  } else {
    cube = axesGuess(views);
  }
  for (int pass = 0; pass < 2; ++pass) {
    Vec3d lo, hi;
    occupiedBounds(views, cube, coarse, lo, hi);
    check(lo[0] <= hi[0],
          "the silhouettes do not agree on any region: nothing is left after carving the "
          "capture volume (check the calibration, the masks, or MinViews)");
    double extent = 0;
    for (int k = 0; k < 3; ++k)
      extent = std::max(extent, hi[k] - lo[k]);
    const double size = extent * (1 + 2 * margin);
    cube.size = size;
    for (int k = 0; k < 3; ++k)
      cube.origin[k] = 0.5 * (lo[k] + hi[k]) - 0.5 * size;
  }
  return cube;
}

double enclosedVolume(const Mesh& mesh) {
  if (mesh.positions.empty()) return 0;
  // Relative to a vertex, so that meshes far from the origin keep their precision.
  const Vec3d o = mesh.positions[0];
  double volume = 0;
  for (const Triangle& t : mesh.triangles) {
    const Vec3d a = mesh.positions[t[0]] - o;
    const Vec3d b = mesh.positions[t[1]] - o;
    const Vec3d c = mesh.positions[t[2]] - o;
    volume += dot(a, cross(b, c));
  }
  return volume / 6;
}

}  // namespace tdvo
