// The grid that fits the object (Grid::fitObject, GridFit object) and the Quality knob
// (encoder/quality.h): candidates, trial, the keys the user set, and what the Encoder does.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "common/core/error.h"
#include "common/core/grid.h"
#include "encoder/encoder.h"
#include "encoder/quality.h"
#include "encoder/sequence_encoder.h"
#include "tools/eval/sample_mesh.h"

namespace tdvo {
namespace {

TEST(GridFitObject, StepFromTheObjectBitsFromThePath) {
  // An object of size 1 walking 10 along x: 8 bits over the object is a step of 1/255, and the
  // path of 10 needs 2550 steps, 12 bits.
  const Grid g = Grid::fitObject({0, 0, 0}, {10, 1, 1}, 1.0, 8);
  EXPECT_EQ(g.step, 1.0 / 255);
  EXPECT_EQ(g.bits, 12);
  EXPECT_EQ(g.origin, (Vec3d{0, 0, 0}));
  EXPECT_EQ(g.quantise(Vec3d{10, 1, 1}), (Vec3i{2550, 255, 255}));
}

TEST(GridFitObject, AnObjectThatSpansItsPathIsTheSequenceGrid) {
  const Grid a = Grid::fitObject({0, 0, 0}, {2, 1, 1}, 2.0, 10);
  const Grid b = Grid::fromBounds({0, 0, 0}, {2, 1, 1}, 10);
  EXPECT_EQ(a.step, b.step);
  EXPECT_EQ(a.bits, b.bits);
}

TEST(GridFitObject, APathTooLongForTwentyBitsGetsTheTwentyBitSequenceGrid) {
  const Grid g = Grid::fitObject({0, 0, 0}, {1e6, 1, 1}, 1.0, 12);
  const Grid s = Grid::fromBounds({0, 0, 0}, {1e6, 1, 1}, Grid::kMaxBits);
  EXPECT_EQ(g.bits, Grid::kMaxBits);
  EXPECT_EQ(g.step, s.step);
}

TEST(GridFitObject, SpannedSizeIsWhatTheGridSteps) {
  // The object's size with GridFit object (as long as it is smaller than the box), else the
  // box's largest extent: what 2^bits - 1 steps of fitObject / fromBounds cover.
  const Vec3d lo{0, 0, 0}, hi{10, 1, 1};
  EXPECT_EQ(Grid::largestExtent(lo, hi), 10.0);
  EXPECT_EQ(Grid::spannedSize(lo, hi, 1.0, GridFit::kObject), 1.0);
  EXPECT_EQ(Grid::spannedSize(lo, hi, 1.0, GridFit::kSequence), 10.0);
  EXPECT_EQ(Grid::spannedSize(lo, hi, 0.0, GridFit::kObject), 10.0);
  EXPECT_EQ(Grid::spannedSize(lo, hi, 1.0, GridFit::kObject) / 255,
            Grid::fitObject(lo, hi, 1.0, 8).step);
  EXPECT_EQ(Grid::spannedSize(lo, hi, 1.0, GridFit::kSequence) / 255,
            Grid::fromBounds(lo, hi, 8).step);
}

// The blob moved along x by `speed` of its size per frame.
std::vector<Mesh> walkingBlob(int frames, double speed) {
  std::vector<Mesh> seq = deformingBlob(2, frames);
  for (size_t k = 0; k < seq.size(); ++k)
    for (Vec3d& p : seq[k].positions)
      p[0] += speed * 2.0 * static_cast<double>(k);
  return seq;
}

FrameSource sourceOf(const std::vector<Mesh>& frames) {
  FrameSource s;
  s.count = frames.size();
  s.read = [&frames](size_t k) { return frames[k]; };
  s.name = [](size_t k) { return "frame " + std::to_string(k); };
  return s;
}

// sourceOf(frames) counting each frame's reads in `reads` (one counter per frame).
FrameSource countingSourceOf(const std::vector<Mesh>& frames,
                             std::vector<std::atomic<int>>& reads) {
  FrameSource s = sourceOf(frames);
  s.read = [&frames, &reads](size_t k) {
    ++reads[k];
    return frames[k];
  };
  return s;
}

TEST(GridFitObject, TheEncoderKeepsPrecisionOnAWalkingObject) {
  const std::vector<Mesh> frames = walkingBlob(6, 1.0);
  const FrameSource source = sourceOf(frames);
  const SequenceBounds b = boundsOfSequence(source);
  const Grid object = gridFor(b, 10, GridFit::kObject);
  const Grid sequence = gridFor(b, 10, GridFit::kSequence);
  EXPECT_GT(object.bits, 10);  // the path needs more than the object
  EXPECT_LT(object.step, sequence.step / 3);
  // Frame 0's largest extent spans about 2^10 - 1 steps.
  EXPECT_NEAR(b.objectExtent / object.step, 1023.0, 1e-6);
}

struct Resolved {
  EncoderParams params;
  std::string report;
};

Resolved resolve(const std::vector<Mesh>& frames, int quality, std::set<std::string> set = {},
                 EncoderParams p = {}) {
  p.quality = quality;
  p.gomSize = static_cast<int>(frames.size());
  const FrameSource source = sourceOf(frames);
  Resolved r;
  r.params = resolveQuality(
      p, boundsOfSequence(source), source,
      [&set](const std::string& key) { return set.count(key) > 0; }, &r.report);
  return r;
}

TEST(Quality, OffLeavesEveryKeyAsItIs) {
  EncoderParams p;
  p.gridBits = 9;
  p.motionQuantStep = 3;
  const Resolved r = resolve(walkingBlob(4, 0.1), -1, {}, p);
  EXPECT_EQ(r.params.gridBits, 9);
  EXPECT_EQ(r.params.motionQuantStep, 3);
  EXPECT_EQ(r.params.gridFit, GridFit::kSequence);
  EXPECT_TRUE(r.report.empty());
}

TEST(Quality, ChoosesTheCandidateOfLeastJAndReachesTheTargetStep) {
  const std::vector<Mesh> frames = walkingBlob(10, 0.05);
  for (int q : {0, 50, 90}) {
    const Resolved r = resolve(frames, q);
    EXPECT_EQ(r.params.gridFit, GridFit::kObject);
    // The target step: 2^-(5 + q/10) of the object's size, as grid step times quantiser.
    const SequenceBounds b = boundsOfSequence(sourceOf(frames));
    const Grid grid = gridFor(b, r.params.gridBits, GridFit::kObject);
    const double target = b.objectExtent / std::exp2(5 + q / 10.0);
    if (r.params.gridBits > Grid::kMinBits) {
      EXPECT_NEAR(grid.step * r.params.motionQuantStep / target, 1.0, 0.35) << r.report;
    }
    // The report lists each candidate (and the chosen one with its I meshes rounded to its
    // step, "IMeshQuantStep s"); the chosen one has the least J.
    EXPECT_NE(r.report.find("GridBits " + std::to_string(r.params.gridBits)), std::string::npos);
    double least = 1e300, chosen = -1;
    for (size_t at = r.report.find(", J ", r.report.find(" R: ")); at != std::string::npos;
         at = r.report.find(", J ", at + 1)) {
      const double j = std::stod(r.report.substr(at + 4));
      const size_t name = r.report.rfind("GridBits ", at);
      const int bits = std::stoi(r.report.substr(name + 9));
      const std::string entry = r.report.substr(name, at - name);
      const size_t rounded = entry.find("IMeshQuantStep ");
      const int iMeshStep =
          rounded == std::string::npos ? 1 : std::stoi(entry.substr(rounded + 15));
      least = std::min(least, j);
      if (bits == r.params.gridBits && iMeshStep == r.params.iMeshQuantStep) chosen = j;
    }
    ASSERT_LT(least, 1e300) << r.report;  // a trial was made
    EXPECT_EQ(chosen, least) << r.report;
  }
}

// The numbers after `key` in `text` from `at` on.
double numberAfter(const std::string& text, const std::string& key, size_t at = 0) {
  const size_t found = text.find(key, at);
  if (found == std::string::npos) return std::nan("");
  return std::stod(text.substr(found + key.size()));
}

TEST(Quality, LambdaIsTheSlopeMeasuredOnTheFinerSideOfTheModelsChoice) {
  // The report gives λ, each candidate's extrapolated rate R (kbit), distortion D and J, and
  // the coding that measured the slope: the model's choice (least D + (ln 2 / 6) R) with half
  // its step. Where that coding is cheaper in D and dearer in R, λ is the slope between the
  // two, and the choice is the least D + λ R.
  const std::vector<Mesh> frames = walkingBlob(10, 0.05);
  const double model = std::log(2.0) / 6.0;
  bool measuredOnce = false;
  for (int q : {0, 10, 20, 30, 50}) {
    const Resolved r = resolve(frames, q);
    const double lambda = numberAfter(r.report, "J = D + ");
    ASSERT_FALSE(std::isnan(lambda)) << r.report;
    struct Point {
      int bits, step;
      double rate, d, j;
    };
    std::vector<Point> points;
    for (size_t at = r.report.find("GridBits ", r.report.find("J = D + "));
         at != std::string::npos && at < r.report.find("; slope");
         at = r.report.find("GridBits ", at + 1)) {
      Point p{std::stoi(r.report.substr(at + 9)),
              static_cast<int>(numberAfter(r.report, "MotionQuantStep ", at)),
              1000 * numberAfter(r.report, ": ", at), numberAfter(r.report, "D ", at),
              numberAfter(r.report, "J ", at)};
      points.push_back(p);
    }
    ASSERT_GE(points.size(), 2u) << r.report;
    const Point* chosen = nullptr;
    const Point* byModel = &points[0];
    for (const Point& p : points) {
      EXPECT_NEAR(p.j, p.d + lambda * p.rate, 1e-5 * p.j + 1e-3 * lambda) << r.report;
      if (p.bits == r.params.gridBits) chosen = &p;
      if (p.d + model * p.rate < byModel->d + model * byModel->rate) byModel = &p;
    }
    ASSERT_NE(chosen, nullptr) << r.report;
    for (const Point& p : points)
      EXPECT_LE(chosen->j, p.j) << r.report;
    const size_t slope = r.report.find("; slope from GridBits ");
    if (byModel->step == 1) {
      EXPECT_EQ(slope, std::string::npos) << r.report;
      EXPECT_NEAR(lambda, model, 1e-6) << r.report;
      continue;
    }
    ASSERT_NE(slope, std::string::npos) << r.report;
    EXPECT_EQ(std::stoi(r.report.substr(slope + 22)), byModel->bits) << r.report;
    EXPECT_EQ(static_cast<int>(numberAfter(r.report, "MotionQuantStep ", slope)), byModel->step / 2)
        << r.report;
    const double finerRate = 1000 * numberAfter(r.report, ": ", slope);
    const double finerD = numberAfter(r.report, "D ", slope);
    if (finerRate > byModel->rate && finerD < byModel->d) {
      EXPECT_NEAR(lambda, (byModel->d - finerD) / (finerRate - byModel->rate), 1e-3 * lambda)
          << r.report;
      measuredOnce = measuredOnce || std::abs(lambda - model) > 0.01 * model;
    } else {
      EXPECT_NEAR(lambda, model, 1e-6) << r.report;
    }
  }
  EXPECT_TRUE(measuredOnce);  // the case is not vacuous: some Quality measured its own λ
}

TEST(Quality, TheChoiceDoesNotDependOnTheScale) {
  // Scaled by powers of two, the frames quantise to the same integers on a scaled grid, so the
  // trial codes the same streams: the same choice and the same J (in units of the target
  // step), also where a squared distance in world units overflows (2^600) or underflows
  // (2^-600).
  const std::vector<Mesh> frames = walkingBlob(8, 0.05);
  const Resolved reference = resolve(frames, 50);
  const size_t trial = reference.report.find("(chosen");
  ASSERT_NE(trial, std::string::npos) << reference.report;
  for (int exponent : {600, -600}) {
    std::vector<Mesh> scaled = frames;
    for (Mesh& m : scaled)
      for (Vec3d& position : m.positions)
        for (double& c : position)
          c = std::ldexp(c, exponent);
    const Resolved r = resolve(scaled, 50);
    EXPECT_EQ(r.params.gridBits, reference.params.gridBits) << r.report;
    EXPECT_EQ(r.params.motionQuantStep, reference.params.motionQuantStep) << r.report;
    EXPECT_EQ(r.report.substr(r.report.find("(chosen")), reference.report.substr(trial))
        << "2^" << exponent;
  }
}

TEST(Quality, HigherQualityIsAFinerStep) {
  const std::vector<Mesh> frames = walkingBlob(8, 0.05);
  double previous = 1e300;
  for (int q : {0, 30, 60, 90}) {
    const Resolved r = resolve(frames, q);
    const Grid grid =
        gridFor(boundsOfSequence(sourceOf(frames)), r.params.gridBits, r.params.gridFit);
    const double step = grid.step * r.params.motionQuantStep;
    EXPECT_LT(step, previous) << "Quality " << q << ": " << r.report;
    previous = step;
  }
}

// After λ, the chosen candidate is coded once more with its I meshes rounded to its quantiser
// step (IMeshQuantStep = MotionQuantStep), kept when its J is lower; not tried at step 1 or
// when the user set IMeshQuantStep.
TEST(Quality, TriesTheIMeshRoundedToTheQuantiserStep) {
  const std::vector<Mesh> frames = walkingBlob(20, 0.02);
  bool tried = false;
  for (int q : {20, 40, 60, 80}) {
    const Resolved r = resolve(frames, q);
    const size_t at =
        r.report.find(" IMeshQuantStep " + std::to_string(r.params.motionQuantStep) + ": ");
    if (r.params.motionQuantStep == 1) {
      EXPECT_EQ(at, std::string::npos) << r.report;
      EXPECT_EQ(r.params.iMeshQuantStep, 1);
      continue;
    }
    ASSERT_NE(at, std::string::npos) << r.report;
    const double roundedJ = numberAfter(r.report, "J ", at);
    // The base: the entry of the chosen grid among the candidates (before the slope's coding).
    const size_t base =
        r.report.find("GridBits " + std::to_string(r.params.gridBits) + " MotionQuantStep " +
                      std::to_string(r.params.motionQuantStep) + ": ");
    ASSERT_LT(base, r.report.find("; slope")) << r.report;
    const double baseJ = numberAfter(r.report, "J ", base);
    EXPECT_EQ(r.params.iMeshQuantStep, roundedJ < baseJ ? r.params.motionQuantStep : 1) << r.report;
    tried = true;
    // The chosen parameters are the encode's: its summary line says IMeshQuantStep.
    EXPECT_NE(r.report.find("IMeshQuantStep " + std::to_string(r.params.iMeshQuantStep) + ","),
              std::string::npos)
        << r.report;
  }
  EXPECT_TRUE(tried);  // not vacuous: some Quality chose a step above 1
  // Set by the user: kept, and not tried.
  EncoderParams p;
  p.iMeshQuantStep = 3;
  const Resolved r = resolve(frames, 60, {"IMeshQuantStep"}, p);
  EXPECT_EQ(r.params.iMeshQuantStep, 3);
  EXPECT_EQ(r.report.find(" IMeshQuantStep " + std::to_string(r.params.motionQuantStep) + ": "),
            std::string::npos)
      << r.report;
}

TEST(Quality, KeysTheUserSetAreKept) {
  const std::vector<Mesh> frames = walkingBlob(6, 0.05);
  // GridBits or MotionQuantStep set: coding by hand, nothing derived.
  EncoderParams p;
  p.gridBits = 14;
  Resolved r = resolve(frames, 50, {"GridBits"}, p);
  EXPECT_EQ(r.params.gridBits, 14);
  EXPECT_EQ(r.params.motionQuantStep, 1);
  EXPECT_EQ(r.params.gridFit, GridFit::kSequence);
  EXPECT_NE(r.report.find("not applied"), std::string::npos);
  p = {};
  p.motionQuantStep = 2;
  r = resolve(frames, 50, {"MotionQuantStep"}, p);
  EXPECT_EQ(r.params.motionQuantStep, 2);
  EXPECT_EQ(r.params.gridBits, 12);
  // GridFit set: kept, the rest chosen.
  p = {};
  p.gridFit = GridFit::kSequence;
  r = resolve(frames, 50, {"GridFit"}, p);
  EXPECT_EQ(r.params.gridFit, GridFit::kSequence);
  EXPECT_NE(r.report.find("chosen by coding"), std::string::npos);
}

// B meshes (BMeshGap 8) with d3dmc unless the user chose the keyframes or codes by hand; with
// afxic, or BMeshGap 0, keyframes by rate and distortion. The trial codes the B meshes too: the
// same choice whether BMeshGap 8 is Quality's or the user's.
TEST(Quality, CodesBMeshesUnlessTheKeyframesAreChosen) {
  const std::vector<Mesh> frames = walkingBlob(9, 0.05);
  Resolved r = resolve(frames, 50);
  EXPECT_EQ(r.params.bMeshGap, kQualityBMeshGap);
  EXPECT_EQ(r.params.keyframeLambda, 0);
  EncoderParams p;
  p.bMeshGap = kQualityBMeshGap;
  const Resolved given = resolve(frames, 50, {"BMeshGap"}, p);
  EXPECT_EQ(given.report, r.report);
  p = {};
  p.keyframeCount = 3;
  r = resolve(frames, 50, {"KeyframeCount"}, p);
  EXPECT_EQ(r.params.bMeshGap, 0);
  EXPECT_EQ(r.params.keyframeLambda, 0);
  p = {};
  r = resolve(frames, 50, {"BMeshGap"}, p);  // BMeshGap 0 set: the keyframe choice instead
  EXPECT_EQ(r.params.bMeshGap, 0);
  EXPECT_EQ(r.params.keyframeLambda, -1);
  p = {};
  p.pmeshMode = PMeshMode::kAfxic;
  r = resolve(frames, 50, {"PMeshMode"}, p);
  EXPECT_EQ(r.params.bMeshGap, 0);
  EXPECT_EQ(r.params.keyframeLambda, -1);
  p = {};
  p.gridBits = 12;
  r = resolve(frames, 50, {"GridBits"}, p);  // by hand
  EXPECT_EQ(r.params.bMeshGap, 0);
}

// BMeshQuantStep alone is for Quality's B meshes; where none are coded it is an error (C55),
// not a key without effect.
TEST(Quality, BMeshQuantStepWithoutBMeshesIsRefused) {
  Encoder quality;
  quality.set("BMeshQuantStep", "16");
  EXPECT_NO_THROW(quality.params());
  Encoder manual;
  manual.set("BMeshQuantStep", "16");
  manual.set("Quality", "-1");
  EXPECT_THROW(manual.params(), Error);
  Encoder gap;
  gap.set("BMeshQuantStep", "16");
  gap.set("Quality", "-1");
  gap.set("BMeshGap", "4");
  EXPECT_NO_THROW(gap.params());
}

TEST(Quality, IsDeterministic) {
  const std::vector<Mesh> frames = walkingBlob(9, 0.05);
  const Resolved a = resolve(frames, 40), b = resolve(frames, 40);
  EXPECT_EQ(a.report, b.report);
  EXPECT_EQ(a.params.gridBits, b.params.gridBits);
  EXPECT_EQ(a.params.motionQuantStep, b.params.motionQuantStep);
}

TEST(Quality, TheEncoderUsesItsChoiceAndSaysSo) {
  const std::vector<Mesh> frames = walkingBlob(8, 0.05);
  Encoder defaults;
  defaults.set("GOMSize", "8");
  const EncodedSequence a = defaults.encode(frames);
  EXPECT_NE(defaults.qualityReport().find("Quality 50"), std::string::npos);
  const Resolved r = resolve(frames, 50);
  EXPECT_EQ(defaults.grid().step,
            gridFor(boundsOfSequence(sourceOf(frames)), r.params.gridBits, GridFit::kObject).step);
  Encoder manual;
  manual.set("GOMSize", "8");
  manual.set("Quality", "-1");
  manual.encode(frames);
  EXPECT_TRUE(manual.qualityReport().empty());
  EXPECT_EQ(manual.grid().bits, 12);  // GridBits' default over the sequence's box
}

TEST(Quality, TrialWindowsAreCentredInEqualPartsEachInsideOneGom) {
  const IsSetFunction none = [](const std::string&) { return false; };
  EncoderParams p;
  p.quality = 50;
  // samba's layout: 175 frames in GOMs of 25: three windows of 9 frames around frames 29, 87
  // and 145, moved into their GOMs (25-49, 75-99, 125-149).
  p.gomSize = 25;
  EXPECT_EQ(qualityTrialWindows(p, 175, none),
            (std::vector<TrialWindow>{{25, 9}, {83, 9}, {141, 9}}));
  // Every layout: ceil(n / 64) windows up to 3, each containing its part's middle frame, of 9
  // frames or its whole GOM, inside that GOM, apart and in order.
  for (int gomSize : {1, 2, 5, 8, 9, 25, 100, 1000})
    for (size_t n = 1; n <= 260; ++n) {
      p.gomSize = gomSize;
      const std::vector<TrialWindow> windows = qualityTrialWindows(p, n, none);
      const size_t expected = std::min<size_t>(3, (n + 63) / 64);
      ASSERT_EQ(windows.size(), expected) << n << " frames, GOMs of " << gomSize;
      for (size_t w = 0; w < windows.size(); ++w) {
        const TrialWindow& t = windows[w];
        const size_t gomFirst = t.first / static_cast<size_t>(gomSize) * gomSize;
        const size_t gomCount = std::min<size_t>(gomSize, n - gomFirst);
        EXPECT_EQ(t.count, std::min<size_t>(9, gomCount)) << n << " " << gomSize << " " << w;
        EXPECT_LE(t.first + t.count, gomFirst + gomCount) << n << " " << gomSize << " " << w;
        if (w > 0) {
          EXPECT_GE(t.first, windows[w - 1].first + windows[w - 1].count) << n << " " << gomSize;
        }
        const size_t centre = (2 * w + 1) * n / (2 * expected);
        EXPECT_TRUE(t.first <= centre && centre < t.first + t.count)
            << n << " " << gomSize << " " << w;
      }
    }
  // No trial: Quality off, coding by hand, every frame intra.
  p.gomSize = 25;
  p.quality = -1;
  EXPECT_TRUE(qualityTrialWindows(p, 175, none).empty());
  p.quality = 50;
  EXPECT_TRUE(qualityTrialWindows(p, 175, [](const std::string& key) {
                return key == "MotionQuantStep";
              }).empty());
  p.pmeshMode = PMeshMode::kIntra;
  EXPECT_TRUE(qualityTrialWindows(p, 175, none).empty());
}

TEST(Quality, TheTrialCodesItsWindowsReadingEachFrameOnce) {
  // 140 frames in GOMs of 20: windows around frames 23, 70 and 116 (the last moved to end with
  // its GOM, 100-119); resolveQuality reads those frames once each and no other, and names
  // them in its report by their frame numbers.
  const std::vector<Mesh> frames = walkingBlob(140, 0.01);
  std::vector<std::atomic<int>> reads(frames.size());
  const FrameSource counted = countingSourceOf(frames, reads);
  EncoderParams p;
  p.quality = 50;
  p.gomSize = 20;
  p.firstFrame = 1000;
  std::string report;
  resolveQuality(
      p, boundsOfSequence(sourceOf(frames)), counted, [](const std::string&) { return false; },
      &report);
  const std::vector<TrialWindow> windows =
      qualityTrialWindows(p, frames.size(), [](const std::string&) { return false; });
  ASSERT_EQ(windows, (std::vector<TrialWindow>{{20, 9}, {66, 9}, {111, 9}}));
  for (size_t k = 0; k < frames.size(); ++k) {
    bool inWindow = false;
    for (const TrialWindow& w : windows)
      inWindow = inWindow || (k >= w.first && k < w.first + w.count);
    EXPECT_EQ(reads[k], inWindow ? 1 : 0) << "frame " << k;
  }
  EXPECT_NE(report.find("chosen by coding frame numbers 1020-1028, 1066-1074, 1111-1119 "),
            std::string::npos)
      << report;
}

TEST(Quality, ATrialThatMeetsAnInputErrorStopsAndSaysSo) {
  // Frame 5 of a GOM of 10 has a vertex fewer: the trial's window (frames 1 .. 9) cannot be
  // coded. resolveQuality does not throw the window's version of the error (the encode reports
  // it with its own GOM); its first candidate stands and the report says why.
  std::vector<Mesh> frames = walkingBlob(10, 0.05);
  frames[5].positions.pop_back();
  frames[5].triangles.clear();
  const Resolved r = resolve(frames, 50);
  EXPECT_NE(r.report.find("(the trial, coding frame numbers 1-9, stopped: "), std::string::npos)
      << r.report;
  EXPECT_EQ(r.report.find("chosen by coding"), std::string::npos) << r.report;
  const Resolved fine = resolve(walkingBlob(10, 0.05), 50);
  const size_t first = fine.report.find("GridBits ", fine.report.find(" R: "));
  ASSERT_NE(first, std::string::npos) << fine.report;
  EXPECT_EQ(r.params.gridBits, std::stoi(fine.report.substr(first + 9))) << r.report;
}

TEST(Quality, TheTrialReadsNoFrameAThirdTime) {
  // The Encoder reads every frame twice (bounds, then GOM by GOM; frame 0 once more for
  // encodeSequence's look at its attributes); the trial codes its windows' frames (20 .. 28,
  // 66 .. 74 and 111 .. 119 here, with gaps between them) kept from the first pass.
  const std::vector<Mesh> frames = walkingBlob(140, 0.01);
  std::vector<std::atomic<int>> reads(frames.size());
  const FrameSource counted = countingSourceOf(frames, reads);
  Encoder encoder;
  encoder.set("GOMSize", "20");
  encoder.encode(counted);
  EXPECT_NE(encoder.qualityReport().find("chosen by coding frame numbers 20-28, 66-74, 111-119 "),
            std::string::npos)
      << encoder.qualityReport();
  for (size_t k = 0; k < frames.size(); ++k)
    EXPECT_EQ(reads[k], k == 0 ? 3 : 2) << "frame " << k;
}

}  // namespace
}  // namespace tdvo
