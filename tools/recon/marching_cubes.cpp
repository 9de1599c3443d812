#include "tools/recon/marching_cubes.h"

#include <algorithm>
#include <cstddef>
#include <stdexcept>

namespace tdvo {

const std::array<std::array<int, 2>, 12> kCubeEdgeCorners = {{
    {0, 1},
    {2, 3},
    {4, 5},
    {6, 7},  // along x
    {0, 2},
    {1, 3},
    {4, 6},
    {5, 7},  // along y
    {0, 4},
    {1, 5},
    {2, 6},
    {3, 7},  // along z
}};

namespace {

// The six faces, each as its four corners counter-clockwise seen from outside the cube
// ((p1 − p0) × (p2 − p0) points out of the cube).
constexpr int kFaces[6][4] = {
    {0, 4, 6, 2}, {1, 3, 7, 5},  // x = 0, x = 1
    {0, 1, 5, 4}, {2, 6, 7, 3},  // y = 0, y = 1
    {0, 2, 3, 1}, {4, 5, 7, 6},  // z = 0, z = 1
};

int edgeBetween(int a, int b) {
  for (int e = 0; e < 12; ++e)
    if ((kCubeEdgeCorners[e][0] == a && kCubeEdgeCorners[e][1] == b) ||
        (kCubeEdgeCorners[e][0] == b && kCubeEdgeCorners[e][1] == a))
      return e;
  return -1;  // not reached for the corners of one face
}

// True when two cube edges lie on a common face.
bool shareFace(int a, int b) {
  for (const auto& face : kFaces) {
    int found = 0;
    for (int k = 0; k < 4; ++k) {
      const int e = edgeBetween(face[k], face[(k + 1) % 4]);
      found += (e == a) + (e == b);
    }
    if (found == 2) return true;
  }
  return false;
}

// Triangulates a loop of crossings (its order gives the winding). A diagonal between two
// crossings on one cube face would lie in that face, where the neighbouring cube may draw the
// same edge: only diagonals between crossings on different faces are used, splitting the loop
// as evenly as possible.
void triangulate(const std::vector<int>& loop, CubeCaseTriangles& triangles) {
  const size_t n = loop.size();
  if (n == 3) {
    triangles.push_back({static_cast<uint8_t>(loop[0]), static_cast<uint8_t>(loop[1]),
                         static_cast<uint8_t>(loop[2])});
    return;
  }
  size_t bestI = 0, bestJ = 0, bestBalance = 0;
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // neighbours on the loop
      if (shareFace(loop[i], loop[j])) continue;
      const size_t balance = std::min(j - i, n - (j - i));
      if (balance > bestBalance) {
        bestBalance = balance;
        bestI = i;
        bestJ = j;
      }
    }
  if (bestBalance == 0) throw std::logic_error("marching cubes: loop without a usable diagonal");
  std::vector<int> first(loop.begin() + static_cast<long>(bestI),
                         loop.begin() + static_cast<long>(bestJ) + 1);
  std::vector<int> second(loop.begin() + static_cast<long>(bestJ), loop.end());
  second.insert(second.end(), loop.begin(), loop.begin() + static_cast<long>(bestI) + 1);
  triangulate(first, triangles);
  triangulate(second, triangles);
}

CubeCaseTriangles buildCase(int index) {
  auto inside = [index](int corner) { return ((index >> corner) & 1) != 0; };
  // next[e]: the crossing that follows crossing e on the surface's boundary loop in this cube.
  std::array<int, 12> next;
  next.fill(-1);
  for (const auto& face : kFaces) {
    // Crossings in counter-clockwise order around the face (seen from outside); `entry` when
    // the walk goes from an outside corner to an inside one.
    int edges[4], count = 0;
    bool entry[4];
    for (int k = 0; k < 4; ++k) {
      const int a = face[k], b = face[(k + 1) % 4];
      if (inside(a) == inside(b)) continue;
      edges[count] = edgeBetween(a, b);
      entry[count] = inside(b);
      ++count;
    }
    // Each exit is paired with the entry just before it: the segment cuts off the run of inside
    // corners between them. On an ambiguous face (four crossings) this separates the two inside
    // corners, a choice that depends on the face alone. The segment runs exit → entry, which
    // keeps the inside on its left seen from outside.
    for (int i = 0; i < count; ++i)
      if (!entry[i]) next[edges[i]] = edges[(i + count - 1) % count];
  }
  CubeCaseTriangles triangles;
  std::array<bool, 12> used{};
  for (int start = 0; start < 12; ++start) {
    if (next[start] < 0 || used[start]) continue;
    std::vector<int> loop;
    for (int e = start; !used[e]; e = next[e]) {
      used[e] = true;
      loop.push_back(e);
    }
    // The loop runs counter-clockwise around the inside corners seen from outside the cube, so
    // its right-hand normal points into the inside region; it is reversed to make normals point
    // outwards.
    std::reverse(loop.begin(), loop.end());
    triangulate(loop, triangles);
  }
  return triangles;
}

}  // namespace

const std::array<CubeCaseTriangles, 256>& marchingCubesTable() {
  static const std::array<CubeCaseTriangles, 256> table = [] {
    std::array<CubeCaseTriangles, 256> t;
    for (int c = 0; c < 256; ++c)
      t[static_cast<size_t>(c)] = buildCase(c);
    return t;
  }();
  return table;
}

MarchingCubesMesher::MarchingCubesMesher(const Vec3d& origin, double step, int64_t corners)
    : origin_(origin), step_(step), corners_(corners) {}

void MarchingCubesMesher::addCube(int64_t i, int64_t j, int64_t k,
                                  const std::array<float, 8>& value) {
  const CubeCaseTriangles& triangles = marchingCubesTable()[static_cast<size_t>(cubeCase(value))];
  if (triangles.empty()) return;
  std::array<uint32_t, 12> vertexOfEdge;
  vertexOfEdge.fill(UINT32_MAX);
  for (const auto& triangle : triangles) {
    Triangle out;
    for (size_t s = 0; s < 3; ++s) {
      const int e = triangle[s];
      if (vertexOfEdge[static_cast<size_t>(e)] == UINT32_MAX) {
        const int a = kCubeEdgeCorners[static_cast<size_t>(e)][0];
        const int b = kCubeEdgeCorners[static_cast<size_t>(e)][1];
        const int64_t ai = i + (a & 1), aj = j + ((a >> 1) & 1), ak = k + ((a >> 2) & 1);
        const int axis = e / 4;
        const uint64_t key = static_cast<uint64_t>((ak * corners_ + aj) * corners_ + ai) * 3 +
                             static_cast<uint64_t>(axis);
        auto [it, fresh] = edgeVertex_.emplace(key, static_cast<uint32_t>(mesh_.positions.size()));
        if (fresh) {
          const double va = value[static_cast<size_t>(a)], vb = value[static_cast<size_t>(b)];
          const double t = std::clamp(va / (va - vb), 1e-3, 1 - 1e-3);
          Vec3d p = {origin_[0] + step_ * static_cast<double>(ai),
                     origin_[1] + step_ * static_cast<double>(aj),
                     origin_[2] + step_ * static_cast<double>(ak)};
          p[static_cast<size_t>(axis)] += t * step_;
          mesh_.positions.push_back(p);
        }
        vertexOfEdge[static_cast<size_t>(e)] = it->second;
      }
      out[s] = vertexOfEdge[static_cast<size_t>(e)];
    }
    mesh_.triangles.push_back(out);
  }
}

}  // namespace tdvo
