// The Quality knob (cfg key Quality; docs/options.md, "Quality"): one number from which the
// encoder derives the grid and the quantiser, so that users need not know how GridBits and
// MotionQuantStep trade against each other.
//
// Quality q in [0, 100] asks for a target step  Δ = S / 2^P  with  P = 5 + q / 10  bits over
// the object's size S (the largest extent of any one frame): q = 0 is about 5 bits, q = 50 10
// bits, q = 100 15 bits. The grid fits the object (GridFit object); the candidates are the grids
// of B .. B + 3 bits, B = max(round(P), 8), with MotionQuantStep = round(Δ / grid step), i.e.
// the same target step reached by a finer grid and a coarser quantiser. Which pays depends on
// the sequence (how much of the rate the I meshes take, how the motion clusters), so each
// candidate codes a few windows of the sequence (qualityTrialWindows(): up to
// kQualityTrialWindows runs of kQualityTrialFrames frames, one centred in each equal part of the
// sequence, each inside one GOM) and the candidate with the least J = D + λ·R, extrapolated
// from the windows' mean to the whole sequence, wins (D: squared distance of the decoded
// vertices to the input's, R: bits). λ is the slope the sequence shows: first the model's,
// (ln 2 / 6)·Δ² (an entropy-coded uniform quantiser of step Δ at high rate), picks a candidate;
// that candidate's grid with half its step is coded too, and the slope between the two, where
// the finer coding costs more rate for less distortion, is λ for the final choice. With d3dmc
// it then turns on B meshes (BMeshGap kQualityBMeshGap; else, or with BMeshGap 0, keyframes by
// rate and distortion). Keys the user sets are kept (GridFit, Lambda, KeyframeLambda, BMeshGap,
// BMeshQuantStep, BMeshLambdaGrowth); setting GridBits or MotionQuantStep means coding by hand:
// Quality then changes nothing.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "encoder/encoder_params.h"
#include "encoder/sequence_encoder.h"

namespace tdvo {

constexpr double kQualityBitsAtZero = 5.0;
constexpr double kQualityBitsPerStep = 0.1;  // bits of precision per Quality step
constexpr int kQualityBMeshGap = 8;          // BMeshGap under Quality (d3dmc)
// A trial window: two keyframes BMeshGap apart and the B meshes between them, as the encode
// codes them.
constexpr int kQualityTrialFrames = kQualityBMeshGap + 1;
constexpr int kQualityTrialWindows = 3;           // at most
constexpr int kQualityFramesPerTrialWindow = 64;  // one window per 64 frames, rounded up

// Whether the user set a cfg key (it then keeps its value).
using IsSetFunction = std::function<bool(const std::string& key)>;

// A run of frames the trial codes as one GOM: frames first .. first + count - 1.
struct TrialWindow {
  size_t first = 0, count = 0;
  bool operator==(const TrialWindow& o) const { return first == o.first && count == o.count; }
};

// The windows the trial of resolveQuality() reads from a sequence of `frameCount` frames: W =
// min(kQualityTrialWindows, ceil(frameCount / kQualityFramesPerTrialWindow)) windows, window i
// centred on frame floor((2i + 1) · frameCount / 2W) (the middle of the i-th of W equal parts),
// of kQualityTrialFrames frames or its GOM's length if shorter, and moved to lie inside that
// GOM. A sequence's first frames are often its stillest (an actor waits for the cue): a trial
// there favours a fine grid that the moving middle does not pay for. In frame order, apart
// (disjoint); empty when there is no trial (Quality < 0, coding by hand, or PMeshMode intra,
// whose one candidate needs none). A caller that read these frames already (the bounds pass)
// can keep them and serve them to the trial.
std::vector<TrialWindow> qualityTrialWindows(const EncoderParams& params, size_t frameCount,
                                             const IsSetFunction& isSet);

// Whether Quality turns B meshes on (BMeshGap kQualityBMeshGap): Quality on, not coding by
// hand, PMeshMode d3dmc, and neither BMeshGap nor a keyframe key set.
bool qualityCodesBMeshes(const EncoderParams& params, const IsSetFunction& isSet);

// `params` with Quality resolved (Quality < 0: `params` unchanged). `source` and `bounds` are the
// sequence's; the trial reads the frames of qualityTrialWindows() through `source`, each once.
// `report` (optional) receives one line saying what was chosen and what each candidate measured.
EncoderParams resolveQuality(const EncoderParams& params, const SequenceBounds& bounds,
                             const FrameSource& source, const IsSetFunction& isSet,
                             std::string* report = nullptr);

}  // namespace tdvo
