#include "encoder/keyframe_selection.h"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <numeric>

#include "common/core/error.h"
#include "common/geometry/keyframes.h"

namespace tdvo {

namespace {

// Squared error and largest coordinate error of frame f interpolated between a and b.
void interpolationError(const std::vector<std::vector<Vec3i>>& frames, int a, int b, int f,
                        double& squared, int64_t& largest) {
  const std::vector<Vec3i> p = interpolateFrame(frames[a], frames[b], a, b, f);
  squared = 0;
  largest = 0;
  for (size_t v = 0; v < p.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      const int64_t e = int64_t{p[v][c]} - frames[f][v][c];
      squared += double(e) * double(e);
      largest = std::max(largest, e < 0 ? -e : e);
    }
}

std::vector<int> optimalCount(const std::vector<std::vector<Vec3i>>& frames, int count) {
  const int n = static_cast<int>(frames.size());
  // cost[a][b]: total squared error of the frames strictly between keyframes a and b.
  std::vector<std::vector<double>> cost(n, std::vector<double>(n, 0));
  for (int a = 0; a < n; ++a)
    for (int b = a + 2; b < n; ++b)
      for (int f = a + 1; f < b; ++f) {
        double squared;
        int64_t largest;
        interpolationError(frames, a, b, f, squared, largest);
        cost[a][b] += squared;
      }
  // best[k][b]: least cost of k + 1 keyframes from 0 to b (b a keyframe).
  const double kInf = std::numeric_limits<double>::infinity();
  std::vector<std::vector<double>> best(count, std::vector<double>(n, kInf));
  std::vector<std::vector<int>> from(count, std::vector<int>(n, -1));
  best[0][0] = 0;
  for (int k = 1; k < count; ++k)
    for (int b = k; b < n; ++b)
      for (int a = k - 1; a < b; ++a)
        if (best[k - 1][a] + cost[a][b] < best[k][b]) {
          best[k][b] = best[k - 1][a] + cost[a][b];
          from[k][b] = a;
        }
  std::vector<int> keys;
  for (int k = count - 1, b = n - 1; k >= 0; b = from[k][b], --k)
    keys.push_back(b);
  std::reverse(keys.begin(), keys.end());
  return keys;
}

std::vector<int> greedyMaxError(const std::vector<std::vector<Vec3i>>& frames, double maxError) {
  const int n = static_cast<int>(frames.size());
  std::vector<int> keys = {0, n - 1};
  for (;;) {
    int worstFrame = -1;
    int64_t worst = 0;
    for (size_t i = 0; i + 1 < keys.size(); ++i)
      for (int f = keys[i] + 1; f < keys[i + 1]; ++f) {
        double squared;
        int64_t largest;
        interpolationError(frames, keys[i], keys[i + 1], f, squared, largest);
        if (largest > worst) {
          worst = largest;
          worstFrame = f;
        }
      }
    if (worstFrame < 0 || worst <= maxError) return keys;
    keys.insert(std::upper_bound(keys.begin(), keys.end(), worstFrame), worstFrame);
  }
}

}  // namespace

std::vector<int> selectKeyframes(const std::vector<std::vector<Vec3i>>& frames, int keyframeCount,
                                 double maxError) {
  const int n = static_cast<int>(frames.size());
  std::vector<int> all(n);
  std::iota(all.begin(), all.end(), 0);
  if (n <= 2) return all;
  // The searches' work, bounded (a 9 KB glTF animation of a tetrahedron over 1000 frames took
  // 10 s with KeyframeCount, 20,000 frames 3.2 GB before its first keyframe).
  const double vertices = static_cast<double>(frames[0].size());
  auto checkWork = [&](double work, const char* key) {
    if (work > kMaxKeyframeSearchWork) {
      char text[320];
      std::snprintf(text, sizeof text,
                    "%s: choosing the keyframes of a GOM of %d frames of %.0f vertices would "
                    "interpolate %.3g vertices (more than 2^32): use shorter GOMs (GOMSize, "
                    "GOMListFile) or KeyframeLambda",
                    key, n, vertices, work);
      throw Error(text);
    }
  };
  if (keyframeCount > 0) {
    const int count = std::min(std::max(keyframeCount, 2), n);
    if (count == n) return all;
    checkWork(double(n) * double(n) * double(n) / 6 * vertices, "KeyframeCount");
    return optimalCount(frames, count);
  }
  if (maxError > 0) {
    checkWork(double(n) * double(n) / 2 * vertices, "KeyframeMaxError");
    return greedyMaxError(frames, maxError);
  }
  return all;
}

std::vector<int> selectKeyframesRd(int n, int maxGap, const std::function<double(int, int)>& bound,
                                   const std::function<double(int, int)>& cost) {
  std::vector<int> keys(std::max(n, 0));
  std::iota(keys.begin(), keys.end(), 0);
  if (n <= 2) return keys;
  // best[b]: least cost of frames 1 .. b with b a keyframe; from[b]: the keyframe before b.
  std::vector<double> best(n, 0);
  std::vector<int> from(n, -1);
  for (int b = 1; b < n; ++b) {
    best[b] = best[b - 1] + cost(b - 1, b);
    from[b] = b - 1;
    for (int a = b - 2; a >= 0 && b - a <= maxGap; --a) {
      const double lower = bound(a, b);
      if (lower >= best[b]) break;
      if (best[a] + lower >= best[b]) continue;
      const double c = best[a] + cost(a, b);
      if (c < best[b]) {
        best[b] = c;
        from[b] = a;
      }
    }
  }
  keys.clear();
  for (int b = n - 1; b >= 0; b = from[b])
    keys.push_back(b);
  std::reverse(keys.begin(), keys.end());
  return keys;
}

}  // namespace tdvo
