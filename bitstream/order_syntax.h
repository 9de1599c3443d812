// The output order of an I mesh (VERTEX_ORDER unit, docs/bitstream.md "Output order"), written
// once for encoder and decoder.
//
// Draco's Edgebreaker coder reorders vertices and triangles. The decoder works in Draco's order
// (the "coding order": P meshes refer to it) and outputs every frame in the input's order: the
// VERTEX_ORDER payload that follows each I mesh of a random access point says, for every decoded
// vertex, its output index, and lists the output triangles in the input's order and corner
// rotation. Its CABAC payload has two parts:
//
// Vertices, in coding order j = 0 .. n-1: vo_vertex_delta, the output index minus a prediction:
// the output index of the latest earlier neighbour of j (the largest i < j sharing a triangle
// with j), else that of vertex j - 1, else 0. Output indices are < m = vo_num_vertices (<= n)
// and each is given at least once: n - m vertices repeat an index taken before (the copies
// Draco makes of a non-manifold vertex; the output takes the first copy's position).
// Triangles, in output order i = 0 .. T-1: vo_corner_delta, the output triangle's first vertex
// minus the previous output triangle's first vertex (0 before the first), then vo_corner_choice,
// which of the corners at that vertex whose triangle is not yet output it is (the corners listed
// by the output index of the next vertex, then of the third, then by triangle; not coded when
// there is one): the triangle is output with that corner first. Every decoded triangle is so
// output once, in the orientation Draco decoded.
//
// Degenerate triangles (a repeated vertex: Draco cannot code them), last: vo_num_degenerate
// (<= the I mesh's triangle count), then for each k = 0 .. D-1, with vo_triangle_order 1,
// vo_degenerate_gap, its position p_k in the output list (T + D triangles) minus p_(k-1) + 1
// (p_-1 = -1; p_k <= T + k), and, in either case, vo_degenerate_vertex three times: the first
// output vertex minus the first vertex of the triangle before it in the output list (0 at
// position 0), then the second and the third minus the first. With vo_triangle_order 0 the
// degenerate triangles follow the others (p_k = T + k, not coded).
//
// Binarisation of an unsigned value v <= max: the class c (v + 1 in [2^c, 2^(c+1))) in unary,
// each bin with its own context (the terminating 0 omitted at the largest class max allows),
// then the c low bits of v + 1, most significant first (context per class for the first, one
// shared context for the rest). A signed value: a nonzero flag, a sign bin, then |v| - 1 as
// above. The context sets of vo_vertex_delta and vo_corner_delta are chosen by the magnitude of
// the previous value of the same element (<= 1, <= 32, more); those of vo_corner_choice by the
// number of candidates (2, 3, 4, more).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "bitstream/cabac_io.h"
#include "common/core/mesh.h"

namespace tdvo {

struct MeshOrder {
  uint32_t numVertices = 0;            // output vertices (vo_num_vertices)
  std::vector<uint32_t> vertexOutput;  // coding-order vertex -> output index, onto [0, numVertices)
  std::vector<Triangle> triangles;     // the output triangle list, in output vertex indices
  std::vector<uint32_t> degenerate;    // ascending positions in `triangles` of the triangles the
                                       // I mesh does not have (repeated vertex: Draco drops them)
};

struct OrderContexts {
  static constexpr int kPrefixCtx = 12;
  struct Set {
    ContextModel nonzero, sign, prefix[kPrefixCtx], top[33], rest;
  };
  Set vertex[3];
  Set corner[3];
  ContextModel reuse[3][3];
  Set choice[4];
  Set degenerate[4];  // vo_num_degenerate, vo_degenerate_gap, vo_degenerate_vertex (first, rest)
  static int deltaClass(int64_t delta) {
    const int64_t a = delta < 0 ? -delta : delta;
    return int(a > 1) + int(a > 32);
  }
};

namespace order_detail {

inline int classOf(uint64_t valuePlusOne) {
  int c = 0;
  while (valuePlusOne >> (c + 1))
    ++c;
  return c;
}

template <class Io>
void codeUnsigned(Io& io, const char* name, OrderContexts::Set& s, uint32_t& value,
                  uint32_t maxValue) {
  if (!Io::kReading) io.require(value <= maxValue, std::string(name) + " out of range");
  const int maxClass = classOf(uint64_t{maxValue} + 1);
  int c = Io::kReading ? 0 : classOf(uint64_t{value} + 1);
  for (int i = 0; i < maxClass; ++i) {
    unsigned more = i < c;
    io.bin(name, s.prefix[std::min(i, OrderContexts::kPrefixCtx - 1)], more);
    if (!more) break;
    if (Io::kReading) c = i + 1;
  }
  uint64_t v = Io::kReading ? 1 : uint64_t{value} + 1;
  for (int b = c - 1; b >= 0; --b) {
    unsigned bit = Io::kReading ? 0 : unsigned(v >> b) & 1u;
    io.bin(name, b == c - 1 ? s.top[c] : s.rest, bit);
    if (Io::kReading) v = v << 1 | bit;
  }
  if (Io::kReading) {
    io.require(v - 1 <= maxValue, std::string(name) + " = " + std::to_string(v - 1) +
                                      " out of range [0, " + std::to_string(maxValue) + "]");
    value = static_cast<uint32_t>(v - 1);
  }
}

template <class Io>
void codeSigned(Io& io, const char* name, OrderContexts::Set& s, int64_t& value, uint32_t maxAbs) {
  unsigned nonzero = value != 0;
  io.bin(name, s.nonzero, nonzero);
  if (!nonzero) {
    value = 0;
    return;
  }
  io.require(maxAbs > 0, std::string(name) + " must be 0 here");
  unsigned negative = value < 0;
  io.bin(name, s.sign, negative);
  uint32_t magnitude = Io::kReading ? 0 : static_cast<uint32_t>((value < 0 ? -value : value) - 1);
  codeUnsigned(io, name, s, magnitude, maxAbs - 1);
  value = negative ? -(int64_t{magnitude} + 1) : int64_t{magnitude} + 1;
}

// Counts of the corners not yet output, per vertex: a Fenwick tree over each vertex's sorted
// corner list, so that finding the k-th remaining corner costs O(log degree).
class CornerSets {
 public:
  void init(const std::vector<uint32_t>& start) {
    start_ = start;
    tree_.resize(start.back());
    for (size_t v = 0; v + 1 < start.size(); ++v)
      for (uint32_t i = 1; i <= start[v + 1] - start[v]; ++i)
        tree_[start[v] + i - 1] = i & (~i + 1);
    remaining_.resize(start.size() - 1);
    for (size_t v = 0; v + 1 < start.size(); ++v)
      remaining_[v] = start[v + 1] - start[v];
  }
  uint32_t remaining(uint32_t v) const { return remaining_[v]; }
  // Removes entry `i` (0-based in v's list).
  void remove(uint32_t v, uint32_t i) {
    const uint32_t size = start_[v + 1] - start_[v];
    for (uint32_t k = i + 1; k <= size; k += k & (~k + 1))
      --tree_[start_[v] + k - 1];
    --remaining_[v];
  }
  // Remaining entries before entry `i` of v's list.
  uint32_t rank(uint32_t v, uint32_t i) const {
    uint32_t sum = 0;
    for (uint32_t k = i; k > 0; k -= k & (~k + 1))
      sum += tree_[start_[v] + k - 1];
    return sum;
  }
  // The index of the k-th (0-based) remaining entry of v's list; k < remaining(v).
  uint32_t select(uint32_t v, uint32_t k) const {
    const uint32_t size = start_[v + 1] - start_[v];
    uint32_t pos = 0, step = 1;
    while (step * 2 <= size)
      step *= 2;
    for (; step > 0; step /= 2)
      if (pos + step <= size && tree_[start_[v] + pos + step - 1] <= k) {
        pos += step;
        k -= tree_[start_[v] + pos - 1];
      }
    return pos;
  }

 private:
  std::vector<uint32_t> start_, tree_, remaining_;
};

// The degenerate triangles of `order` (docs/bitstream.md "Output order"): order.triangles is
// the list without them (the I mesh's `numTriangles`), `degenerate` the ones set aside
// (writing) or decoded (reading); on return order.triangles is the merged list and
// order.degenerate their positions in it. With `coded` false their positions are not coded: they
// follow the others.
template <class Io>
void codeDegenerate(Io& io, uint32_t numTriangles, MeshOrder& order,
                    std::vector<Triangle>& degenerate, OrderContexts& ctx, bool coded) {
  const uint32_t m = order.numVertices;
  uint32_t count = static_cast<uint32_t>(degenerate.size());
  codeUnsigned(io, "vo_num_degenerate", ctx.degenerate[0], count, numTriangles);
  std::vector<uint32_t>& positions = order.degenerate;
  if (Io::kReading) {
    positions.assign(count, 0);
    degenerate.assign(count, Triangle{0, 0, 0});
  }
  if (!coded && !Io::kReading)
    for (uint32_t k = 0; k < count; ++k)
      io.require(positions[k] == numTriangles + k,
                 "degenerate triangles must follow the others in coding order");
  uint32_t next = 0;  // p_(k-1) + 1
  for (uint32_t k = 0; k < count; ++k) {
    if (coded) {
      uint32_t gap = Io::kReading ? 0 : positions[k] - next;
      codeUnsigned(io, "vo_degenerate_gap", ctx.degenerate[1], gap, numTriangles + k - next);
      positions[k] = next + gap;
    } else {
      positions[k] = numTriangles + k;
    }
    // The triangle before it in the output list: the previous degenerate one or a proper one.
    const uint32_t p = positions[k];
    const Triangle before = p == 0                               ? Triangle{0, 0, 0}
                            : k > 0 && positions[k - 1] == p - 1 ? degenerate[k - 1]
                            : p - 1 - k < order.triangles.size() ? order.triangles[p - 1 - k]
                                                                 : Triangle{0, 0, 0};
    Triangle& t = degenerate[k];
    for (int c = 0; c < 3; ++c) {
      const int64_t prediction = c == 0 ? int64_t{before[0]} : int64_t{t[0]};
      int64_t delta = Io::kReading ? 0 : int64_t{t[c]} - prediction;
      codeSigned(io, "vo_degenerate_vertex", ctx.degenerate[2 + (c > 0)], delta, m - 1);
      const int64_t v = prediction + delta;
      io.require(v >= 0 && v < m, "vo_degenerate_vertex gives output index " + std::to_string(v) +
                                      " for degenerate triangle " + std::to_string(k) +
                                      ", out of range [0, " + std::to_string(m - 1) + "]");
      t[c] = static_cast<uint32_t>(v);
    }
    next = p + 1;
  }
  if (count == 0) return;
  std::vector<Triangle> merged;
  merged.reserve(size_t{numTriangles} + count);
  uint32_t d = 0, q = 0;
  for (uint32_t i = 0; i < numTriangles + count; ++i)  // (the bounds hold unless writing junk)
    merged.push_back(d < count && positions[d] == i ? degenerate[d++]
                     : q < order.triangles.size()   ? order.triangles[q++]
                                                    : Triangle{0, 0, 0});
  order.triangles = std::move(merged);
}

}  // namespace order_detail

// Codes the output order of `decoded` (the I mesh in coding order). order.numVertices is given
// (vo_num_vertices). Writing, `order` must map the vertices onto [0, numVertices) and hold a
// triangle list that outputs every decoded triangle once, rotated only; reading fills it. Io is
// CabacWriterIo or CabacReaderIo; the Io's finish() is left to the caller. With `triangles` false
// only the vertices are coded and the output triangles are the decoded ones in coding order and
// rotation (in output vertex indices).
template <class Io>
void codeMeshOrder(Io& io, const IntMesh& decoded, MeshOrder& order, bool triangles = true) {
  using namespace order_detail;
  const uint32_t n = static_cast<uint32_t>(decoded.positions.size());
  const uint32_t numTriangles = static_cast<uint32_t>(decoded.triangles.size());
  if (Io::kReading) {
    order.vertexOutput.assign(n, 0);
    order.triangles.assign(numTriangles, Triangle{0, 0, 0});
  }
  // Writing, the degenerate triangles are set aside; both sides merge them back at the end.
  std::vector<Triangle> degenerate;
  if (!Io::kReading) {
    const std::vector<uint32_t>& positions = order.degenerate;
    io.require(positions.size() <= numTriangles &&
                   order.triangles.size() == numTriangles + positions.size() &&
                   std::is_sorted(positions.begin(), positions.end()) &&
                   std::adjacent_find(positions.begin(), positions.end()) == positions.end() &&
                   (positions.empty() || positions.back() < order.triangles.size()),
               "degenerate triangle positions and output list disagree");
    std::vector<uint8_t> isDegenerate(order.triangles.size(), 0);
    for (uint32_t p : positions) {
      if (p < order.triangles.size()) isDegenerate[p] = 1;
      degenerate.push_back(p < order.triangles.size() ? order.triangles[p] : Triangle{0, 0, 0});
    }
    std::vector<Triangle> proper;
    proper.reserve(numTriangles);
    for (size_t i = 0; i < order.triangles.size(); ++i)
      if (!isDegenerate[i]) proper.push_back(order.triangles[i]);
    order.triangles = std::move(proper);
  }
  io.require(order.vertexOutput.size() == n && order.triangles.size() == numTriangles,
             "output order and I mesh disagree");
  const uint32_t m = order.numVertices;
  io.require(m >= 1 && m <= n, "vo_num_vertices " + std::to_string(m) + " is not in [1, " +
                                   std::to_string(n) + "] (the I mesh's vertex count)");
  OrderContexts ctx;

  // Vertices.
  std::vector<uint32_t> latest(n, 0);  // 1 + the latest earlier neighbour, 0 if none
  for (const Triangle& t : decoded.triangles)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        if (t[a] < t[b]) latest[t[b]] = std::max(latest[t[b]], t[a] + 1);
  std::vector<uint8_t> placed(m, 0);
  uint32_t copies = 0;  // vertices given an output index already taken: at most n - m
  int cls = 0;
  for (uint32_t j = 0; j < n; ++j) {
    const int64_t prediction = latest[j] ? order.vertexOutput[latest[j] - 1]
                               : j > 0   ? order.vertexOutput[j - 1]
                                         : 0;
    int64_t delta = Io::kReading ? 0 : int64_t{order.vertexOutput[j]} - prediction;
    codeSigned(io, "vo_vertex_delta", ctx.vertex[cls], delta, m - 1);
    const int64_t out = prediction + delta;
    const bool inRange = out >= 0 && out < m;
    copies += inRange && placed[out];
    io.require(inRange && copies <= n - m,
               "vo_vertex_delta gives output index " + std::to_string(out) + " for vertex " +
                   std::to_string(j) + (inRange ? ", already taken" : ", out of range"));
    placed[out] = 1;
    order.vertexOutput[j] = static_cast<uint32_t>(out);
    cls = OrderContexts::deltaClass(delta);
  }

  const std::vector<uint32_t>& out = order.vertexOutput;
  if (!triangles) {
    for (uint32_t i = 0; i < numTriangles; ++i) {
      const Triangle& d = decoded.triangles[i];
      const Triangle t{out[d[0]], out[d[1]], out[d[2]]};
      if (!Io::kReading)
        io.require(order.triangles[i] == t, "the output triangles are not in coding order");
      order.triangles[i] = t;
    }
    codeDegenerate(io, numTriangles, order, degenerate, ctx, false);
    return;
  }

  // Triangles: the corners at every vertex, sorted as the choice lists them.
  std::vector<uint32_t> start(m + 1, 0);
  for (const Triangle& t : decoded.triangles)
    for (uint32_t v : t)
      ++start[out[v] + 1];
  for (uint32_t v = 0; v < m; ++v)
    start[v + 1] += start[v];
  std::vector<uint32_t> corners(start.back());  // 3 * triangle + corner
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (uint32_t t = 0; t < numTriangles; ++t)
      for (uint32_t k = 0; k < 3; ++k)
        corners[fill[out[decoded.triangles[t][k]]]++] = 3 * t + k;
  }
  auto key = [&](uint32_t corner) {
    const Triangle& t = decoded.triangles[corner / 3];
    const uint32_t k = corner % 3;
    return std::array<uint32_t, 3>{out[t[(k + 1) % 3]], out[t[(k + 2) % 3]], corner / 3};
  };
  std::vector<uint32_t> position(corners.size());  // corner -> index in its vertex's list
  for (uint32_t v = 0; v < m; ++v) {
    std::sort(corners.begin() + start[v], corners.begin() + start[v + 1],
              [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
    for (uint32_t i = start[v]; i < start[v + 1]; ++i)
      position[corners[i]] = i - start[v];
  }
  CornerSets remaining;
  remaining.init(start);

  Triangle previous{0, 0, 0};
  cls = 0;
  static constexpr int kReuse[3] = {0, 2, 1};  // vo_corner_reuse r: the previous triangle's
                                               // vertex kReuse[r]
  for (uint32_t i = 0; i < numTriangles; ++i) {
    Triangle& t = order.triangles[i];
    uint32_t reuse = 3;  // 3: none, a delta follows
    if (!Io::kReading)
      for (uint32_t r = 3; r-- > 0;)
        if (t[0] == previous[kReuse[r]]) reuse = r;
    for (uint32_t r = 0; r < 3; ++r) {
      unsigned bin = reuse == r;
      io.bin("vo_corner_reuse", ctx.reuse[cls][r], bin);
      if (bin) {
        reuse = r;
        break;
      }
      if (Io::kReading) reuse = 3;
    }
    int64_t first = previous[kReuse[reuse < 3 ? reuse : 0]];
    if (reuse == 3) {
      int64_t delta = Io::kReading ? 0 : int64_t{t[0]} - first;
      codeSigned(io, "vo_corner_delta", ctx.corner[cls], delta, m - 1);
      first += delta;
      cls = 1 + int(delta > 32 || delta < -32);
    } else {
      cls = 0;
    }
    io.require(first >= 0 && first < m,
               "vo_corner_delta gives vertex " + std::to_string(first) + ", out of range");
    const uint32_t a = static_cast<uint32_t>(first);
    const uint32_t candidates = remaining.remaining(a);
    io.require(candidates > 0, "vo_corner_delta gives vertex " + std::to_string(a) +
                                   ", which has no triangle left (output triangle " +
                                   std::to_string(i) + ")");
    uint32_t choice = 0;
    if (!Io::kReading) {
      // The first remaining corner at a that makes triangle t.
      const uint32_t* begin = corners.data() + start[a];
      const uint32_t* end = corners.data() + start[a + 1];
      const std::array<uint32_t, 3> wanted{t[1], t[2], 0};
      const uint32_t* it = std::lower_bound(
          begin, end, wanted,
          [&](uint32_t c, const std::array<uint32_t, 3>& w) { return key(c) < w; });
      // The corners with that key follow one another from `it`, some of them used already:
      // the first remaining one at or after `it`, found in the tree (stepping over the used
      // ones one by one took time quadratic in the copies of a repeated triangle).
      choice = remaining.rank(a, uint32_t(it - begin));
      const bool found = choice < candidates && [&] {
        const std::array<uint32_t, 3> k = key(begin[remaining.select(a, choice)]);
        return k[0] == t[1] && k[1] == t[2];
      }();
      io.require(found,
                 "output triangle " + std::to_string(i) + " is no remaining decoded triangle");
    }
    if (candidates > 1)
      codeUnsigned(io, "vo_corner_choice", ctx.choice[std::min<uint32_t>(candidates - 2, 3)],
                   choice, candidates - 1);
    const uint32_t corner = corners[start[a] + remaining.select(a, choice)];
    const Triangle& d = decoded.triangles[corner / 3];
    const uint32_t k = corner % 3;
    t = Triangle{a, out[d[(k + 1) % 3]], out[d[(k + 2) % 3]]};
    for (uint32_t c = 0; c < 3; ++c)
      remaining.remove(out[d[c]], position[3 * (corner / 3) + c]);
    previous = t;
  }
  codeDegenerate(io, numTriangles, order, degenerate, ctx, true);
}

// A frame of the I mesh's connectivity in output order: positions[j] (coding order) goes to
// output index vertexOutput[j]; the triangles are the output list.
inline void applyVertexOrder(const MeshOrder& order, const std::vector<Vec3i>& coded,
                             std::vector<Vec3i>& output) {
  output.resize(order.numVertices);
  for (size_t j = coded.size(); j-- > 0;)  // copies: the first one's position
    output[order.vertexOutput[j]] = coded[j];
}

}  // namespace tdvo
