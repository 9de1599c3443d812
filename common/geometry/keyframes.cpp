#include "common/geometry/keyframes.h"

#include <cstddef>

#include "common/geometry/pmesh_prediction.h"

namespace tdvo {

void interpolateFrame(const std::vector<Vec3i>& ka, const std::vector<Vec3i>& kb, int a, int b,
                      int f, std::vector<Vec3i>& out) {
  out.resize(ka.size());
  const int64_t span = b - a, t = f - a;
  if (span > 0 && (span & (span - 1)) == 0) {
    // roundDiv(n, span) = floor((2n + span) / (2 span)), for a power of two an arithmetic shift
    // (exactly the same values; the B meshes' spans, which this loop then runs vectorised).
    const int shift = __builtin_ctzll(static_cast<uint64_t>(span)) + 1;
    for (size_t v = 0; v < ka.size(); ++v)
      for (int c = 0; c < 3; ++c)
        out[v][c] = static_cast<int32_t>(
            ka[v][c] + ((2 * (int64_t{kb[v][c]} - ka[v][c]) * t + span) >> shift));
    return;
  }
  for (size_t v = 0; v < ka.size(); ++v)
    for (int c = 0; c < 3; ++c)
      out[v][c] =
          static_cast<int32_t>(ka[v][c] + roundDiv((int64_t{kb[v][c]} - ka[v][c]) * t, span));
}

int bMeshLevel(int a, int b, int f) {
  for (int level = 1;; ++level) {
    const int m = bMeshMiddle(a, b);
    if (m == f || b - a < 2) return level;  // (the latter only for f outside a .. b)
    (f < m ? b : a) = m;
  }
}

std::vector<Vec3i> interpolateFrame(const std::vector<Vec3i>& ka, const std::vector<Vec3i>& kb,
                                    int a, int b, int f) {
  std::vector<Vec3i> out;
  interpolateFrame(ka, kb, a, b, f, out);
  return out;
}

}  // namespace tdvo
