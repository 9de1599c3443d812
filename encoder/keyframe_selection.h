// Choice of a GOM's keyframes (see common/geometry/keyframes.h). The first and the last frame of a
// GOM are always keyframes, so every GOM interpolates only between its own frames and stays a
// random-access point.
#pragma once

#include <functional>
#include <vector>

#include "common/core/mesh.h"

namespace tdvo {

// `frames` are the GOM's quantised input positions (one vector per frame, same vertex count).
// keyframeCount > 0: exactly min(max(keyframeCount, 2), n) keyframes minimising the total
//   squared interpolation error (dynamic programming over all choices).
// maxError > 0: the fewest keyframes found by repeatedly adding the frame with the largest
//   interpolation error until no coordinate of any frame is off by more than maxError grid
//   units (greedy refinement, as in polyline simplification).
// Neither: every frame is a keyframe. Returns the keyframes' offsets in the GOM, ascending.
// Both searches interpolate frames many times: the dynamic programming n³/6 vertex-frames (and
// an n x n table), the greedy refinement up to n²/2. Beyond kMaxKeyframeSearchWork vertex
// interpolations (a GOM of about 2000 frames of a triangle, or 130 frames of 10,000 vertices
// for KeyframeCount) it throws Error instead, naming the key, the GOM's size and the ways out.
constexpr double kMaxKeyframeSearchWork = 4294967296.0;  // 2^32
std::vector<int> selectKeyframes(const std::vector<std::vector<Vec3i>>& frames, int keyframeCount,
                                 double maxError);

// Rate-distortion choice (KeyframeLambda): the keyframes 0 = k0 < k1 < ... = n - 1 of a GOM of
// `n` frames, no two consecutive keyframes more than `maxGap` frames apart, that minimise the
// sum of cost(k_i, k_i+1) over the intervals (dynamic programming over the last keyframe).
// cost(a, b) is the interval's J = D + lambda * R: the rate of keyframe b's P mesh and the
// squared error of frames a + 1 .. b. It is asked for every (b - 1, b); for a longer interval
// only when bound(a, b) (a cheap estimate of cost(a, b) from below, e.g. the interpolation
// error alone) leaves it a chance, i.e. when best(a) + bound(a, b) < the best cost of 0 .. b
// found so far; intervals ending at b are tried from the shortest, and longer ones no more once
// bound(a, b) alone reaches that cost (interpolation error grows with the gap). Returns the
// keyframes ascending; every frame when n <= 2. Deterministic: the intervals are tried in a
// fixed order and a longer one replaces the best only when strictly cheaper.
constexpr int kKeyframeRdMaxGap = 16;  // the longest interval the RD choice considers
std::vector<int> selectKeyframesRd(int n, int maxGap, const std::function<double(int, int)>& bound,
                                   const std::function<double(int, int)>& cost);

}  // namespace tdvo
