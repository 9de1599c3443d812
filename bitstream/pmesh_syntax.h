// P-mesh syntax and decoding process, written once for encoder and decoder.
//
// A P mesh carries the motion of every vertex of the GOM relative to the previous decoded
// frame. Its CABAC payload has two passes (docs/bitstream.md, "P-mesh payload"):
//
// Pass 1, octree clustering. The octree over the previous frame's grid positions
// (pmesh_prediction.h) is traversed depth first, octants in order, empty cells skipped. A cell
// with more than one vertex above the maximum depth codes pm_split_flag. A leaf codes its mode:
//   pm_leaf_moving     0: ZERO            every vertex of the leaf keeps its position
//   pm_leaf_residual   0: REPRESENTATIVE  one motion vector for the whole leaf, coded as the
//                                         difference pm_rep_delta_{x,y,z} to the previous
//                                         representative of this P mesh ((0,0,0) at the start)
//                      1: RESIDUAL        motion coded per vertex in pass 2
// Pass 2, residuals. Vertices of RESIDUAL leaves, in the GOM's breadth-first order, get
// motion = prediction + MotionQuantStep * pm_residual_{x,y,z}, where the prediction
// (predictMotion) uses only motions already final: ZERO/REPRESENTATIVE vertices and earlier
// RESIDUAL vertices; with no final neighbour it is the previous pass-2 vertex's motion.
// The residual's contexts are chosen by the residuals already decoded around the vertex.
// Finally each position becomes applyMotion(previous, motion) and a terminate bin ends the
// payload.
//
// codePMesh<Io, Decider> is this process. With CabacReaderIo it parses (the Decider is
// ignored); with CabacWriterIo it writes the values the encoder's Decider chooses. Either way
// it returns the reconstruction, so the encoder's reconstruction is the decoder's by
// construction.
#pragma once

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "bitstream/cabac_io.h"
#include "common/geometry/pmesh_prediction.h"

namespace tdvo {

enum class LeafMode : uint8_t { kZero = 0, kRepresentative = 1, kResidual = 2 };

// |motion| limit: grids have at most 20 bits, so a motion or residual beyond 2^21 is corrupt.
constexpr int32_t kMaxMotion = 1 << 21;

struct PMeshParams {
  int gridBits = 12;
  int quantStep = 1;  // MotionQuantStep
  int maxDepth = 12;  // deepest octree level (<= gridBits)
};

// Every context of the P-mesh payload with its initial state; a fresh set per P mesh.
struct PMeshContexts {
  static constexpr int kSplitDepthClasses = 12;
  static constexpr int kRepCtx = 4, kRepK = 2, kRepCutoff = 8;
  static constexpr int kResidualClasses = 5, kResidualCtx = 6, kResidualK = 0, kResidualCutoff = 12;
  ContextModel split[kSplitDepthClasses];
  ContextModel leafMoving[3];                                // by the previous leaf's mode
  ContextModel leafResidual[3];                              // by the previous leaf's mode
  ContextModel rep[3][kRepCtx];                              // per component
  ContextModel residual[kResidualClasses][3][kResidualCtx];  // neighbour class x component
};

// The decoder's Decider: never consulted, as every value is read.
struct NoDecisions {
  bool split(const uint32_t*, const uint32_t*, int) { return false; }
  LeafMode leafMode(const uint32_t*, const uint32_t*) { return LeafMode::kZero; }
  Vec3i representative(const uint32_t*, const uint32_t*) { return {0, 0, 0}; }
  int32_t residual(uint32_t, int, int32_t) { return 0; }
};

// Residual context class (see PMeshContexts::residual) from the 1-ring neighbours of a vertex
// that already have a decoded residual: `count` of them, `sumAbs` the sum of their |residual|
// in the component coded. 0 no such neighbour; 1 all their residuals are 0; 2 mean |r| < 2;
// 3 mean |r| < 6; 4 otherwise. (Written as a sum of comparisons: the class follows the data,
// and branches on it are mispredicted. sumAbs is 0 when count is.)
inline int residualClass(int64_t count, int64_t sumAbs) {
  return int(count > 0) *
         (1 + int(sumAbs > 0) + int(sumAbs >= 2 * count) + int(sumAbs >= 6 * count));
}

// Buffers of codePMesh, kept by the caller from one P mesh to the next: once they have grown
// to the GOM's vertex count, coding further P meshes allocates nothing.
struct PMeshWorkspace {
  std::vector<MotionRecord> vertices;   // per vertex, in rank order
  std::vector<uint32_t> residualRanks;  // pass 2's vertices
  MortonOctree octree;
};

// Codes one P mesh. `previous` is the previous decoded frame's positions (GOM order); the new
// positions are written to `positions` (resized to the vertex count; must not be `previous`).
// Io is CabacWriterIo or CabacReaderIo; Decider supplies the encoder's choices (NoDecisions
// when reading). The Io's finish() is left to the caller.
template <class Io, class Decider>
void codePMesh(Io& io, Decider& decider, const GomTopology& topology,
               const std::vector<Vec3i>& previous, const PMeshParams& params, PMeshWorkspace& work,
               std::vector<Vec3i>& positions) {
  const uint32_t n = topology.numVertices;
  io.require(previous.size() == n, "previous frame and GOM topology disagree");
  PMeshContexts ctx;
  work.vertices.assign(n, MotionRecord());
  // Raw pointers: a local pointer, unlike a vector's, is not reloaded after every store.
  MotionRecord* const state = work.vertices.data();

  // Pass 1: octree clustering. The cells are ranges of the Morton-sorted vertices (the order
  // inside a leaf does not matter: every vertex of a leaf is treated alike).
  const uint32_t* const rank = topology.rank.data();
  MortonOctree& octree = work.octree;
  octree.build(previous, params.gridBits);
  uint32_t* const cells = octree.vertices();
  Vec3i lastRep{0, 0, 0};
  int previousMode = 0;
  auto leaf = [&](uint32_t* begin, uint32_t* end) {
    unsigned moving = 0, residual = 0;
    if (!Io::kReading) {
      const LeafMode mode = decider.leafMode(begin, end);
      moving = mode != LeafMode::kZero;
      residual = mode == LeafMode::kResidual;
    }
    io.bin("pm_leaf_moving", ctx.leafMoving[previousMode], moving);
    if (moving) io.bin("pm_leaf_residual", ctx.leafResidual[previousMode], residual);
    const LeafMode mode = !moving    ? LeafMode::kZero
                          : residual ? LeafMode::kResidual
                                     : LeafMode::kRepresentative;
    previousMode = static_cast<int>(mode);
    if (mode == LeafMode::kRepresentative) {
      Vec3i rep{0, 0, 0};
      if (!Io::kReading) rep = decider.representative(begin, end);
      static const char* const kNames[3] = {"pm_rep_delta_x", "pm_rep_delta_y", "pm_rep_delta_z"};
      for (int c = 0; c < 3; ++c) {
        int32_t delta = rep[c] - lastRep[c];
        io.signedUeg(kNames[c], ctx.rep[c], PMeshContexts::kRepCtx, PMeshContexts::kRepK,
                     PMeshContexts::kRepCutoff, delta, 2 * kMaxMotion);
        rep[c] = lastRep[c] + delta;
        io.require(rep[c] >= -kMaxMotion && rep[c] <= kMaxMotion,
                   "representative motion out of range");
      }
      lastRep = rep;
      const Lanes4 motion{rep[0], rep[1], rep[2], -1};
      for (uint32_t* it = begin; it != end; ++it)
        state[rank[*it]].motion = motion;
    } else if (mode == LeafMode::kResidual) {
      for (uint32_t* it = begin; it != end; ++it)
        state[rank[*it]].motion[3] = 0;  // not available until pass 2 decodes it
    }
  };
  auto cell = [&](auto& self, uint32_t begin, uint32_t end, int depth) -> void {
    unsigned split = 0;
    if (end - begin > 1 && depth < params.maxDepth) {
      if (!Io::kReading) split = decider.split(cells + begin, cells + end, depth);
      io.bin("pm_split_flag", ctx.split[std::min(depth, PMeshContexts::kSplitDepthClasses - 1)],
             split);
    }
    if (!split) return leaf(cells + begin, cells + end);
    std::array<uint32_t, 9> bounds;
    octree.split(begin, end, depth, bounds);
    // The non-empty octants, in order, listed without a branch per octant (which one is empty
    // follows the data), then visited.
    int nonEmpty[8], count = 0;
    for (int o = 0; o < 8; ++o) {
      nonEmpty[count] = o;
      count += bounds[o + 1] > bounds[o];
    }
    for (int i = 0; i < count; ++i)
      self(self, bounds[nonEmpty[i]], bounds[nonEmpty[i] + 1], depth + 1);
  };
  if (n > 0) cell(cell, 0u, n, 0);

  // Pass 2: residuals in breadth-first order, i.e. rank by rank. The prediction is
  // predictMotion's over the records in rank space, which sums the residual context statistics
  // in the same neighbour loop. A vertex of a RESIDUAL leaf is still unavailable when its turn
  // comes (only its own turn makes it available), every other vertex is available.
  Vec3i fallback{0, 0, 0};
  static const char* const kResidualNames[3] = {"pm_residual_x", "pm_residual_y", "pm_residual_z"};
  const RingView rings = topology.rankRings();
  const int64_t quantStep = params.quantStep;
  // The ranks of the vertices of RESIDUAL leaves, listed without a branch per vertex (which
  // vertex is one follows the data).
  work.residualRanks.resize(n);
  uint32_t* const residualRanks = work.residualRanks.data();
  uint32_t numResidual = 0;
  for (uint32_t r = 0; r < n; ++r) {
    residualRanks[numResidual] = r;
    numResidual += state[r].motion[3] == 0;
  }
  for (const uint32_t* next = residualRanks; next != residualRanks + numResidual; ++next) {
    const uint32_t r = *next;
    MotionRecord& sv = state[r];
    RingResiduals around;
    const Vec3i prediction = predictMotion(rings, state, r, fallback, around);
    const uint32_t v = topology.order[r];
    // Scalars until all three are known: a vector assembled in memory lane by lane would be
    // read back before the stores could be forwarded to it.
    int32_t residual[3] = {0, 0, 0}, motion[3], absResidual[3];
    ContextModel* contexts[3];
    for (int c = 0; c < 3; ++c) {
      if (!Io::kReading) residual[c] = decider.residual(v, c, prediction[c]);
      contexts[c] = ctx.residual[residualClass(around.count(), around.sums[c])][c];
    }
    io.signedUeg3(kResidualNames, contexts, PMeshContexts::kResidualCtx, PMeshContexts::kResidualK,
                  PMeshContexts::kResidualCutoff, residual, kMaxMotion);
    for (int c = 0; c < 3; ++c) {
      const int64_t m = int64_t{prediction[c]} + quantStep * residual[c];
      io.require(m >= -kMaxMotion && m <= kMaxMotion, "decoded motion out of range");
      motion[c] = static_cast<int32_t>(m);
      absResidual[c] = residual[c] < 0 ? -residual[c] : residual[c];
    }
    sv.motion = Lanes4{motion[0], motion[1], motion[2], -1};
    sv.absResidual = Lanes4{absResidual[0], absResidual[1], absResidual[2], 1};
    fallback = {motion[0], motion[1], motion[2]};
  }

  positions.resize(n);
  for (uint32_t v = 0; v < n; ++v) {
    const Lanes4& m = state[rank[v]].motion;
    positions[v] = applyMotion(previous[v], {m[0], m[1], m[2]}, params.gridBits);
  }
}

// As above, with buffers of its own (convenient for single P meshes and tests).
template <class Io, class Decider>
std::vector<Vec3i> codePMesh(Io& io, Decider& decider, const GomTopology& topology,
                             const std::vector<Vec3i>& previous, const PMeshParams& params) {
  PMeshWorkspace work;
  std::vector<Vec3i> positions;
  codePMesh(io, decider, topology, previous, params, work, positions);
  return positions;
}

// The AFX-IC-style reference P mesh (PMeshMode afxic): every vertex, in index order, codes its
// motion from the previous keyframe directly (temporal DPCM of each vertex trajectory, no
// clustering, no spatial prediction): motion = MotionQuantStep * pt_residual_{x,y,z}, each
// se(0, 12, ctx[class][c][6]) where class is 0, 1 or 2 for |residual| of the previous vertex in
// that component = 0, < 4, >= 4. Then positions = applyMotion(previous, motion) and a
// terminate bin ends the payload.
struct TemporalDpcmContexts {
  static constexpr int kClasses = 3, kCtx = 6, kK = 0, kCutoff = 12;
  ContextModel residual[kClasses][3][kCtx];
};

// Writes the new positions to `positions` (resized; must not be `previous`).
template <class Io, class Decider>
void codeTemporalDpcm(Io& io, Decider& decider, const std::vector<Vec3i>& previous,
                      const PMeshParams& params, std::vector<Vec3i>& positions) {
  TemporalDpcmContexts ctx;
  static const char* const kNames[3] = {"pt_residual_x", "pt_residual_y", "pt_residual_z"};
  positions.resize(previous.size());
  Vec3i last{0, 0, 0};
  for (uint32_t v = 0; v < previous.size(); ++v) {
    Vec3i motion;
    for (int c = 0; c < 3; ++c) {
      int32_t r = 0;
      if (!Io::kReading) r = decider.residual(v, c, 0);
      const int32_t magnitude = last[c] < 0 ? -last[c] : last[c];
      const int cls = magnitude == 0 ? 0 : magnitude < 4 ? 1 : 2;
      io.signedUeg(kNames[c], ctx.residual[cls][c], TemporalDpcmContexts::kCtx,
                   TemporalDpcmContexts::kK, TemporalDpcmContexts::kCutoff, r, kMaxMotion);
      const int64_t m = int64_t{params.quantStep} * r;
      io.require(m >= -kMaxMotion && m <= kMaxMotion, "decoded motion out of range");
      motion[c] = static_cast<int32_t>(m);
      last[c] = r;
    }
    positions[v] = applyMotion(previous[v], motion, params.gridBits);
  }
}

template <class Io, class Decider>
std::vector<Vec3i> codeTemporalDpcm(Io& io, Decider& decider, const std::vector<Vec3i>& previous,
                                    const PMeshParams& params) {
  std::vector<Vec3i> positions;
  codeTemporalDpcm(io, decider, previous, params, positions);
  return positions;
}

}  // namespace tdvo
