// Shared P-mesh tools: the GOM's topology, the motion predictor and the octree partition. Both
// the P-mesh encoder and decoder call exactly this code, so their predictions cannot drift
// apart. Everything here is integer arithmetic with documented rounding (docs/bitstream.md,
// "P-mesh decoding process").
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "common/mesh.h"

namespace tdvo {

// Connectivity facts of a GOM's I mesh that P-mesh prediction uses.
struct GomTopology {
  uint32_t numVertices = 0;
  // 1-ring of vertex v: neighbours[neighbourStart[v] .. neighbourStart[v+1]), ascending.
  std::vector<uint32_t> neighbourStart, neighbours;
  // Wings of vertex v: wings[wingStart[v] .. wingStart[v+1]). A wing (a, b, o) says that
  // (v, a, b) is a triangle and o is the third vertex of another triangle on edge a-b, so that
  // a + b - o is a parallelogram prediction of v.
  std::vector<uint32_t> wingStart;
  std::vector<std::array<uint32_t, 3>> wings;
  // Breadth-first order over the I mesh: components in order of their lowest vertex index,
  // each from that vertex, neighbours visited in ascending index order.
  std::vector<uint32_t> order;

  static GomTopology build(const IntMesh& iMesh);
};

// round(num / den) for den > 0, halves rounded up: floor((2 * num + den) / (2 * den)).
int64_t roundDiv(int64_t num, int64_t den);

// The motion predictor of vertex v from motions already final (available[u] != 0):
//   k  available 1-ring neighbours, sN = sum of their motions;
//   kp wings (a, b, o) with a, b, o all available, sP = sum of (m_a + m_b - m_o);
//   k == 0          -> fallback
//   kp == 0         -> roundDiv(sN, k)                   (mean of neighbours)
//   otherwise       -> roundDiv(kp * sN + k * sP, 2 k kp) (average of the mean of neighbours and
//                                                          the mean parallelogram prediction)
Vec3i predictMotion(const GomTopology& topology, uint32_t v, const std::vector<Vec3i>& motion,
                    const std::vector<uint8_t>& available, const Vec3i& fallback);

// Octree over grid positions. The root cell is the whole grid [0, 2^gridBits)^3; a cell at
// depth d is split into octants by bit (gridBits - 1 - d) of x, y and z; the octant number is
// 4 * xbit + 2 * ybit + zbit. Cells at depth gridBits are single grid points.
struct OctreePartition {
  // Reorders vertex indices [begin, end) stably by octant at `depth` and writes the 9 bounds
  // of the octant ranges (bounds[o] .. bounds[o+1]) relative to begin.
  static void split(const std::vector<Vec3i>& positions, uint32_t* begin, uint32_t* end,
                    int gridBits, int depth, std::array<uint32_t, 9>& bounds,
                    std::vector<uint32_t>& scratch);
};

// prev + motion, clamped into the grid [0, 2^gridBits - 1] per coordinate.
Vec3i applyMotion(const Vec3i& previous, const Vec3i& motion, int gridBits);

}  // namespace tdvo
