#include "tools/eval/sample_mesh.h"

#include <cmath>
#include <map>
#include <utility>

#include "common/core/error.h"

namespace tdvo {

namespace {

Vec3d normalised(const Vec3d& v) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / n, v[1] / n, v[2] / n};
}

}  // namespace

Mesh icosphere(int subdivisions) {
  check(subdivisions >= 0 && subdivisions <= 8, "icosphere subdivisions must be in [0, 8]");
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  Mesh mesh;
  mesh.positions = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3d& p : mesh.positions)
    p = normalised(p);
  mesh.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = midpoints.find(key);
      if (it != midpoints.end()) return it->second;
      const Vec3d& pa = mesh.positions[a];
      const Vec3d& pb = mesh.positions[b];
      mesh.positions.push_back(normalised({pa[0] + pb[0], pa[1] + pb[1], pa[2] + pb[2]}));
      const uint32_t index = static_cast<uint32_t>(mesh.positions.size() - 1);
      midpoints.emplace(key, index);
      return index;
    };
    std::vector<Triangle> finer;
    finer.reserve(mesh.triangles.size() * 4);
    for (const Triangle& tri : mesh.triangles) {
      const uint32_t ab = midpoint(tri[0], tri[1]);
      const uint32_t bc = midpoint(tri[1], tri[2]);
      const uint32_t ca = midpoint(tri[2], tri[0]);
      finer.push_back({tri[0], ab, ca});
      finer.push_back({tri[1], bc, ab});
      finer.push_back({tri[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    mesh.triangles = std::move(finer);
  }
  return mesh;
}

std::vector<Mesh> deformingBlob(int subdivisions, int frames) {
  check(frames >= 1, "deformingBlob needs at least one frame");
  const Mesh base = icosphere(subdivisions);
  const double kPi = 3.14159265358979323846;
  std::vector<Mesh> sequence;
  sequence.reserve(frames);
  for (int f = 0; f < frames; ++f) {
    const double phase = 2.0 * kPi * f / frames;
    Mesh mesh = base;
    for (Vec3d& p : mesh.positions) {
      // A travelling wave along y, a bend in x that grows with height, and a sideways sway.
      const double radius = 1.0 + 0.18 * std::sin(3.0 * p[1] + phase) +
                            0.07 * std::cos(5.0 * std::atan2(p[2], p[0]) - 2.0 * phase);
      const double y = 1.3 * p[1];
      p = {p[0] * radius + 0.25 * std::sin(phase) * (y + 1.3) * (y + 1.3) / 2.0 +
               0.3 * std::sin(phase),
           y, p[2] * radius};
    }
    sequence.push_back(std::move(mesh));
  }
  return sequence;
}

}  // namespace tdvo
