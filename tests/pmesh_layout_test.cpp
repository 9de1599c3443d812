// The data layouts that make P-mesh coding fast (issue 10) against straightforward references:
// the GOM topology built with counting sorts against a brute-force construction, its
// breadth-first rank space against its vertex space, the Morton-sorted octree against
// OctreePartition's recursive splits, and decoding a GOM's P meshes without allocating.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdlib>
#include <map>
#include <new>
#include <random>
#include <vector>

#include "common/core/grid.h"
#include "common/geometry/pmesh_prediction.h"
#include "decoder/pmesh_decoder.h"
#include "encoder/imesh_encoder.h"
#include "encoder/pmesh_encoder.h"
#include "tools/eval/sample_mesh.h"

// Counts heap allocations of this test program (for DecodingAGomAllocatesOnlyOnItsFirstFrame).
// Not inlined: g++ -O2 with sanitizers inlines them into gtest's `new TestClass` and then warns
// that malloc'ed memory is freed by a mismatched delete (-Wmismatched-new-delete).
namespace {
std::atomic<long> gAllocations{0};
}
__attribute__((noinline)) void* operator new(std::size_t size) {
  ++gAllocations;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
__attribute__((noinline)) void operator delete(void* p) noexcept {
  std::free(p);
}
__attribute__((noinline)) void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
// The nothrow forms too (std::stable_sort's temporary buffer uses them): otherwise memory from
// the library's (or a sanitizer's) nothrow new would reach the free() above.
__attribute__((noinline)) void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  ++gAllocations;
  return std::malloc(size ? size : 1);
}
__attribute__((noinline)) void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}

namespace tdvo {
namespace {

// A mesh with what real data has besides a clean manifold: a non-manifold edge (three
// triangles on edge 0-1), a vertex used by no triangle (7) and a second component.
IntMesh awkwardMesh() {
  IntMesh m;
  for (int i = 0; i < 11; ++i)
    m.positions.push_back({i, 2 * i, 3 * i});
  m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4},  {2, 1, 5},
                 {5, 1, 3}, {2, 5, 6}, {8, 9, 10}, {10, 9, 6}};
  return m;
}

// Rings and wings straight from their definitions (pmesh_prediction.h), by brute force.
void referenceTopology(const IntMesh& m, std::vector<std::vector<uint32_t>>& rings,
                       std::vector<std::vector<std::array<uint32_t, 3>>>& wings) {
  const size_t n = m.positions.size();
  rings.assign(n, {});
  wings.assign(n, {});
  for (const Triangle& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      rings[t[k]].push_back(t[(k + 1) % 3]);
      rings[t[k]].push_back(t[(k + 2) % 3]);
    }
  for (auto& r : rings) {
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
  }
  // For each corner (v, a, b), in triangle order: every corner of any triangle (in triangle
  // order) facing the same undirected edge a-b whose vertex is not v.
  for (const Triangle& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = t[k], a = t[(k + 1) % 3], b = t[(k + 2) % 3];
      for (const Triangle& u : m.triangles)
        for (int j = 0; j < 3; ++j) {
          const uint32_t x = u[(j + 1) % 3], y = u[(j + 2) % 3];
          if (((x == a && y == b) || (x == b && y == a)) && u[j] != v)
            wings[v].push_back({a, b, u[j]});
        }
    }
}

void expectMatchesReference(const IntMesh& m) {
  const GomTopology t = GomTopology::build(m);
  std::vector<std::vector<uint32_t>> rings;
  std::vector<std::vector<std::array<uint32_t, 3>>> wings;
  referenceTopology(m, rings, wings);
  ASSERT_EQ(t.numVertices, m.positions.size());
  for (uint32_t v = 0; v < t.numVertices; ++v) {
    EXPECT_EQ(std::vector<uint32_t>(t.neighbours.begin() + t.neighbourStart[v],
                                    t.neighbours.begin() + t.neighbourStart[v + 1]),
              rings[v])
        << "ring of " << v;
    const std::vector<std::array<uint32_t, 3>> w(t.wings.begin() + t.wingStart[v],
                                                 t.wings.begin() + t.wingStart[v + 1]);
    EXPECT_EQ(w, wings[v]) << "wings of " << v;
  }
  // Rank space is vertex space renamed by breadth-first rank.
  ASSERT_EQ(t.order.size(), t.numVertices);
  for (uint32_t r = 0; r < t.numVertices; ++r) {
    const uint32_t v = t.order[r];
    ASSERT_EQ(t.rank[v], r);
    std::vector<uint32_t> ring;
    for (uint32_t i = t.rankNeighbourStart[r]; i < t.rankNeighbourStart[r + 1]; ++i)
      ring.push_back(t.order[t.rankNeighbours[i]]);
    EXPECT_EQ(ring, rings[v]);
    std::vector<std::array<uint32_t, 3>> w;
    for (uint32_t i = t.rankWingStart[r]; i < t.rankWingStart[r + 1]; ++i)
      w.push_back(
          {t.order[t.rankWings[i][0]], t.order[t.rankWings[i][1]], t.order[t.rankWings[i][2]]});
    EXPECT_EQ(w, wings[v]);
  }
}

TEST(GomTopologyLayout, MatchesTheDefinitionsOnAnAwkwardMesh) {
  expectMatchesReference(awkwardMesh());
}

TEST(GomTopologyLayout, MatchesTheDefinitionsOnAnIcosphere) {
  const Mesh sphere = icosphere(2);
  expectMatchesReference(Grid::fromBounds({-1, -1, -1}, {1, 1, 1}, 10).quantise(sphere));
}

// Every cell of the octree, at every depth, holds the same vertices whether it comes from
// OctreePartition's recursive splits or from the Morton-sorted array; octants come in order.
TEST(MortonOctree, HasTheCellsOfOctreePartition) {
  std::mt19937 rng(7);
  // Grids whose sort leaves 0, 3, 12, 15, 18 and 21 low key bits to split().
  for (int gridBits : {3, 5, 8, 12, 13, 14, 15, 20}) {
    std::uniform_int_distribution<int32_t> coordinate(0, (1 << gridBits) - 1);
    std::vector<Vec3i> positions(500);
    for (Vec3i& p : positions)
      p = {coordinate(rng), coordinate(rng), coordinate(rng)};
    for (int i = 0; i < 50; ++i)  // coincident and nearly coincident vertices
      positions.push_back(positions[static_cast<size_t>(i) * 3]);
    MortonOctree morton;
    morton.build(positions, gridBits);
    std::vector<uint32_t> cells(positions.size()), scratch;
    for (uint32_t v = 0; v < cells.size(); ++v)
      cells[v] = v;
    size_t compared = 0;
    auto visit = [&](auto& self, uint32_t begin, uint32_t end, int depth) -> void {
      std::vector<uint32_t> a(cells.begin() + begin, cells.begin() + end);
      std::vector<uint32_t> b(morton.vertices() + begin, morton.vertices() + end);
      std::sort(a.begin(), a.end());
      std::sort(b.begin(), b.end());
      ASSERT_EQ(a, b) << "cell [" << begin << ", " << end << ") at depth " << depth;
      ++compared;
      if (depth == gridBits || end - begin < 2) return;
      std::array<uint32_t, 9> pb, mb;
      OctreePartition::split(positions, cells.data() + begin, cells.data() + end, gridBits, depth,
                             pb, scratch);
      morton.split(begin, end, depth, mb);
      for (int o = 0; o < 9; ++o)
        ASSERT_EQ(begin + pb[o], mb[o]) << "octant bound " << o << " at depth " << depth;
      for (int o = 0; o < 8; ++o)
        if (mb[o + 1] > mb[o]) self(self, mb[o], mb[o + 1], depth + 1);
    };
    visit(visit, 0, static_cast<uint32_t>(positions.size()), 0);
    EXPECT_GT(compared, size_t{64}) << "gridBits " << gridBits;
  }
}

// Decoding the P meshes of a GOM with one workspace: after the first frame, no allocation.
TEST(PMeshDecoding, DecodingAGomAllocatesOnlyOnItsFirstFrame) {
  const std::vector<Mesh> blob = deformingBlob(3, 6);
  const Grid grid = Grid::fromBounds({-2, -2, -2}, {2, 2, 2}, 12);
  const IMeshEncoding i = encodeIMesh(grid.quantise(blob[0]), 12, 0);
  const GomTopology topology = GomTopology::build(i.decoded);
  PMeshParams params;
  params.gridBits = 12;
  params.maxDepth = 12;
  std::vector<std::vector<uint8_t>> payloads;
  std::vector<Vec3i> previous = i.decoded.positions;
  for (size_t f = 1; f < blob.size(); ++f) {
    const IntMesh q = grid.quantise(blob[f]);
    std::vector<Vec3i> target(i.inputIndex.size());
    for (size_t j = 0; j < target.size(); ++j)
      target[j] = q.positions[i.inputIndex[j]];
    PMeshEncoding e = encodePMesh(topology, previous, target, params, 0);
    payloads.push_back(std::move(e.payload));
    previous = std::move(e.reconstruction);
  }
  const std::string context = "test";  // short: the reader's copy needs no heap
  PMeshWorkspace work;
  std::vector<Vec3i> a = i.decoded.positions, b;
  for (size_t f = 0; f < payloads.size(); ++f) {
    const long before = gAllocations.load();
    decodePMesh(payloads[f].data(), payloads[f].size(), topology, a, params, context, work, b);
    if (f > 0) {
      EXPECT_EQ(gAllocations.load() - before, 0) << "frame " << f + 1;
    }
    a.swap(b);
  }
  EXPECT_EQ(a, previous);  // and it decodes what the encoder reconstructed
}

}  // namespace
}  // namespace tdvo
