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

// What a candidate's trial codings add up to: per window, its I mesh (frame 0, with vertex
// order and attributes) and its P meshes (frames 1 .. n-1), bits and squared distances.
struct TrialSums {
  double intraBits = 0, intraError = 0;  // summed over the windows
  double interBits = 0, interError = 0;  // summed over the windows' P meshes
  double windows = 0, interFrames = 0;
  double lastError = 0;  // summed over the windows: the error of each window's last frame
  double frames = 0;     // summed over the windows: their frames
};

struct Candidate {
  int gridBits = 0;
  int step = 1;
  int iMeshStep = 1;  // IMeshQuantStep
  double j = std::numeric_limits<double>::infinity();
  double bits = 0, distortion = 0;  // extrapolated to the sequence
  TrialSums sums;                   // what its trial codings measured
};

// The I meshes of a sequence of `frames` frames: one per random access point (the first GOM of
// each run), every frame with PMeshMode intra.
size_t randomAccessGoms(const EncoderParams& p, size_t frames) {
  if (p.pmeshMode == PMeshMode::kIntra) return frames;
  return p.randomAccessRuns(p.goms(frames).size()).size();
}

// Codes `frames` (one trial window) as one GOM with candidate `c` and adds its rate and
// distortion to `sums`. Distances are in units of `unit` (Δ), so that J stays finite and ordered
// at any scale of the input (in world units, a squared distance overflows beyond 1e154 and
// underflows below 1e-154).
void codeWindow(TrialSums& sums, const Candidate& c, const EncoderParams& params,
                const SequenceBounds& bounds, const std::vector<Mesh>& frames,
                const std::vector<std::string>& names, double unit) {
  EncoderParams p = params;
  p.gridBits = c.gridBits;
  p.motionQuantStep = c.step;
  p.iMeshQuantStep = c.iMeshStep;
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
  sums.windows += 1;
  sums.intraBits += 8.0 * (coded.iMeshBytes + coded.orderBytes + coded.attributeBytes);
  sums.intraError += frameError[0];
  sums.interBits += 8.0 * coded.pMeshBytes;
  for (size_t k = 1; k < frames.size(); ++k)
    sums.interError += frameError[k];
  sums.interFrames += static_cast<double>(frames.size() - 1);
  sums.lastError += frameError.back();
  sums.frames += static_cast<double>(frames.size());
}

// Candidate `c`'s rate and distortion over a sequence of `sequenceFrames` frames of which
// `intraFrameCount` are I meshes (one per random access point), extrapolated from its trial
// codings: each I mesh as the windows' mean I mesh, each other frame as their mean P mesh.
void extrapolate(Candidate& c, const TrialSums& sums, size_t intraFrameCount,
                 size_t sequenceFrames) {
  const double intraFrames = static_cast<double>(intraFrameCount);
  const double interFrames = static_cast<double>(sequenceFrames) - intraFrames;
  c.bits = intraFrames * sums.intraBits / sums.windows;
  c.distortion = intraFrames * sums.intraError / sums.windows;
  if (sums.interFrames > 0 && interFrames > 0) {
    c.bits += interFrames * sums.interBits / sums.interFrames;
    c.distortion += interFrames * sums.interError / sums.interFrames;
  }
}

// "frame numbers 80-88, 166-174": the windows' frames numbered as the input numbers them
// (`first`: frame 0's number).
std::string describe(const std::vector<TrialWindow>& windows, long long first) {
  std::string text = "frame numbers ";
  for (size_t w = 0; w < windows.size(); ++w) {
    const long long a = first + static_cast<long long>(windows[w].first);
    text += (w ? ", " : "") + std::to_string(a);
    if (windows[w].count > 1)
      text += "-" + std::to_string(a + static_cast<long long>(windows[w].count) - 1);
  }
  return text;
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

std::vector<TrialWindow> qualityTrialWindows(const EncoderParams& params, size_t frameCount,
                                             const IsSetFunction& isSet) {
  std::vector<TrialWindow> windows;
  if (params.quality < 0 || params.pmeshMode == PMeshMode::kIntra || frameCount == 0 ||
      codedByHand(isSet))
    return windows;
  const GomList goms = params.goms(frameCount);
  const size_t per = static_cast<size_t>(kQualityFramesPerTrialWindow);
  const size_t count =
      std::min<size_t>(kQualityTrialWindows, (frameCount + per - 1) / per);  // >= 1
  for (size_t i = 0; i < count; ++i) {
    const size_t centre = (2 * i + 1) * frameCount / (2 * count);
    // The GOM holding the centre (the list covers frames 0 .. frameCount - 1 in order).
    auto gom = std::upper_bound(
        goms.begin(), goms.end(), centre,
        [](size_t f, const std::pair<int, int>& g) { return f < static_cast<size_t>(g.first); });
    --gom;
    const size_t gomFirst = static_cast<size_t>(gom->first);
    const size_t gomCount = static_cast<size_t>(gom->second);
    TrialWindow w;
    w.count = std::min<size_t>(kQualityTrialFrames, gomCount);
    w.first =
        std::clamp(centre - std::min(centre, w.count / 2), gomFirst, gomFirst + gomCount - w.count);
    // Apart from the previous window (they are, unless the GOMs are very uneven).
    if (!windows.empty() && w.first < windows.back().first + windows.back().count) continue;
    windows.push_back(w);
  }
  return windows;
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

  // The I meshes' step: as given, else 1 for the candidates, and the trial also tries the
  // chosen one's quantiser step.
  const bool iMeshStepSet = isSet("IMeshQuantStep");
  std::vector<Candidate> candidates;
  auto add = [&](int bits) {
    bits = std::clamp(bits, Grid::kMinBits, Grid::kMaxBits);
    for (const Candidate& c : candidates)
      if (c.gridBits == bits) return;
    const Grid grid = gridFor(bounds, bits, p.gridFit);
    const double q = target > 0 ? std::round(target / grid.step) : 1.0;
    Candidate c;
    c.gridBits = bits;
    c.step = intra ? 1 : static_cast<int>(std::clamp(q, 1.0, double(kMaxMotionQuantStep)));
    c.iMeshStep = iMeshStepSet ? p.iMeshQuantStep : 1;
    candidates.push_back(c);
  };
  // At least 8 bits (the grid's minimum): below that the candidates differ in the quantiser.
  const int base = std::max(static_cast<int>(std::lround(precision)), Grid::kMinBits);
  if (intra) {
    add(base);  // no quantiser to trade against: the grid is the precision
  } else {
    for (int extra = 0; extra <= 3; ++extra)
      add(base + extra);
  }

  std::string measured, windowText, slopeText, roundedText, stopped;
  int iMeshStep = candidates[0].iMeshStep;  // the chosen candidate's, or its quantiser step
  size_t best = 0;
  double lambda = 0;  // in units of Δ²
  if (candidates.size() > 1) {
    // The trial: every candidate codes every window, its frames named as the encode names them.
    const std::vector<TrialWindow> windows = qualityTrialWindows(p, source.count, isSet);
    std::vector<std::vector<Mesh>> frames(windows.size());
    std::vector<std::vector<std::string>> names(windows.size());
    for (size_t w = 0; w < windows.size(); ++w)
      for (size_t k = windows[w].first; k < windows[w].first + windows[w].count; ++k) {
        frames[w].push_back(source.read(k));
        names[w].push_back(source.name ? source.name(k) : "frame " + std::to_string(k));
      }
    // The trial codes frames the real encode codes (and warns about) again.
    SilenceWarningsScope quiet;
    const double unit = target > 0 ? target : 1.0;
    // The sequence's I meshes, the same for every candidate (goms() reads a GOMListFile).
    const size_t intraFrames = std::min(randomAccessGoms(p, source.count), source.count);
    auto trial = [&](Candidate& c) {
      c.sums = TrialSums();
      for (size_t w = 0; w < windows.size(); ++w)
        codeWindow(c.sums, c, p, bounds, frames[w], names[w], unit);
      extrapolate(c, c.sums, intraFrames, source.count);
    };
    auto choose = [&](double slope) {
      best = 0;
      for (size_t i = 0; i < candidates.size(); ++i) {
        candidates[i].j = candidates[i].distortion + slope * candidates[i].bits;
        if (candidates[i].j < candidates[best].j) best = i;
      }
    };
    // λ: first the model's, (ln 2 / 6)·Δ² (in units of Δ²; 0 when the object has no size, and
    // only the distortion counts), picks a candidate; then the slope between it and its grid at
    // half its step, as the sequence shows it, decides. An empirical rule, chosen on the
    // brute-force hull (tools/rd/quality_lambda_study.py; docs/options.md, "Quality"): the
    // model's λ, the tangent of a high-rate quantiser, is 2 to 4 times smaller than the slopes
    // measured at the shared sequences' Quality points, and with it the choice fell off the hull
    // by up to 4 % at coarse steps.
    try {
      for (Candidate& c : candidates)
        trial(c);
      lambda = target > 0 ? std::log(2.0) / 6.0 : 0.0;
      choose(lambda);
      if (lambda > 0 && candidates[best].step > 1) {
        Candidate finer = candidates[best];
        finer.step /= 2;
        trial(finer);
        const Candidate& at = candidates[best];
        char text[200];
        std::snprintf(text, sizeof text,
                      "; slope from GridBits %d MotionQuantStep %d: %.6g kbit, D %.6g",
                      finer.gridBits, finer.step, finer.bits / 1000, finer.distortion);
        slopeText = text;
        if (finer.bits > at.bits && finer.distortion < at.distortion) {
          lambda = (at.distortion - finer.distortion) / (finer.bits - at.bits);
          choose(lambda);
        }
      }
      // Then the chosen candidate's I mesh rounded to its quantiser step (IMeshQuantStep =
      // MotionQuantStep), kept when it lowers J: it saves I-mesh bits, but the P meshes after
      // it must correct its error, which pays at fine steps and not at coarse ones
      // (docs/options.md). A window holds an I mesh and the frames after it, so its difference
      // from the candidate's window counts once per I mesh of the sequence; what of the
      // rounding the window's last frame (a keyframe) still carries is carried on to the
      // frames after the window, counted at that frame's difference (no further bits).
      if (!iMeshStepSet && candidates[best].step > 1) {
        const Candidate& base = candidates[best];
        Candidate rounded = base;
        rounded.iMeshStep = rounded.step;
        trial(rounded);
        const TrialSums& b = base.sums;
        const TrialSums& r = rounded.sums;
        const double perIMesh = static_cast<double>(intraFrames) / b.windows;
        const double after = std::max(
            0.0, static_cast<double>(source.count) - perIMesh * b.frames);  // frames after them
        rounded.bits =
            base.bits + perIMesh * (r.intraBits + r.interBits - b.intraBits - b.interBits);
        rounded.distortion =
            base.distortion +
            perIMesh * (r.intraError + r.interError - b.intraError - b.interError) +
            after * (r.lastError - b.lastError) / b.windows;
        rounded.j = rounded.distortion + lambda * rounded.bits;
        char text[200];
        std::snprintf(text, sizeof text,
                      "; GridBits %d MotionQuantStep %d IMeshQuantStep %d: %.6g kbit, D %.6g, J "
                      "%.6g",
                      rounded.gridBits, rounded.step, rounded.iMeshStep, rounded.bits / 1000,
                      rounded.distortion, rounded.j);
        roundedText = text;
        if (rounded.j < base.j) iMeshStep = rounded.iMeshStep;
      }
    } catch (const Error& e) {
      // A window is coded as a GOM of its own, so an input error (a frame whose connectivity
      // differs from the others') would name the window's first frame as the GOM's. Each window
      // lies inside one GOM of the encode, which meets the same frames and says it with its own
      // GOM: the trial stops, its first candidate stands, and the report says why.
      best = 0;
      iMeshStep = candidates[0].iMeshStep;
      stopped = e.what();
    }
    for (size_t i = 0; i < candidates.size() && stopped.empty(); ++i) {
      char text[160];
      std::snprintf(text, sizeof text,
                    "%sGridBits %d MotionQuantStep %d: %.6g kbit, D %.6g, J %.6g", i ? "; " : "",
                    candidates[i].gridBits, candidates[i].step, candidates[i].bits / 1000,
                    candidates[i].distortion, candidates[i].j);
      measured += text;
    }
    windowText = describe(windows, p.firstFrame);
  }
  p.gridBits = candidates[best].gridBits;
  p.motionQuantStep = candidates[best].step;
  p.iMeshQuantStep = iMeshStep;
  // Without B meshes (afxic, or BMeshGap 0): keyframes chosen by rate and distortion (never a
  // loss), unless the user chose them.
  if (!keyframeKeysSet(isSet) && p.bMeshGap == 0 && !intra) p.keyframeLambda = -1;
  if (report) {
    char text[256];
    std::snprintf(text, sizeof text,
                  "Quality %d: %.1f bits over the %s (step %.6g): GridFit %s, GridBits %d, "
                  "MotionQuantStep %d, IMeshQuantStep %d, Lambda %g, KeyframeLambda %g, "
                  "BMeshGap %d",
                  p.quality, precision, p.gridFit == GridFit::kObject ? "object" : "sequence",
                  target, p.gridFit == GridFit::kObject ? "object" : "sequence", p.gridBits,
                  p.motionQuantStep, p.iMeshQuantStep, p.effectiveLambda(), p.keyframeLambda,
                  p.bMeshGap);
    *report = text;
    if (!stopped.empty())
      *report += " (the trial, coding " + windowText + ", stopped: " + stopped + ")";
    if (!measured.empty()) {
      std::snprintf(text, sizeof text, "%.6g", lambda);
      *report += " (chosen by coding " + windowText + " with each candidate, J = D + " + text +
                 " R: " + measured + slopeText + roundedText + ")";
    }
  }
  return p;
}

}  // namespace tdvo
