#include "tools/recon/photo_refinement.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "common/core/error.h"
#include "common/views/rasteriser.h"

namespace tdvo {

namespace {

constexpr int kPatch = 2;  // patch radius in samples: 5 × 5
constexpr int kSamples = (2 * kPatch + 1) * (2 * kPatch + 1);

struct GreyImage {
  int width = 0, height = 0;
  std::vector<float> v;
  // Bilinear grey level at pixel coordinates (pixel centres at integers); false off the image.
  bool sample(const Vec2d& p, float& out) const {
    if (!(p[0] >= 0 && p[1] >= 0 && p[0] <= width - 1.001 && p[1] <= height - 1.001)) return false;
    const int x = static_cast<int>(p[0]), y = static_cast<int>(p[1]);
    const float fx = static_cast<float>(p[0] - x), fy = static_cast<float>(p[1] - y);
    const float* r0 = &v[static_cast<size_t>(y) * static_cast<size_t>(width) + size_t(x)];
    const float* r1 = r0 + width;
    out = (1 - fy) * ((1 - fx) * r0[0] + fx * r0[1]) + fy * ((1 - fx) * r1[0] + fx * r1[1]);
    return true;
  }
};

GreyImage toGrey(const Image& image) {
  GreyImage g;
  g.width = image.width;
  g.height = image.height;
  g.v.resize(static_cast<size_t>(image.width) * static_cast<size_t>(image.height));
  for (size_t i = 0; i < g.v.size(); ++i) {
    const uint8_t* p = &image.pixels[i * static_cast<size_t>(image.channels)];
    g.v[i] = image.channels >= 3 ? 0.299f * p[0] + 0.587f * p[1] + 0.114f * p[2] : float(p[0]);
  }
  return g;
}

std::vector<Vec3d> vertexNormals(const Mesh& mesh) {
  std::vector<Vec3d> n(mesh.positions.size(), Vec3d{0, 0, 0});
  for (const Triangle& t : mesh.triangles) {
    const Vec3d& a = mesh.positions[t[0]];
    const Vec3d f = cross(mesh.positions[t[1]] - a, mesh.positions[t[2]] - a);  // 2 × area
    for (uint32_t v : t)
      n[v] = n[v] + f;
  }
  for (Vec3d& v : n) {
    const double l = norm(v);
    v = l > 0 ? (1 / l) * v : Vec3d{0, 0, 1};
  }
  return n;
}

// Normalised cross-correlation of two patches; false when either is flat.
bool ncc(const float* a, const float* b, double& out) {
  double ma = 0, mb = 0;
  for (int k = 0; k < kSamples; ++k) {
    ma += a[k];
    mb += b[k];
  }
  ma /= kSamples;
  mb /= kSamples;
  double sab = 0, saa = 0, sbb = 0;
  for (int k = 0; k < kSamples; ++k) {
    const double da = a[k] - ma, db = b[k] - mb;
    sab += da * db;
    saa += da * da;
    sbb += db * db;
  }
  if (saa < kSamples * 4.0 || sbb < kSamples * 4.0) return false;  // < 2 grey levels std. dev.
  out = sab / std::sqrt(saa * sbb);
  return true;
}

bool insideHull(const std::vector<CarvingView>& hull, const Vec3d& p) {
  for (const CarvingView& view : hull) {
    double d = 0;
    if (view.signedDistance(p, d) && d < 0) return false;
  }
  return true;
}

}  // namespace

PhotoRefineStats photoRefine(Mesh& surface, const std::vector<Camera>& cameras,
                             const std::vector<Image>& images, const std::vector<CarvingView>& hull,
                             double voxel, const PhotoRefineOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  check(cameras.size() == images.size(), "photoRefine: one image per camera");
  PhotoRefineStats stats;
  const size_t nv = surface.positions.size();
  stats.vertices = nv;
  std::vector<GreyImage> grey;
  for (const Image& image : images)
    grey.push_back(toGrey(image));
  std::vector<std::vector<uint32_t>> neighbours(nv);
  for (const Triangle& t : surface.triangles)
    for (int k = 0; k < 3; ++k) {
      neighbours[t[k]].push_back(t[(k + 1) % 3]);
      neighbours[t[k]].push_back(t[(k + 2) % 3]);
    }
  for (auto& n : neighbours) {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
  const std::vector<Vec3d> original = surface.positions;
  std::vector<double> total(nv, 0.0);  // displacement from the original position (world units)
  const int steps = static_cast<int>(std::floor((options.inward + options.outward) / options.step));
  const double cosLimit = std::cos(75.0 * 3.14159265358979323846 / 180);
  const std::vector<Vec3d> base = vertexNormals(surface);  // the search and move directions
  std::vector<size_t> visible;
  std::vector<float> patches;  // per visible camera × kSamples
  for (int iteration = 0; iteration < options.iterations; ++iteration) {
    const std::vector<Vec3d> normals = vertexNormals(surface);
    std::vector<std::vector<float>> depth;
    for (const Camera& camera : cameras)
      depth.push_back(renderDepth(surface, camera));
    std::vector<double> target(nv, 0.0), weight(nv, 0.0);
    size_t targets = 0;
    double scoreBefore = 0, scoreAfter = 0;
    for (size_t v = 0; v < nv; ++v) {
      const Vec3d& p = surface.positions[v];
      const Vec3d& n = base[v];
      // Visibility, and the most frontal camera first.
      visible.clear();
      double bestFacing = -1;
      for (size_t c = 0; c < cameras.size(); ++c) {
        const Camera& camera = cameras[c];
        const Vec3d toCamera = camera.centre() - p;
        const double facing = dot(normals[v], toCamera) / norm(toCamera);
        if (facing < cosLimit) continue;
        Vec2d px;
        if (!camera.project(p, px)) continue;
        // In the image (the nearest pixel), checked before the rounding, which a projection far
        // outside would overflow.
        if (!(px[0] >= -0.5 && px[1] >= -0.5 && px[0] < camera.width - 0.5 &&
              px[1] < camera.height - 0.5))
          continue;
        const int x = static_cast<int>(std::lround(px[0])),
                  y = static_cast<int>(std::lround(px[1]));
        if (x < 0 || y < 0 || x >= camera.width || y >= camera.height) continue;
        const float z = depth[c][static_cast<size_t>(y) * size_t(camera.width) + size_t(x)];
        if (camera.toCamera(p)[2] > double(z) + 1.5 * voxel) continue;
        visible.push_back(c);
        if (facing > bestFacing) {
          bestFacing = facing;
          std::swap(visible.front(), visible.back());
        }
      }
      if (static_cast<int>(visible.size()) < options.minCameras) continue;
      // Tangent frame and patch spacing: one pixel of the frontal camera.
      const Camera& ref = cameras[visible.front()];
      const double spacing = ref.toCamera(p)[2] / (0.5 * (ref.fx + ref.fy));
      const Vec3d a = std::fabs(n[0]) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
      const Vec3d u = spacing * normalized(cross(n, a));
      const Vec3d w = spacing * normalized(cross(n, u));
      patches.resize(visible.size() * kSamples);
      auto score = [&](double t, double& out) {
        const Vec3d q = original[v] + (t * voxel) * n;
        size_t used = 0;
        for (size_t k = 0; k < visible.size(); ++k) {
          const Camera& camera = cameras[visible[k]];
          float* patch = &patches[used * kSamples];
          // The patch's image is affine at this scale: project its centre and two neighbours.
          Vec2d c0, cu, cw;
          bool ok = camera.project(q, c0) && camera.project(q + u, cu) && camera.project(q + w, cw);
          const Vec2d du = {cu[0] - c0[0], cu[1] - c0[1]}, dw = {cw[0] - c0[0], cw[1] - c0[1]};
          int s = 0;
          for (int j = -kPatch; j <= kPatch && ok; ++j)
            for (int i = -kPatch; i <= kPatch && ok; ++i)
              ok = grey[visible[k]].sample(
                  {c0[0] + i * du[0] + j * dw[0], c0[1] + i * du[1] + j * dw[1]}, patch[s++]);
          if (ok)
            ++used;
          else if (k == 0)
            return false;
        }
        double sum = 0;
        int count = 0;
        for (size_t k = 1; k < used; ++k) {
          double r = 0;
          if (ncc(&patches[0], &patches[k * kSamples], r)) {
            sum += r;
            ++count;
          }
        }
        if (count + 1 < options.minCameras || count == 0) return false;
        out = sum / count;
        return true;
      };
      const double current = total[v] / voxel;
      double here = -2;
      if (!score(current, here)) continue;
      double best = here, bestT = current;
      for (int k = 0; k <= steps; ++k) {
        const double t = -options.inward + k * options.step;
        if (std::fabs(t - current) < 1e-9) continue;
        double s = 0;
        if (!score(t, s) || s <= best) continue;
        if (t > 0 && !insideHull(hull, original[v] + (t * voxel) * n)) continue;
        best = s;
        bestT = t;
      }
      if (best >= options.minScore && bestT != current) {
        target[v] = bestT * voxel;
        weight[v] = 1;
        ++targets;
        scoreBefore += here;
        scoreAfter += best;
      } else {
        target[v] = total[v];
        weight[v] = best >= options.minScore ? 1 : 0;
      }
    }
    if (iteration == 0 && targets > 0) {
      stats.meanScoreBefore = scoreBefore / double(targets);
      stats.meanScoreAfter = scoreAfter / double(targets);
    }
    stats.targets = targets;
    // Regularise: Jacobi iterations pulling each displacement to its target and its neighbours.
    std::vector<double> d = target, next(nv);
    for (size_t v = 0; v < nv; ++v)
      if (weight[v] == 0) d[v] = total[v];
    for (int k = 0; k < options.smoothing; ++k) {
      for (size_t v = 0; v < nv; ++v) {
        double mean = 0;
        for (uint32_t nb : neighbours[v])
          mean += d[nb];
        mean = neighbours[v].empty() ? d[v] : mean / double(neighbours[v].size());
        const double wv = weight[v] > 0 ? weight[v] : 0.1;
        const double goal = weight[v] > 0 ? target[v] : 0.0;
        next[v] = (wv * goal + mean) / (wv + 1);
      }
      d.swap(next);
    }
    // Move along the original normals, bounded to the search range and to the hull.
    for (size_t v = 0; v < nv; ++v) {
      const double dv = std::clamp(d[v], -options.inward * voxel, options.outward * voxel);
      const Vec3d q = original[v] + dv * base[v];
      if (dv > 0 && !insideHull(hull, q)) continue;
      total[v] = dv;
      surface.positions[v] = q;
    }
  }
  double sum = 0;
  for (double t : total)
    sum += std::fabs(t);
  stats.meanDisplacement = nv > 0 ? sum / double(nv) / voxel : 0;
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace tdvo
