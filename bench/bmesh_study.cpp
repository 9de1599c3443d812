// Study (docs/prediction.md, "B meshes"): would P meshes predicted from the interpolation of
// two decoded frames (B meshes, as in video coding) code a GOM for fewer bytes than the chain of
// P meshes, at the same error? Made before the syntax had B meshes; 3dvo-enc's `BMeshGap` and
// `BMeshQuantStep` now code them (docs/bitstream.md, "B meshes") as the variants below do.
//
// Encoder side only: every coding below is the real encodePMesh (RD search and CABAC, closed
// loop: each reconstruction is the decoder's), only its reference changes. Per sequence (shared
// data; skipped with a message when absent) and GOM (cfg/per-sequence's GOMSize, on the 12-bit
// grid over the sequence, every GOM from its own lossless I mesh, which costs the same in every
// variant and is not counted):
//   P          frame k from the decoded frame k - 1 (every frame a keyframe);
//   B<G>x<F>   frames 0, G, 2G, ... and the GOM's last frame as a P chain (keyframes); between
//              two decoded frames l < r, the middle frame m = (l + r) / 2 is coded from
//              interpolateFrame(l, r, m) (the decoder's keyframe interpolation), then (l, m) and
//              (m, r) likewise, down to adjacent frames (hierarchical B), with F times the
//              quantiser (and its automatic Lambda) in the B meshes.
// With BMESH_STUDY_CASCADE set, the variants are instead the cascades of docs/prediction.md
// ("B meshes"), all with G = 8:
//   B8x<F>c<c>  the B quantiser F times the P quantiser at the first level of the halving, times
//               c at each level below;
//   B8x<F>L<L>  the B quantiser F times the P quantiser at every level, the Lambda of the octree
//               clustering times L at each level below the first (what BMeshLambdaGrowth does).
// Output, one CSV line per sequence, variant and MotionQuantStep: P-mesh payload bytes and the
// squared error against the quantised input (grid units) over every frame but the I meshes.
// bench/bmesh_study.py turns it into BD-rates against P.
//
//   build/bin/bmesh_study > /tmp/bmesh.csv && /usr/bin/python3 bench/bmesh_study.py /tmp/bmesh.csv
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "common/core/obj_io.h"
#include "common/core/sequence.h"
#include "common/geometry/keyframes.h"
#include "encoder/encoder_params.h"
#include "encoder/imesh_encoder.h"
#include "encoder/pmesh_encoder.h"
#include "encoder/sequence_encoder.h"

using namespace tdvo;

namespace {

struct Sequence {
  const char* name;
  const char* pattern;  // under ../shared/data/meshseq/
  int first, count, gomSize;
};
const Sequence kSequences[] = {
    {"horse-gallop", "horse-gallop/%04d.obj.gz", 1, 48, 48},
    {"samba", "samba/mesh_%04d.obj.gz", 0, 175, 25},
    {"pcow", "pcow/%d.obj.gz", 1, 204, 34},
};

double lambdaFor(int step) {
  EncoderParams p;
  p.motionQuantStep = step;
  return p.effectiveLambda();
}

double squared(const std::vector<Vec3i>& p, const std::vector<Vec3i>& q) {
  double sum = 0;
  for (size_t j = 0; j < p.size(); ++j)
    for (int c = 0; c < 3; ++c) {
      const double e = double(p[j][c]) - double(q[j][c]);
      sum += e * e;
    }
  return sum;
}

struct Tally {
  double bytes = 0, sse = 0, values = 0;
};

struct GomCoder {
  const GomTopology& topology;
  const std::vector<std::vector<Vec3i>>& targets;  // [0]: the decoded I mesh
  int gridBits;
  std::vector<std::vector<Vec3i>> recon;
  Tally tally;

  double lambdaCascade = 1;  // the B meshes' Lambda factor per level below the first
  void code(size_t k, const std::vector<Vec3i>& reference, int step, double lambdaFactor = 1) {
    PMeshParams p;
    p.gridBits = gridBits;
    p.maxDepth = gridBits;
    p.quantStep = step;
    PMeshEncoding e =
        encodePMesh(topology, reference, targets[k], p, lambdaFactor * lambdaFor(step));
    tally.bytes += double(e.payload.size());
    tally.sse += squared(e.reconstruction, targets[k]);
    tally.values += 3.0 * double(targets[k].size());
    recon[k] = std::move(e.reconstruction);
  }
  // `step` at the first level (the middle of two keyframes), times `cascade` per level below.
  void between(int a, int b, double step, double cascade, double lambdaFactor = 1) {
    if (b - a < 2) return;
    const int m = (a + b) / 2;
    code(size_t(m), interpolateFrame(recon[size_t(a)], recon[size_t(b)], a, b, m),
         std::max(1, int(std::lround(step))), lambdaFactor);
    between(a, m, step * cascade, cascade, lambdaFactor * lambdaCascade);
    between(m, b, step * cascade, cascade, lambdaFactor * lambdaCascade);
  }
  // anchorGap 1: today's P chain.
  void run(int anchorGap, int step, double bStep, double cascade) {
    const int n = int(targets.size());
    recon.assign(targets.size(), {});
    recon[0] = targets[0];
    int a = 0;
    while (a < n - 1) {
      const int b = std::min(a + anchorGap, n - 1);
      code(size_t(b), recon[size_t(a)], step);
      between(a, b, bStep, cascade);
      a = b;
    }
  }
};

}  // namespace

int main() {
  const std::string data = std::string(TDVO_SHARED_DATA_DIR) + "/meshseq/";
  const int steps[] = {1, 2, 4, 8, 16, 32, 64};
  struct Variant {
    std::string name;
    int gap;
    double bFactor;
    double cascade = 1;        // the B quantiser's factor per level below the first
    double lambdaCascade = 1;  // the B meshes' Lambda factor per level below the first
  };
  std::vector<Variant> variants = {{"P", 1, 1}};
  if (std::getenv("BMESH_STUDY_CASCADE")) {
    // The quantiser cascade: B8 with the first level at factor F, each level below c times more.
    for (double f : {1.0, 1.5, 2.0})
      for (double c : {1.0, 1.25, 1.5, 2.0})
        variants.push_back(
            {"B8x" + std::to_string(f).substr(0, 3) + "c" + std::to_string(c).substr(0, 4), 8, f,
             c});
    for (double f : {1.5, 2.0, 3.0})
      for (double l : {1.5, 2.0, 3.0})
        variants.push_back(
            {"B8x" + std::to_string(f).substr(0, 3) + "L" + std::to_string(l).substr(0, 3), 8, f,
             1.0, l});
  } else {
    for (int gap : {2, 4, 8, 16})
      for (double f : {1.0, 1.5, 2.0, 3.0})
        variants.push_back(
            {"B" + std::to_string(gap) + "x" + std::to_string(f).substr(0, 3), gap, f});
  }
  std::printf("sequence,variant,step,bytes,sse,values\n");
  for (const Sequence& s : kSequences) {
    const std::string pattern = data + s.pattern;
    if (!std::filesystem::exists(framePath(pattern, s.first + s.count - 1))) {
      std::fprintf(stderr, "bmesh_study: %s not found, skipped\n", pattern.c_str());
      continue;
    }
    std::vector<Mesh> frames;
    for (int k = 0; k < s.count; ++k)
      frames.push_back(readObj(framePath(pattern, s.first + k)));
    const Grid grid = gridForSequence(frames, 12, GridFit::kSequence);
    std::vector<Tally> totals(variants.size() * std::size(steps));
    for (int g0 = 0; g0 < s.count; g0 += s.gomSize) {
      const int n = std::min(s.gomSize, s.count - g0);
      if (n < 2) continue;
      const IntMesh first = grid.quantise(frames[size_t(g0)]);
      const IMeshEncoding iMesh = encodeIMesh(first, grid.bits, 0);
      const GomTopology topology = GomTopology::build(iMesh.decoded);
      std::vector<std::vector<Vec3i>> targets{iMesh.decoded.positions};
      for (int k = 1; k < n; ++k) {
        const IntMesh q = grid.quantise(frames[size_t(g0 + k)]);
        std::vector<Vec3i> t(iMesh.inputIndex.size());
        for (size_t j = 0; j < t.size(); ++j)
          t[j] = q.positions[iMesh.inputIndex[j]];
        targets.push_back(std::move(t));
      }
      for (size_t v = 0; v < variants.size(); ++v)
        for (size_t i = 0; i < std::size(steps); ++i) {
          GomCoder coder{topology, targets, grid.bits, {}, {}, variants[v].lambdaCascade};
          coder.run(variants[v].gap, steps[i], steps[i] * variants[v].bFactor, variants[v].cascade);
          Tally& t = totals[v * std::size(steps) + i];
          t.bytes += coder.tally.bytes;
          t.sse += coder.tally.sse;
          t.values += coder.tally.values;
        }
      std::fprintf(stderr, "bmesh_study: %s frames %d..%d\n", s.name, g0, g0 + n - 1);
    }
    for (size_t v = 0; v < variants.size(); ++v)
      for (size_t i = 0; i < std::size(steps); ++i) {
        const Tally& t = totals[v * std::size(steps) + i];
        std::printf("%s,%s,%d,%.0f,%.0f,%.0f\n", s.name, variants[v].name.c_str(), steps[i],
                    t.bytes, t.sse, t.values);
      }
    std::fflush(stdout);
  }
  return 0;
}
