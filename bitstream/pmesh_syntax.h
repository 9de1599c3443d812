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
#include <numeric>
#include <string>
#include <vector>

#include "bitstream/cabac_io.h"
#include "common/pmesh_prediction.h"

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

// Residual context class of component c of vertex v (see PMeshContexts::residual):
// 0 no neighbour has a residual yet; 1 all such residuals are 0; 2 mean |r| < 2; 3 mean |r| < 6;
// 4 otherwise.
inline int residualClass(const GomTopology& t, uint32_t v, int c, const std::vector<Vec3i>& q,
                         const std::vector<uint8_t>& hasResidual) {
  int64_t count = 0, sum = 0;
  for (uint32_t i = t.neighbourStart[v]; i < t.neighbourStart[v + 1]; ++i) {
    const uint32_t u = t.neighbours[i];
    if (!hasResidual[u]) continue;
    ++count;
    sum += q[u][c] < 0 ? -int64_t{q[u][c]} : q[u][c];
  }
  if (count == 0) return 0;
  if (sum == 0) return 1;
  if (sum < 2 * count) return 2;
  if (sum < 6 * count) return 3;
  return 4;
}

// Codes one P mesh. `previous` is the previous decoded frame's positions (GOM order);
// returns the new positions. Io is CabacWriterIo or CabacReaderIo; Decider supplies the
// encoder's choices (NoDecisions when reading). The Io's finish() is left to the caller.
template <class Io, class Decider>
std::vector<Vec3i> codePMesh(Io& io, Decider& decider, const GomTopology& topology,
                             const std::vector<Vec3i>& previous, const PMeshParams& params) {
  const uint32_t n = topology.numVertices;
  io.require(previous.size() == n, "previous frame and GOM topology disagree");
  PMeshContexts ctx;
  std::vector<Vec3i> motion(n, Vec3i{0, 0, 0});
  std::vector<uint8_t> inResidualLeaf(n, 0);

  // Pass 1: octree clustering.
  std::vector<uint32_t> cells(n);
  std::iota(cells.begin(), cells.end(), 0u);
  std::vector<uint32_t> scratch;
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
      for (uint32_t* it = begin; it != end; ++it)
        motion[*it] = rep;
    } else if (mode == LeafMode::kResidual) {
      for (uint32_t* it = begin; it != end; ++it)
        inResidualLeaf[*it] = 1;
    }
  };
  auto cell = [&](auto& self, uint32_t* begin, uint32_t* end, int depth) -> void {
    unsigned split = 0;
    if (end - begin > 1 && depth < params.maxDepth) {
      if (!Io::kReading) split = decider.split(begin, end, depth);
      io.bin("pm_split_flag", ctx.split[std::min(depth, PMeshContexts::kSplitDepthClasses - 1)],
             split);
    }
    if (!split) return leaf(begin, end);
    std::array<uint32_t, 9> bounds;
    OctreePartition::split(previous, begin, end, params.gridBits, depth, bounds, scratch);
    for (int o = 0; o < 8; ++o)
      if (bounds[o + 1] > bounds[o])
        self(self, begin + bounds[o], begin + bounds[o + 1], depth + 1);
  };
  if (n > 0) cell(cell, cells.data(), cells.data() + n, 0);

  // Pass 2: residuals in breadth-first order.
  std::vector<uint8_t> available(n);
  for (uint32_t v = 0; v < n; ++v)
    available[v] = !inResidualLeaf[v];
  std::vector<Vec3i> q(n, Vec3i{0, 0, 0});
  std::vector<uint8_t> hasResidual(n, 0);
  Vec3i fallback{0, 0, 0};
  static const char* const kResidualNames[3] = {"pm_residual_x", "pm_residual_y", "pm_residual_z"};
  const int32_t maxResidual = kMaxMotion;
  for (uint32_t v : topology.order) {
    if (!inResidualLeaf[v]) continue;
    const Vec3i prediction = predictMotion(topology, v, motion, available, fallback);
    for (int c = 0; c < 3; ++c) {
      int32_t r = 0;
      if (!Io::kReading) r = decider.residual(v, c, prediction[c]);
      const int cls = residualClass(topology, v, c, q, hasResidual);
      io.signedUeg(kResidualNames[c], ctx.residual[cls][c], PMeshContexts::kResidualCtx,
                   PMeshContexts::kResidualK, PMeshContexts::kResidualCutoff, r, maxResidual);
      const int64_t m = int64_t{prediction[c]} + int64_t{params.quantStep} * r;
      io.require(m >= -kMaxMotion && m <= kMaxMotion, "decoded motion out of range");
      motion[v][c] = static_cast<int32_t>(m);
      q[v][c] = r;
    }
    available[v] = 1;
    hasResidual[v] = 1;
    fallback = motion[v];
  }

  std::vector<Vec3i> positions(n);
  for (uint32_t v = 0; v < n; ++v)
    positions[v] = applyMotion(previous[v], motion[v], params.gridBits);
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

template <class Io, class Decider>
std::vector<Vec3i> codeTemporalDpcm(Io& io, Decider& decider, const std::vector<Vec3i>& previous,
                                    const PMeshParams& params) {
  TemporalDpcmContexts ctx;
  static const char* const kNames[3] = {"pt_residual_x", "pt_residual_y", "pt_residual_z"};
  std::vector<Vec3i> positions(previous.size());
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
  return positions;
}

}  // namespace tdvo
