// Shared P-mesh tools: the GOM's topology, the motion predictor and the octree partition. Both
// the P-mesh encoder and decoder call exactly this code, so their predictions cannot drift
// apart. Everything here is integer arithmetic with documented rounding (docs/bitstream.md,
// "P-mesh decoding process").
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "common/core/mesh.h"

namespace tdvo {

// The 1-rings and wings of a GOM's vertices as flat arrays (GomTopology's, in vertex space or in
// rank space): vertex v's neighbours are neighbours[neighbourStart[v] .. neighbourStart[v+1]),
// its wings wings[wingStart[v] .. wingStart[v+1]); both index the records of that space.
struct RingView {
  const uint32_t* neighbourStart;
  const uint32_t* neighbours;
  const uint32_t* wingStart;
  const std::array<uint32_t, 3>* wings;
};

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

  // The same rings and wings in breadth-first rank space (rank[v]: the place of v in `order`),
  // for P-mesh coding, which walks the vertices in that order: vertex order[r]'s neighbours are
  // rankNeighbours[rankNeighbourStart[r] .. rankNeighbourStart[r+1]) (ranks, not indices), its
  // wings rankWings[rankWingStart[r] .. rankWingStart[r+1]). A vertex's neighbours are then
  // close to it in rank, so the per-vertex records they point at share cache lines.
  std::vector<uint32_t> rank;
  std::vector<uint32_t> rankNeighbourStart, rankNeighbours;
  std::vector<uint32_t> rankWingStart;
  std::vector<std::array<uint32_t, 3>> rankWings;

  // Throws Error when pairs of triangles on shared edges exceed three per triangle (more than
  // two triangles on some edges; the wings would grow quadratically), before allocating them.
  static GomTopology build(const IntMesh& iMesh);

  // The rings and wings as a RingView: indexed by vertex, or by rank.
  RingView vertexRings() const {
    return {neighbourStart.data(), neighbours.data(), wingStart.data(), wings.data()};
  }
  RingView rankRings() const {
    return {rankNeighbourStart.data(), rankNeighbours.data(), rankWingStart.data(),
            rankWings.data()};
  }
};

// ceil(2^64 / b) for the divisors b in [2, kCount) that floorDiv handles by multiplication.
struct SmallReciprocals {
  static constexpr int64_t kCount = 1024;
  uint64_t value[kCount];
  constexpr SmallReciprocals() : value() {
    for (int64_t b = 2; b < kCount; ++b)
      value[b] = UINT64_MAX / uint64_t(b) + 1;
  }
};
inline constexpr SmallReciprocals kSmallReciprocals;

// floor(a / b) for b > 0.
inline int64_t floorDiv(int64_t a, int64_t b) {
  if (b >= 2 && b < SmallReciprocals::kCount) {
    // A 64-bit division takes about 15 cycles, a multiplication 4. a * ceil(2^64 / b) / 2^64
    // differs from a / b by less than 1/2 for any int64 a, so its floor is floor(a / b) or a
    // neighbour, and the remainder (in [-b, 2b), computed modulo 2^64) says which. Exact.
    int64_t q = int64_t((__int128{a} * __int128{kSmallReciprocals.value[b]}) >> 64);
    const int64_t r = int64_t(uint64_t(a) - uint64_t(q) * uint64_t(b));
    return q + int64_t(r >= b) - int64_t(r < 0);
  }
  // C++ truncates toward zero, one too high when a negative a leaves a remainder. Written
  // without a branch on the sign, which follows the data.
  const int64_t q = a / b, r = a % b;
  return q - (r < 0);
}

// round(num / den) for den > 0, halves rounded up: floor((2 * num + den) / (2 * den)).
inline int64_t roundDiv(int64_t num, int64_t den) {
  return floorDiv(2 * num + den, 2 * den);
}

// Four int32 lanes that + and - combine lane by lane, one SIMD instruction each (a GCC/Clang
// vector extension): x, y, z and a count.
using Lanes4 = int32_t __attribute__((vector_size(16)));
// The same lanes widened to int64, for sums that could overflow int32.
using Wide4 = int64_t __attribute__((vector_size(32)));

// What the predictor knows about one vertex (and what codePMesh, bitstream/pmesh_syntax.h,
// keeps per vertex while it codes a P mesh). 32 bytes, so that the neighbour loops read one
// cache line per neighbour. Each half is four lanes whose last lane is a flag, so that summing
// records over a 1-ring also counts the flags. Two invariants let those loops add without
// branching: a vertex whose motion is not final yet has motion (0, 0, 0), and absResidual is
// (0, 0, 0) unless the vertex has a decoded residual. Motions and residuals are at most 2^21 in
// magnitude (kMaxMotion; any motion on a grid of at most 20 bits).
struct MotionRecord {
  // m[v] in lanes 0-2; lane 3 "available": -1 (all bits set, a ready-made mask) when the motion
  // is final, else 0.
  Lanes4 motion{0, 0, 0, -1};
  // |residual| per component in lanes 0-2 once decoded; lane 3 "hasResidual": 1 once decoded.
  Lanes4 absResidual{0, 0, 0, 0};
};
static_assert(sizeof(MotionRecord) == 32, "one record per half cache line");

// The residual statistics of a vertex's 1-ring (for the residual's context, pmesh_syntax.h):
// sums[c] the sum of |residual| in component c over the neighbours with a decoded residual,
// sums[3] how many they are (the absResidual lanes, summed).
struct RingResiduals {
  int64_t sums[4];
  int64_t count() const { return sums[3]; }
};

namespace detail {

template <bool kResiduals>
inline Vec3i predictMotion(const RingView rings, const MotionRecord* records, uint32_t v,
                           const Vec3i& fallback, RingResiduals* residuals) {
  // Over the 1-ring: sN and -k (k available neighbours) from the motion lanes, the residual
  // statistics and their count from the absResidual lanes. Lanes add in int32 in runs of at
  // most kRun terms, each run then widened: |motion|, |residual| <= 2^21, |m_a + m_b - m_o|
  // <= 3 * 2^21, so a run cannot overflow, and a ring of any size sums exactly.
  constexpr uint32_t kRun = 256;
  Wide4 motionSum{0, 0, 0, 0}, residualSum{0, 0, 0, 0};
  for (uint32_t i = rings.neighbourStart[v], end = rings.neighbourStart[v + 1]; i < end;
       i += kRun) {
    Lanes4 m{0, 0, 0, 0}, a{0, 0, 0, 0};
    const uint32_t runEnd = end - i > kRun ? i + kRun : end;
    for (uint32_t j = i; j < runEnd; ++j) {
      const MotionRecord& u = records[rings.neighbours[j]];
      m += u.motion;
      if constexpr (kResiduals) a += u.absResidual;
    }
    motionSum += __builtin_convertvector(m, Wide4);
    if constexpr (kResiduals) residualSum += __builtin_convertvector(a, Wide4);
  }
  if constexpr (kResiduals)
    for (int c = 0; c < 4; ++c)
      residuals->sums[c] = residualSum[c];
  const int64_t k = -motionSum[3];
  if (k == 0) return fallback;
  // Wings (a, b, o) with all three available: sP = sum of m_a + m_b - m_o, and -kp in lane 3
  // (-1 - 1 + 1).
  int64_t p[4] = {};
  for (uint32_t i = rings.wingStart[v], end = rings.wingStart[v + 1]; i < end; i += kRun) {
    Lanes4 run{0, 0, 0, 0};
    const uint32_t runEnd = end - i > kRun ? i + kRun : end;
    for (uint32_t j = i; j < runEnd; ++j) {
      const Lanes4 a = records[rings.wings[j][0]].motion, b = records[rings.wings[j][1]].motion,
                   o = records[rings.wings[j][2]].motion;
      const Lanes4 all = a & b & o;
      run += (a + b - o) & Lanes4{all[3], all[3], all[3], all[3]};
    }
    for (int c = 0; c < 4; ++c)
      p[c] += run[c];
  }
  const int64_t kp = -p[3];
  Vec3i prediction;
  for (int c = 0; c < 3; ++c) {
    const int64_t sN = motionSum[c], sP = p[c];
    prediction[c] =
        static_cast<int32_t>(kp == 0 ? roundDiv(sN, k) : roundDiv(kp * sN + k * sP, 2 * k * kp));
  }
  return prediction;
}

}  // namespace detail

// The motion predictor, the only one: encoder and decoder (codePMesh, pmesh_syntax.h) and the
// encoder's rate estimate (pmesh_encoder.cpp) all call it. The prediction of vertex v from the
// motions already final (records whose "available" lane is set):
//   k  available 1-ring neighbours, sN = sum of their motions;
//   kp wings (a, b, o) with a, b, o all available, sP = sum of (m_a + m_b - m_o);
//   k == 0          -> fallback
//   kp == 0         -> roundDiv(sN, k)                   (mean of neighbours)
//   otherwise       -> roundDiv(kp * sN + k * sP, 2 k kp) (average of the mean of neighbours and
//                                                          the mean parallelogram prediction)
// `rings` and `records` are in the same space (vertex indices or breadth-first ranks).
inline Vec3i predictMotion(const RingView rings, const MotionRecord* records, uint32_t v,
                           const Vec3i& fallback) {
  return detail::predictMotion<false>(rings, records, v, fallback, nullptr);
}

// The same, summing the ring's residual statistics (`residuals`) in the same neighbour loop.
inline Vec3i predictMotion(const RingView rings, const MotionRecord* records, uint32_t v,
                           const Vec3i& fallback, RingResiduals& residuals) {
  return detail::predictMotion<true>(rings, records, v, fallback, &residuals);
}

// Convenience form (tests, single vertices): records made from `motion` (in vertex order) and
// `available` (nonzero: final), then the predictor above. O(vertex count) per call.
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

// The same octree as one sorted array, for coding where only the cells matter, not the order
// of vertices inside a cell: the vertices sorted by their Morton key (the octant numbers of
// depths 0, 1, ... as base-8 digits, depth 0 most significant). Every cell at every depth is
// then a contiguous range whose octants follow each other in increasing order, so a split is a
// few binary searches instead of a pass over the cell. Buffers are kept between build() calls.
class MortonOctree {
 public:
  // Sorts vertex indices 0 .. positions.size() - 1 by Morton key (LSD radix sort, stable: equal
  // positions stay in index order). As in OctreePartition, only the low gridBits bits of each
  // coordinate count (grid positions lie in [0, 2^gridBits)). gridBits <= 20 (else throws
  // std::invalid_argument), as for any 3DVO grid.
  // On grids of more than 4 bits the sort leaves out the digits of the 4 to 7 deepest levels
  // (sortItems says how many), which few cells reach: split() sorts a cell of the first such
  // depth by them when it splits it.
  void build(const std::vector<Vec3i>& positions, int gridBits);
  // The sorted vertex indices; a cell is a range [begin, end) of this array.
  uint32_t* vertices() { return vertices_.data(); }
  uint32_t size() const { return static_cast<uint32_t>(vertices_.size()); }
  // The octant ranges of cell [begin, end) at `depth`: octant o is [bounds[o], bounds[o+1]),
  // absolute indices into vertices(); the cell must be one of this octree's cells at `depth`,
  // reached by splitting its ancestors from the root down (as a traversal does).
  void split(uint32_t begin, uint32_t end, int depth, std::array<uint32_t, 9>& bounds);

 private:
  __extension__ using Wide = unsigned __int128;
  // The sort moves one integer per vertex, (key << indexBits_) | vertex index: sorting these
  // sorts by key and, among equal keys, by index. 64 bits hold them when 3 * gridBits +
  // indexBits_ <= 64 (e.g. a 12-bit grid with up to 2^28 vertices), 128 bits otherwise.
  template <class Item>
  void sortItems(const std::vector<Vec3i>& positions, std::vector<Item>& items,
                 std::vector<Item>& scratch);
  template <class Item>
  void splitItems(std::vector<Item>& items, uint32_t begin, uint32_t end, int depth,
                  std::array<uint32_t, 9>& bounds);

  int gridBits_ = 0;
  int indexBits_ = 0;
  int unsortedDepth_ = 0;  // the first depth whose octant digit build() left unsorted
  bool wide_ = false;      // the items are wideItems_
  std::vector<uint64_t> items_, itemScratch_;
  std::vector<Wide> wideItems_, wideScratch_;
  std::vector<uint32_t> vertices_, counts_;
};

// prev + motion, clamped into the grid [0, 2^gridBits - 1] per coordinate.
inline Vec3i applyMotion(const Vec3i& previous, const Vec3i& motion, int gridBits) {
  const int64_t maxCoordinate = (int64_t{1} << gridBits) - 1;
  Vec3i out;
  for (int c = 0; c < 3; ++c)
    out[c] = static_cast<int32_t>(
        std::clamp<int64_t>(int64_t{previous[c]} + motion[c], 0, maxCoordinate));
  return out;
}

}  // namespace tdvo
