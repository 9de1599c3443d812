#include "encoder/pmesh_encoder.h"

#include <cmath>
#include <stdexcept>

namespace tdvo {

namespace {

// Estimated bits of a signed Exp-Golomb-like code for v (sign included when v != 0):
// 2 + 2 floor(log2 |v|), with floor(log2 |v|) taken as the index of the highest set bit: the
// same value as std::floor(std::log2(double(|v|))) for every |v| < 2^24 (checked for all of
// them; motions and their differences stay below 2^23 on a 20-bit grid), without libm.
double signedBits(int64_t v) {
  if (v == 0) return 1.0;
  const uint64_t a = static_cast<uint64_t>(v < 0 ? -v : v);
  return 2.0 + 2.0 * (63 - __builtin_clzll(a));
}

// One visited octree cell in traversal order: a split, or a leaf with its mode.
struct CellDecision {
  bool split = false;
  LeafMode mode = LeafMode::kZero;
  Vec3i rep{0, 0, 0};
};

class RdDecisions {
 public:
  RdDecisions(const GomTopology& topology, const std::vector<Vec3i>& previous,
              const std::vector<Vec3i>& target, const PMeshParams& params, double lambda)
      : previous_(previous), params_(params), lambda_(lambda > 0 ? lambda : 1e-9) {
    const uint32_t n = topology.numVertices;
    motion_.resize(n);
    for (uint32_t v = 0; v < n; ++v)
      for (int c = 0; c < 3; ++c)
        motion_[v][c] = target[v][c] - previous[v][c];
    // Open-loop residual cost of every vertex: prediction from all neighbours' true motions
    // (the decoder's predictor, every motion available).
    std::vector<MotionRecord> all(n);
    for (uint32_t v = 0; v < n; ++v)
      all[v].motion = Lanes4{motion_[v][0], motion_[v][1], motion_[v][2], -1};
    const RingView rings = topology.vertexRings();
    residualBits_.resize(n);
    residualDistortion_.resize(n);
    for (uint32_t v = 0; v < n; ++v) {
      const Vec3i p = predictMotion(rings, all.data(), v, Vec3i{0, 0, 0});
      double bits = 0, distortion = 0;
      for (int c = 0; c < 3; ++c) {
        const int64_t r = roundDiv(motion_[v][c] - p[c], params.quantStep);
        const double error = motion_[v][c] - (p[c] + r * params.quantStep);
        bits += signedBits(r);
        distortion += error * error;
      }
      residualBits_[v] = bits;
      residualDistortion_[v] = distortion;
    }
  }

  // Runs the RD search; afterwards the Decider interface replays the decisions.
  void search(uint32_t* begin, uint32_t* end) {
    decisions_.clear();
    Vec3i parentMean{0, 0, 0};
    best(begin, end, 0, parentMean, decisions_);
    next_ = 0;
  }

  // ---- Decider interface used by codePMesh (in traversal order) ----
  bool split(const uint32_t*, const uint32_t*, int) {
    if (next_ >= decisions_.size()) throw std::logic_error("P-mesh decisions exhausted");
    if (!decisions_[next_].split) return false;
    ++next_;
    return true;
  }
  LeafMode leafMode(const uint32_t*, const uint32_t*) {
    if (next_ >= decisions_.size() || decisions_[next_].split)
      throw std::logic_error("P-mesh decisions out of step with the octree traversal");
    current_ = decisions_[next_++];
    return current_.mode;
  }
  Vec3i representative(const uint32_t*, const uint32_t*) { return current_.rep; }
  int32_t residual(uint32_t v, int c, int32_t prediction) {
    return static_cast<int32_t>(roundDiv(int64_t{motion_[v][c]} - prediction, params_.quantStep));
  }

 private:
  // Best cost of a cell; appends its decisions (preorder) to `out`.
  double best(uint32_t* begin, uint32_t* end, int depth, const Vec3i& parentMean,
              std::vector<CellDecision>& out) {
    const double count = static_cast<double>(end - begin);
    double sum[3] = {0, 0, 0}, sumSquares = 0, resBits = 0, resDistortion = 0;
    for (uint32_t* it = begin; it != end; ++it) {
      const Vec3i& m = motion_[*it];
      for (int c = 0; c < 3; ++c) {
        sum[c] += m[c];
        sumSquares += double(m[c]) * m[c];
      }
      resBits += residualBits_[*it];
      resDistortion += residualDistortion_[*it];
    }
    Vec3i mean;
    double repDistortion = sumSquares, repBits = 2.0;
    for (int c = 0; c < 3; ++c) {
      mean[c] = static_cast<int32_t>(std::floor(sum[c] / count + 0.5));
      repDistortion += -2.0 * mean[c] * sum[c] + count * double(mean[c]) * mean[c];
      repBits += signedBits(int64_t{mean[c]} - parentMean[c]);
    }
    const double zeroCost = sumSquares + lambda_ * 1.0;
    const double repCost = repDistortion + lambda_ * repBits;
    const double resCost = resDistortion + lambda_ * (2.0 + resBits);
    CellDecision leaf;
    double leafCost = zeroCost;
    if (repCost < leafCost) {
      leafCost = repCost;
      leaf.mode = LeafMode::kRepresentative;
      leaf.rep = mean;
    }
    if (resCost < leafCost) {
      leafCost = resCost;
      leaf.mode = LeafMode::kResidual;
    }

    if (end - begin > 1 && depth < params_.maxDepth && leafCost > 0) {
      const size_t mark = out.size();
      out.push_back(CellDecision{true, LeafMode::kZero, {0, 0, 0}});
      std::array<uint32_t, 9> bounds;
      OctreePartition::split(previous_, begin, end, params_.gridBits, depth, bounds, scratch_);
      double splitCost = lambda_ * 1.0;
      for (int o = 0; o < 8 && splitCost < leafCost; ++o)
        if (bounds[o + 1] > bounds[o])
          splitCost += best(begin + bounds[o], begin + bounds[o + 1], depth + 1, mean, out);
      if (splitCost < leafCost) return splitCost;
      out.resize(mark);  // keep the leaf; the children's decisions are dropped
    }
    out.push_back(leaf);
    return leafCost;
  }

  const std::vector<Vec3i>& previous_;
  PMeshParams params_;
  double lambda_;
  std::vector<Vec3i> motion_;
  std::vector<double> residualBits_, residualDistortion_;
  std::vector<CellDecision> decisions_;
  std::vector<uint32_t> scratch_;
  size_t next_ = 0;
  CellDecision current_;
};

// Decider of codeTemporalDpcm: the rounded quantised motion of each vertex.
class TemporalDecisions {
 public:
  TemporalDecisions(const std::vector<Vec3i>& previous, const std::vector<Vec3i>& target,
                    int quantStep)
      : previous_(previous), target_(target), quantStep_(quantStep) {}
  int32_t residual(uint32_t v, int c, int32_t prediction) const {
    const int64_t motion = int64_t{target_[v][c]} - previous_[v][c];
    return static_cast<int32_t>(roundDiv(motion - prediction, quantStep_));
  }

 private:
  const std::vector<Vec3i>& previous_;
  const std::vector<Vec3i>& target_;
  int quantStep_;
};

}  // namespace

PMeshEncoding encodeTemporalDpcm(const std::vector<Vec3i>& previous,
                                 const std::vector<Vec3i>& target, const PMeshParams& params) {
  if (previous.size() != target.size())
    throw std::logic_error("encodeTemporalDpcm: vertex counts disagree");
  TemporalDecisions decisions(previous, target, params.quantStep);
  CabacWriterIo io;
  PMeshEncoding out;
  out.reconstruction = codeTemporalDpcm(io, decisions, previous, params);
  out.payload = io.finish();
  out.bins = io.binCount();
  return out;
}

PMeshEncoding encodePMesh(const GomTopology& topology, const std::vector<Vec3i>& previous,
                          const std::vector<Vec3i>& target, const PMeshParams& params,
                          double lambda) {
  if (previous.size() != topology.numVertices || target.size() != topology.numVertices)
    throw std::logic_error("encodePMesh: vertex counts disagree");
  RdDecisions rd(topology, previous, target, params, lambda);
  std::vector<uint32_t> cells(topology.numVertices);
  for (uint32_t v = 0; v < cells.size(); ++v)
    cells[v] = v;
  if (!cells.empty()) rd.search(cells.data(), cells.data() + cells.size());

  CabacWriterIo io;
  PMeshEncoding out;
  out.reconstruction = codePMesh(io, rd, topology, previous, params);
  out.payload = io.finish();
  out.bins = io.binCount();
  return out;
}

}  // namespace tdvo
