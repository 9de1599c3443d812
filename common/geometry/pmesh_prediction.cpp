#include "common/geometry/pmesh_prediction.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "common/core/error.h"

namespace tdvo {

namespace {

// Counting sort of (key, value) pairs into CSR form: start[k] .. start[k+1] holds the values of
// key k in the order they were given. `emit(add)` must call add(key, value) for every pair, and
// is called twice (count, then fill), so it must emit the same pairs both times.
template <class Value, class Emit>
void buildCsr(uint32_t numKeys, std::vector<uint32_t>& start, std::vector<Value>& values,
              Emit emit) {
  start.assign(numKeys + 1, 0);
  emit([&](uint32_t key, const Value&) { ++start[key + 1]; });
  for (uint32_t k = 0; k < numKeys; ++k)
    start[k + 1] += start[k];
  values.resize(start[numKeys]);
  std::vector<uint32_t> fill(start.begin(), start.end() - 1);
  emit([&](uint32_t key, const Value& value) { values[fill[key]++] = value; });
}

}  // namespace

// Everything is built with counting sorts into flat arrays (no hashing, no vector per vertex):
// this runs once per GOM on the decoder's path.
GomTopology GomTopology::build(const IntMesh& iMesh) {
  GomTopology t;
  const uint32_t n = static_cast<uint32_t>(iMesh.positions.size());
  const std::vector<Triangle>& tris = iMesh.triangles;
  t.numVertices = n;

  // 1-rings: both other corners of every corner, then each ring sorted and deduplicated.
  std::vector<uint32_t> rawStart, raw;
  buildCsr<uint32_t>(n, rawStart, raw, [&](auto add) {
    for (const Triangle& tri : tris)
      for (int k = 0; k < 3; ++k) {
        add(tri[k], tri[(k + 1) % 3]);
        add(tri[k], tri[(k + 2) % 3]);
      }
  });
  t.neighbourStart.assign(n + 1, 0);
  t.neighbours.reserve(raw.size());
  for (uint32_t v = 0; v < n; ++v) {
    const auto first = raw.begin() + rawStart[v], last = raw.begin() + rawStart[v + 1];
    std::sort(first, last);
    t.neighbours.insert(t.neighbours.end(), first, std::unique(first, last));
    t.neighbourStart[v + 1] = static_cast<uint32_t>(t.neighbours.size());
  }
  t.neighbours.shrink_to_fit();

  // Undirected edges are numbered by their place in the lower endpoint's ring, so edge (a, b)
  // is neighbours index of max(a, b) in the ring of min(a, b).
  auto edgeId = [&t](uint32_t a, uint32_t b) {
    if (a > b) std::swap(a, b);
    const auto first = t.neighbours.begin() + t.neighbourStart[a];
    const auto last = t.neighbours.begin() + t.neighbourStart[a + 1];
    return static_cast<uint32_t>(std::lower_bound(first, last, b) - t.neighbours.begin());
  };
  // The corners opposite each edge, in triangle order: corner k of triangle i faces the edge
  // between its two other corners.
  const uint32_t numEdgeSlots = static_cast<uint32_t>(t.neighbours.size());
  std::vector<uint32_t> cornerEdge(tris.size() * 3);
  for (size_t i = 0; i < tris.size(); ++i)
    for (int k = 0; k < 3; ++k)
      cornerEdge[3 * i + k] = edgeId(tris[i][(k + 1) % 3], tris[i][(k + 2) % 3]);
  std::vector<uint32_t> oppositeStart, opposite;
  buildCsr<uint32_t>(numEdgeSlots, oppositeStart, opposite, [&](auto add) {
    for (size_t i = 0; i < tris.size(); ++i)
      for (int k = 0; k < 3; ++k)
        add(cornerEdge[3 * i + k], tris[i][k]);
  });

  // k triangles on one edge give k (k - 1) wings: a corrupt I mesh with thousands of triangles
  // on one edge would ask for gigabytes and quadratic time. Bounded first, in linear time: the
  // pairs of distinct corners facing the same edge may be at most three per triangle, as in any
  // mesh whose edges have at most two triangles (Draco's Edgebreaker decodes only such meshes).
  uint64_t cornerPairs = 0;
  for (const uint32_t e : cornerEdge)
    cornerPairs += oppositeStart[e + 1] - oppositeStart[e] - 1;
  check(cornerPairs <= 3 * uint64_t{tris.size()},
        "I mesh: " + std::to_string(cornerPairs) + " pairs of triangles on shared edges, more " +
            "than three per triangle (" + std::to_string(tris.size()) +
            " triangles; docs/bitstream.md, section 5.4)");

  // Wings: for each corner (v, a, b), in triangle order, every other corner facing edge a-b.
  buildCsr<std::array<uint32_t, 3>>(n, t.wingStart, t.wings, [&](auto add) {
    for (size_t i = 0; i < tris.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = tris[i][k], a = tris[i][(k + 1) % 3], b = tris[i][(k + 2) % 3];
        const uint32_t e = cornerEdge[3 * i + k];
        for (uint32_t j = oppositeStart[e]; j < oppositeStart[e + 1]; ++j)
          if (opposite[j] != v) add(v, std::array<uint32_t, 3>{a, b, opposite[j]});
      }
  });

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

  // Rank space.
  t.rank.resize(n);
  for (uint32_t r = 0; r < n; ++r)
    t.rank[t.order[r]] = r;
  t.rankNeighbourStart.resize(n + 1);
  t.rankNeighbours.resize(t.neighbours.size());
  t.rankWingStart.resize(n + 1);
  t.rankWings.resize(t.wings.size());
  t.rankNeighbourStart[0] = t.rankWingStart[0] = 0;
  for (uint32_t r = 0; r < n; ++r) {
    const uint32_t v = t.order[r];
    uint32_t at = t.rankNeighbourStart[r];
    for (uint32_t i = t.neighbourStart[v]; i < t.neighbourStart[v + 1]; ++i)
      t.rankNeighbours[at++] = t.rank[t.neighbours[i]];
    t.rankNeighbourStart[r + 1] = at;
    at = t.rankWingStart[r];
    for (uint32_t i = t.wingStart[v]; i < t.wingStart[v + 1]; ++i)
      t.rankWings[at++] = {t.rank[t.wings[i][0]], t.rank[t.wings[i][1]], t.rank[t.wings[i][2]]};
    t.rankWingStart[r + 1] = at;
  }
  return t;
}

Vec3i predictMotion(const GomTopology& topology, uint32_t v, const std::vector<Vec3i>& motion,
                    const std::vector<uint8_t>& available, const Vec3i& fallback) {
  std::vector<MotionRecord> records(topology.numVertices);
  for (uint32_t u = 0; u < topology.numVertices; ++u)
    if (available[u])
      records[u].motion = Lanes4{motion[u][0], motion[u][1], motion[u][2], -1};
    else
      records[u].motion = Lanes4{0, 0, 0, 0};
  return predictMotion(topology.vertexRings(), records.data(), v, fallback);
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

namespace {

// kSpread8[b]: bit i of the byte b moved to bit 3i.
struct Spread8 {
  uint32_t table[256];
  constexpr Spread8() : table() {
    for (uint32_t b = 0; b < 256; ++b)
      for (int i = 0; i < 8; ++i)
        table[b] |= ((b >> i) & 1u) << (3 * i);
  }
};
constexpr Spread8 kSpread8;

// Bit i of x moved to bit 3i, for x < 2^16 and x < 2^24.
inline uint64_t spreadBits3Of16(uint32_t x) {
  return uint64_t{kSpread8.table[x & 255]} | uint64_t{kSpread8.table[(x >> 8) & 255]} << 24;
}
inline uint64_t spreadBits3Of24(uint32_t x) {
  return spreadBits3Of16(x) | uint64_t{kSpread8.table[(x >> 16) & 255]} << 48;
}

}  // namespace

void MortonOctree::build(const std::vector<Vec3i>& positions, int gridBits) {
  if (gridBits < 0 || gridBits > 20)
    throw std::invalid_argument("MortonOctree: gridBits out of [0, 20]");
  gridBits_ = gridBits;
  const size_t n = positions.size();
  indexBits_ = 0;
  while (indexBits_ < 64 && (uint64_t{1} << indexBits_) < n)
    ++indexBits_;
  wide_ = 3 * gridBits + indexBits_ > 64;
  if (wide_) {
    sortItems(positions, wideItems_, wideScratch_);
  } else {
    sortItems(positions, items_, itemScratch_);
  }
}

template <class Item>
void MortonOctree::sortItems(const std::vector<Vec3i>& positions, std::vector<Item>& items,
                             std::vector<Item>& scratch) {
  const size_t n = positions.size();
  items.resize(n);
  scratch.resize(n);
  vertices_.resize(n);
  const int indexBits = indexBits_;
  // LSD radix sort of the keys, 12 bits per pass (at most 4 for 20-bit grids); the histograms
  // of all passes are counted while the keys are made. A pass over a digit that every key
  // shares is skipped. On grids of more than 4 bits the lowest bits, of the deepest levels
  // that few cells reach, are left to split(): 3 * gridBits - 12 * passes of them, 12 to 21
  // (4 to 7 levels; as many as leave whole 12-bit digits above them, so that a 13-bit grid
  // takes two passes, not three).
  constexpr int kDigitBits = 12;
  constexpr uint32_t kBuckets = 1u << kDigitBits;
  constexpr uint64_t kDigit = kBuckets - 1;
  const int keyBits = 3 * gridBits_;
  const int passes = keyBits <= kDigitBits ? 1 : std::max(1, (keyBits - kDigitBits) / kDigitBits);
  const int unsortedBits = keyBits <= kDigitBits ? 0 : keyBits - passes * kDigitBits;
  unsortedDepth_ = gridBits_ - unsortedBits / 3;
  counts_.assign(size_t(passes) * kBuckets, 0u);
  uint32_t* const counts = counts_.data();
  Item* from = items.data();
  Item* to = scratch.data();
  // Bit 3i + 2 of a key is bit i of x, 3i + 1 of y, 3i of z: the octant digit of depth d sits at
  // bit 3 * (gridBits - 1 - d). Only the low gridBits bits of a coordinate choose octants (as in
  // OctreePartition).
  const uint32_t mask = (uint32_t{1} << gridBits_) - 1;
  auto makeKeys = [&](auto spread) {
    for (size_t v = 0; v < n; ++v) {
      const Vec3i& p = positions[v];
      const uint64_t key = spread(uint32_t(p[0]) & mask) << 2 | spread(uint32_t(p[1]) & mask) << 1 |
                           spread(uint32_t(p[2]) & mask);
      from[v] = Item{key} << indexBits | v;
      // Unrolled: a loop over the passes costs more than the counting.
      const uint64_t sorted = key >> unsortedBits;
      ++counts[sorted & kDigit];
      if (passes > 1) ++counts[kBuckets + (sorted >> kDigitBits & kDigit)];
      if (passes > 2) ++counts[2 * kBuckets + (sorted >> (2 * kDigitBits) & kDigit)];
      if (passes > 3) ++counts[3 * kBuckets + (sorted >> (3 * kDigitBits) & kDigit)];
    }
  };
  if (gridBits_ <= 16) {
    makeKeys(spreadBits3Of16);
  } else {
    makeKeys(spreadBits3Of24);
  }
  for (int pass = 0; pass < passes; ++pass) {
    const int shift = indexBits + unsortedBits + pass * kDigitBits;
    uint32_t* const count = counts + size_t(pass) * kBuckets;
    if (n == 0 || count[uint32_t(from[0] >> shift) & (kBuckets - 1)] == n) continue;
    uint32_t sum = 0;
    for (uint32_t b = 0; b < kBuckets; ++b) {
      const uint32_t c = count[b];
      count[b] = sum;
      sum += c;
    }
    for (size_t i = 0; i < n; ++i)
      to[count[uint32_t(from[i] >> shift) & (kBuckets - 1)]++] = from[i];
    std::swap(from, to);
  }
  if (from != items.data()) items.swap(scratch);  // the sorted items are in items
  const Item indexMask = (Item{1} << indexBits) - 1;
  uint32_t* const vertices = vertices_.data();
  for (size_t i = 0; i < n; ++i)
    vertices[i] = uint32_t(from[i] & indexMask);
}

void MortonOctree::split(uint32_t begin, uint32_t end, int depth, std::array<uint32_t, 9>& bounds) {
  if (wide_) {
    splitItems(wideItems_, begin, end, depth, bounds);
  } else {
    splitItems(items_, begin, end, depth, bounds);
  }
}

template <class Item>
void MortonOctree::splitItems(std::vector<Item>& items, uint32_t begin, uint32_t end, int depth,
                              std::array<uint32_t, 9>& bounds) {
  if (depth == unsortedDepth_) {
    // The first split at this depth: sort the cell by the digits build() left out (the whole
    // item, as all its other key bits are equal), and every cell inside it is a range again.
    std::sort(items.begin() + begin, items.begin() + end);
    const Item indexMask = (Item{1} << indexBits_) - 1;
    for (uint32_t i = begin; i < end; ++i)
      vertices_[i] = uint32_t(items[i] & indexMask);
  }
  const int shift = indexBits_ + 3 * (gridBits_ - 1 - depth);
  const Item* const sorted = items.data();
  auto octant = [&](uint32_t i) { return uint32_t(sorted[i] >> shift) & 7u; };
  bounds[0] = begin;
  bounds[8] = end;
  // The octant digits of a cell are sorted; everything here is branch-free, as the data decides
  // where the octants end.
  if (end - begin <= 255) {
    // Small cells (nearly all): count the octants in eight byte counters of one word; a
    // multiplication by 0x0101... makes byte o the number of vertices in octants 0 .. o.
    uint64_t counts = 0;
    for (uint32_t i = begin; i < end; ++i)
      counts += uint64_t{1} << (8 * octant(i));
    const uint64_t below = counts * 0x0101010101010101u;
    for (int o = 0; o < 7; ++o)
      bounds[o + 1] = begin + uint32_t((below >> (8 * o)) & 0xFF);
    return;
  }
  // Large cells: for each octant o < 7, the first vertex whose digit exceeds o, by a binary
  // search whose steps depend only on the length.
  uint32_t at = begin;
  for (uint32_t o = 0; o < 7; ++o) {
    uint32_t first = at, length = end - at;
    while (length > 0) {
      const uint32_t half = length / 2;
      const bool below = octant(first + half) <= o;
      first = below ? first + half + 1 : first;
      length = below ? length - half - 1 : half;
    }
    at = first;
    bounds[o + 1] = at;
  }
}

}  // namespace tdvo
