#include "common/pmesh_prediction.h"

#include <algorithm>
#include <unordered_map>

namespace tdvo {

namespace {

uint64_t undirectedEdge(uint32_t a, uint32_t b) {
  return a < b ? (uint64_t(a) << 32 | b) : (uint64_t(b) << 32 | a);
}

}  // namespace

GomTopology GomTopology::build(const IntMesh& iMesh) {
  GomTopology t;
  const uint32_t n = static_cast<uint32_t>(iMesh.positions.size());
  t.numVertices = n;

  // 1-rings in CSR form.
  std::vector<std::vector<uint32_t>> ring(n);
  for (const Triangle& tri : iMesh.triangles)
    for (int k = 0; k < 3; ++k) {
      ring[tri[k]].push_back(tri[(k + 1) % 3]);
      ring[tri[k]].push_back(tri[(k + 2) % 3]);
    }
  t.neighbourStart.assign(n + 1, 0);
  for (uint32_t v = 0; v < n; ++v) {
    std::sort(ring[v].begin(), ring[v].end());
    ring[v].erase(std::unique(ring[v].begin(), ring[v].end()), ring[v].end());
    t.neighbourStart[v + 1] = t.neighbourStart[v] + static_cast<uint32_t>(ring[v].size());
  }
  t.neighbours.reserve(t.neighbourStart[n]);
  for (uint32_t v = 0; v < n; ++v)
    t.neighbours.insert(t.neighbours.end(), ring[v].begin(), ring[v].end());

  // Wings: for each corner (v, a, b) every other triangle's third vertex on edge a-b.
  std::unordered_map<uint64_t, std::vector<uint32_t>> opposite;
  opposite.reserve(iMesh.triangles.size() * 3 / 2 + 1);
  for (const Triangle& tri : iMesh.triangles)
    for (int k = 0; k < 3; ++k)
      opposite[undirectedEdge(tri[(k + 1) % 3], tri[(k + 2) % 3])].push_back(tri[k]);
  std::vector<std::vector<std::array<uint32_t, 3>>> wingsOf(n);
  for (const Triangle& tri : iMesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = tri[k], a = tri[(k + 1) % 3], b = tri[(k + 2) % 3];
      for (uint32_t o : opposite[undirectedEdge(a, b)])
        if (o != v) wingsOf[v].push_back({a, b, o});
    }
  t.wingStart.assign(n + 1, 0);
  for (uint32_t v = 0; v < n; ++v)
    t.wingStart[v + 1] = t.wingStart[v] + static_cast<uint32_t>(wingsOf[v].size());
  t.wings.reserve(t.wingStart[n]);
  for (uint32_t v = 0; v < n; ++v)
    t.wings.insert(t.wings.end(), wingsOf[v].begin(), wingsOf[v].end());

  // Breadth-first order.
  t.order.reserve(n);
  std::vector<uint8_t> seen(n, 0);
  for (uint32_t start = 0; start < n; ++start) {
    if (seen[start]) continue;
    seen[start] = 1;
    size_t head = t.order.size();
    t.order.push_back(start);
    while (head < t.order.size()) {
      const uint32_t v = t.order[head++];
      for (uint32_t i = t.neighbourStart[v]; i < t.neighbourStart[v + 1]; ++i) {
        const uint32_t u = t.neighbours[i];
        if (!seen[u]) {
          seen[u] = 1;
          t.order.push_back(u);
        }
      }
    }
  }
  return t;
}

int64_t roundDiv(int64_t num, int64_t den) {
  const int64_t a = 2 * num + den, b = 2 * den;
  // Floor division (C++ truncates toward zero).
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

Vec3i predictMotion(const GomTopology& t, uint32_t v, const std::vector<Vec3i>& motion,
                    const std::vector<uint8_t>& available, const Vec3i& fallback) {
  int64_t sN[3] = {0, 0, 0}, sP[3] = {0, 0, 0};
  int64_t k = 0, kp = 0;
  for (uint32_t i = t.neighbourStart[v]; i < t.neighbourStart[v + 1]; ++i) {
    const uint32_t u = t.neighbours[i];
    if (!available[u]) continue;
    ++k;
    for (int c = 0; c < 3; ++c)
      sN[c] += motion[u][c];
  }
  if (k == 0) return fallback;
  for (uint32_t i = t.wingStart[v]; i < t.wingStart[v + 1]; ++i) {
    const auto& w = t.wings[i];
    if (!available[w[0]] || !available[w[1]] || !available[w[2]]) continue;
    ++kp;
    for (int c = 0; c < 3; ++c)
      sP[c] += int64_t{motion[w[0]][c]} + motion[w[1]][c] - motion[w[2]][c];
  }
  Vec3i p;
  for (int c = 0; c < 3; ++c)
    p[c] = static_cast<int32_t>(kp == 0 ? roundDiv(sN[c], k)
                                        : roundDiv(kp * sN[c] + k * sP[c], 2 * k * kp));
  return p;
}

void OctreePartition::split(const std::vector<Vec3i>& positions, uint32_t* begin, uint32_t* end,
                            int gridBits, int depth, std::array<uint32_t, 9>& bounds,
                            std::vector<uint32_t>& scratch) {
  const int shift = gridBits - 1 - depth;
  auto octant = [&](uint32_t v) {
    const Vec3i& p = positions[v];
    return ((p[0] >> shift) & 1) << 2 | ((p[1] >> shift) & 1) << 1 | ((p[2] >> shift) & 1);
  };
  std::array<uint32_t, 8> count{};
  for (uint32_t* it = begin; it != end; ++it)
    ++count[octant(*it)];
  bounds[0] = 0;
  for (int o = 0; o < 8; ++o)
    bounds[o + 1] = bounds[o] + count[o];
  scratch.resize(static_cast<size_t>(end - begin));
  std::array<uint32_t, 8> fill;
  for (int o = 0; o < 8; ++o)
    fill[o] = bounds[o];
  for (uint32_t* it = begin; it != end; ++it)
    scratch[fill[octant(*it)]++] = *it;
  std::copy(scratch.begin(), scratch.end(), begin);
}

Vec3i applyMotion(const Vec3i& previous, const Vec3i& motion, int gridBits) {
  const int64_t maxCoordinate = (int64_t{1} << gridBits) - 1;
  Vec3i out;
  for (int c = 0; c < 3; ++c)
    out[c] = static_cast<int32_t>(
        std::clamp<int64_t>(int64_t{previous[c]} + motion[c], 0, maxCoordinate));
  return out;
}

}  // namespace tdvo
