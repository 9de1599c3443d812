// Choice of a GOM's keyframes (see common/geometry/keyframes.h). The first and the last frame of a
// GOM are always keyframes, so every GOM interpolates only between its own frames and stays a
// random-access point.
#pragma once

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
std::vector<int> selectKeyframes(const std::vector<std::vector<Vec3i>>& frames, int keyframeCount,
                                 double maxError);

}  // namespace tdvo
