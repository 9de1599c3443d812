// Keyframes: in a GOM coded with P meshes, only keyframes carry geometry; the frames between
// two decoded keyframes are linear interpolations of them (coordinate-interpolator style).
// The interpolation is integer arithmetic, so encoder and decoder produce the same frames.
#pragma once

#include <vector>

#include "common/core/mesh.h"

namespace tdvo {

// Frame `f` between keyframes a < f < b with decoded positions ka and kb:
//   ka + roundDiv((kb - ka) * (f - a), b - a)   per coordinate (roundDiv: pmesh_prediction.h).
std::vector<Vec3i> interpolateFrame(const std::vector<Vec3i>& ka, const std::vector<Vec3i>& kb,
                                    int a, int b, int f);
// The same into `out` (resized; must be neither ka nor kb), for callers that reuse a buffer.
void interpolateFrame(const std::vector<Vec3i>& ka, const std::vector<Vec3i>& kb, int a, int b,
                      int f, std::vector<Vec3i>& out);

// B meshes (docs/bitstream.md, "B meshes"): the frames a < f < b between two keyframes are
// coded in the preorder of the halving of a .. b, its middle frame bMeshMiddle(a, b) first (the
// decoder's order and the encoder's levels both come from it).
constexpr int bMeshMiddle(int a, int b) {
  return a + (b - a) / 2;
}
// The level of frame f in that halving: 1 for the middle m of a .. b, 2 for the middles of
// a .. m and m .. b, and so on.
int bMeshLevel(int a, int b, int f);

}  // namespace tdvo
