#include "encoder/quality.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "common/core/error.h"
#include "common/core/warnings.h"

namespace tdvo {

namespace {

struct Candidate {
  int gridBits = 0;
  int step = 1;
  double j = std::numeric_limits<double>::infinity();
  double bits = 0, distortion = 0;  // extrapolated to the sequence
};

// The I meshes of a sequence of `frames` frames: one per random access point (the first GOM of
// each run), every frame with PMeshMode intra.
size_t randomAccessGoms(const EncoderParams& p, size_t frames) {
  if (p.pmeshMode == PMeshMode::kIntra) return frames;
  return p.randomAccessRuns(p.goms(frames).size()).size();
}

// Codes the first `count` frames as one GOM with candidate `c` and fills its extrapolated rate,
// distortion and J = D + λ·R with λ = (ln 2 / 6) Δ², Δ = `target` (0: the object has no size,
// and only the distortion counts). Distances are in units of Δ, so that J stays finite and
// ordered at any scale of the input (in world units, a squared distance overflows beyond 1e154
// and underflows below 1e-154); λ is then ln 2 / 6.
void measure(Candidate& c, const EncoderParams& params, const SequenceBounds& bounds,
             const std::vector<Mesh>& frames, const std::vector<std::string>& names,
             size_t sequenceFrames, double target) {
  const double unit = target > 0 ? target : 1.0;
  const double lambda = target > 0 ? std::log(2.0) / 6.0 : 0.0;
  EncoderParams p = params;
  p.gridBits = c.gridBits;
  p.motionQuantStep = c.step;
  p.frameCount = static_cast<int>(frames.size());
  p.gomSize = static_cast<int>(frames.size());
  p.gomListFile.clear();
  p.randomAccessPeriod = 1;
  p.threads = 1;
  const Grid grid = gridFor(bounds, c.gridBits, p.gridFit);
  std::vector<double> frameError(frames.size(), 0.0);
  std::vector<IntMesh> recon;
  const EncodedSequence coded = encodeSequence(
      p, grid, frames, names, [&](int, const IntMesh& mesh) { recon.push_back(mesh); });
  for (size_t k = 0; k < frames.size(); ++k) {
    const std::vector<uint32_t>& input = coded.frameInputIndex[k];
    for (size_t v = 0; v < recon[k].positions.size(); ++v) {
      const Vec3d decoded = grid.dequantise(recon[k].positions[v]);
      const Vec3d& original = frames[k].positions[input[v]];
      for (int a = 0; a < 3; ++a) {
        const double d = decoded[a] / unit - original[a] / unit;
        frameError[k] += d * d;
      }
    }
  }
  // Frame 0 stands for the I meshes (with their vertex order and attributes), frames 1 .. n-1
  // for the P meshes; the sequence has one I mesh per random access point.
  const double intraBits = 8.0 * (coded.iMeshBytes + coded.orderBytes + coded.attributeBytes);
  const double n = static_cast<double>(frames.size());
  const double intraFrames =
      static_cast<double>(std::min(randomAccessGoms(params, sequenceFrames), sequenceFrames));
  const double interFrames = static_cast<double>(sequenceFrames) - intraFrames;
  c.bits = intraFrames * intraBits / (params.pmeshMode == PMeshMode::kIntra ? n : 1.0);
  c.distortion = intraFrames * frameError[0];
  if (frames.size() > 1 && interFrames > 0) {
    double interError = 0;
    for (size_t k = 1; k < frames.size(); ++k)
      interError += frameError[k];
    c.bits += interFrames * 8.0 * coded.pMeshBytes / (n - 1);
    c.distortion += interFrames * interError / (n - 1);
  }
  c.j = c.distortion + lambda * c.bits;
}

// Setting either precision key means coding by hand: Quality derives nothing.
bool codedByHand(const IsSetFunction& isSet) {
  return isSet("GridBits") || isSet("MotionQuantStep");
}

bool keyframeKeysSet(const IsSetFunction& isSet) {
  return isSet("KeyframeLambda") || isSet("KeyframeCount") || isSet("KeyframeMaxError");
}

}  // namespace

bool qualityCodesBMeshes(const EncoderParams& params, const IsSetFunction& isSet) {
  return params.quality >= 0 && !codedByHand(isSet) && params.pmeshMode == PMeshMode::kD3dmc &&
         !isSet("BMeshGap") && !keyframeKeysSet(isSet);
}

size_t qualityTrialFrames(const EncoderParams& params, size_t frameCount,
                          const IsSetFunction& isSet) {
  if (params.quality < 0 || params.pmeshMode == PMeshMode::kIntra || frameCount == 0 ||
      codedByHand(isSet))
    return 0;
  const size_t firstGom = static_cast<size_t>(params.goms(frameCount).front().second);
  return std::min<size_t>(kQualityTrialFrames, firstGom);
}

EncoderParams resolveQuality(const EncoderParams& params, const SequenceBounds& bounds,
                             const FrameSource& source, const IsSetFunction& isSet,
                             std::string* report) {
  if (params.quality < 0) return params;
  if (codedByHand(isSet)) {
    // Coding by hand: the precision keys as given, and nothing else derived.
    if (report)
      *report = "Quality " + std::to_string(params.quality) +
                " not applied: GridBits or MotionQuantStep is set, so every key is as given";
    return params;
  }
  EncoderParams p = params;
  if (!isSet("GridFit")) p.gridFit = GridFit::kObject;
  // B meshes before the trial, so that it measures the coding the encode will use.
  if (qualityCodesBMeshes(params, isSet)) p.bMeshGap = kQualityBMeshGap;
  const double precision = kQualityBitsAtZero + kQualityBitsPerStep * p.quality;
  // Δ, world units, over the size 2^GridBits - 1 steps span as gridFor() will use it.
  const double target = bounds.spannedSize(p.gridFit) / std::exp2(precision);
  const bool intra = p.pmeshMode == PMeshMode::kIntra;

  std::vector<Candidate> candidates;
  auto add = [&](int bits) {
    bits = std::clamp(bits, Grid::kMinBits, Grid::kMaxBits);
    for (const Candidate& c : candidates)
      if (c.gridBits == bits) return;
    const Grid grid = gridFor(bounds, bits, p.gridFit);
    const double q = target > 0 ? std::round(target / grid.step) : 1.0;
    candidates.push_back(
        {bits, intra ? 1 : static_cast<int>(std::clamp(q, 1.0, double(kMaxMotionQuantStep)))});
  };
  // At least 8 bits (the grid's minimum): below that the candidates differ in the quantiser.
  const int base = std::max(static_cast<int>(std::lround(precision)), Grid::kMinBits);
  if (intra) {
    add(base);  // no quantiser to trade against: the grid is the precision
  } else {
    for (int extra = 0; extra <= 3; ++extra)
      add(base + extra);
  }

  std::string measured;
  size_t best = 0;
  if (candidates.size() > 1) {
    // The trial: the first frames of the first GOM.
    const size_t count = qualityTrialFrames(p, source.count, isSet);
    // Named as the encode names them, so that an error the trial meets (it meets the real
    // encode's first errors first) reads the same.
    std::vector<Mesh> frames;
    std::vector<std::string> names;
    for (size_t k = 0; k < count; ++k) {
      frames.push_back(source.read(k));
      names.push_back(source.name ? source.name(k) : "frame " + std::to_string(k));
    }
    // The trial codes frames the real encode codes (and warns about) again.
    SilenceWarningsScope quiet;
    for (size_t i = 0; i < candidates.size(); ++i) {
      measure(candidates[i], p, bounds, frames, names, source.count, target);
      if (candidates[i].j < candidates[best].j) best = i;
      char text[160];
      std::snprintf(text, sizeof text, "%sGridBits %d MotionQuantStep %d: %.4g kbit, J %.6g",
                    i ? "; " : "", candidates[i].gridBits, candidates[i].step,
                    candidates[i].bits / 1000, candidates[i].j);
      measured += text;
    }
  }
  p.gridBits = candidates[best].gridBits;
  p.motionQuantStep = candidates[best].step;
  // Without B meshes (afxic, or BMeshGap 0): keyframes chosen by rate and distortion (never a
  // loss), unless the user chose them.
  if (!keyframeKeysSet(isSet) && p.bMeshGap == 0 && !intra) p.keyframeLambda = -1;
  if (report) {
    char text[256];
    std::snprintf(text, sizeof text,
                  "Quality %d: %.1f bits over the %s (step %.6g): GridFit %s, GridBits %d, "
                  "MotionQuantStep %d, Lambda %g, KeyframeLambda %g, BMeshGap %d",
                  p.quality, precision, p.gridFit == GridFit::kObject ? "object" : "sequence",
                  target, p.gridFit == GridFit::kObject ? "object" : "sequence", p.gridBits,
                  p.motionQuantStep, p.effectiveLambda(), p.keyframeLambda, p.bMeshGap);
    *report = text;
    if (!measured.empty())
      *report += " (chosen by coding the first frames with each candidate: " + measured + ")";
  }
  return p;
}

}  // namespace tdvo
