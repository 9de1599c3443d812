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
// candidate codes the first frames of the sequence (at most kQualityTrialFrames, in the first
// GOM) and the candidate with the least J = D + λ·R, extrapolated to the whole sequence, wins
// (D: squared distance of the decoded vertices to the input's, R: bits; λ = (ln 2 / 6)·Δ², the
// slope of an entropy-coded uniform quantiser of step Δ). With d3dmc it then turns on B meshes
// (BMeshGap kQualityBMeshGap; else, or with BMeshGap 0, keyframes by rate and distortion). Keys
// the user sets are kept (GridFit, Lambda, KeyframeLambda, BMeshGap, BMeshQuantStep,
// BMeshLambdaGrowth); setting GridBits or MotionQuantStep means coding by hand: Quality then
// changes nothing.
#pragma once

#include <functional>
#include <string>

#include "encoder/encoder_params.h"
#include "encoder/sequence_encoder.h"

namespace tdvo {

constexpr int kQualityTrialFrames = 8;
constexpr double kQualityBitsAtZero = 5.0;
constexpr double kQualityBitsPerStep = 0.1;  // bits of precision per Quality step
constexpr int kQualityBMeshGap = 8;          // BMeshGap under Quality (d3dmc)

// Whether the user set a cfg key (it then keeps its value).
using IsSetFunction = std::function<bool(const std::string& key)>;

// How many frames the trial of resolveQuality() reads, the first of the sequence of `frameCount`
// frames: kQualityTrialFrames at most, and no more than the first GOM; 0 when it has no trial
// (Quality < 0, coding by hand, or PMeshMode intra, whose one candidate needs none). A caller
// that read them already (the bounds pass) can keep them and serve them to the trial.
size_t qualityTrialFrames(const EncoderParams& params, size_t frameCount,
                          const IsSetFunction& isSet);

// Whether Quality turns B meshes on (BMeshGap kQualityBMeshGap): Quality on, not coding by
// hand, PMeshMode d3dmc, and neither BMeshGap nor a keyframe key set.
bool qualityCodesBMeshes(const EncoderParams& params, const IsSetFunction& isSet);

// `params` with Quality resolved (Quality < 0: `params` unchanged). `source` and `bounds` are the
// sequence's; the trial reads frames 0 .. qualityTrialFrames() - 1 through `source` once.
// `report` (optional) receives one line saying what was chosen and what each candidate measured.
EncoderParams resolveQuality(const EncoderParams& params, const SequenceBounds& bounds,
                             const FrameSource& source, const IsSetFunction& isSet,
                             std::string* report = nullptr);

}  // namespace tdvo
