// Keyframes: integer interpolation, keyframe selection, and bit-exact coding of GOMs whose
// frames are partly interpolated, in both P-mesh modes.
#include <gtest/gtest.h>

#include <random>

#include "common/core/md5.h"
#include "common/geometry/keyframes.h"
#include "encoder/keyframe_selection.h"
#include "encoder/sequence_encoder.h"
#include "tools/eval/sample_mesh.h"

namespace tdvo {
namespace {

TEST(InterpolateFrame, RoundsLikeRoundDiv) {
  const std::vector<Vec3i> a = {{0, 10, -5}}, b = {{3, 0, 5}};
  // f = 1 of 0..2: 0 + roundDiv(3, 2) = 2; 10 + roundDiv(-10, 2) = 5; -5 + roundDiv(10, 2) = 0
  EXPECT_EQ(interpolateFrame(a, b, 0, 2, 1), (std::vector<Vec3i>{{2, 5, 0}}));
  // f = 1 of 0..4: 0 + roundDiv(3, 4) = 1 (0.75); 10 + roundDiv(-10, 4) = 8 (-2.5 -> -2)
  EXPECT_EQ(interpolateFrame(a, b, 0, 4, 1)[0][0], 1);
  EXPECT_EQ(interpolateFrame(a, b, 0, 4, 1)[0][1], 8);
  EXPECT_EQ(interpolateFrame(a, b, 0, 4, 0), a);
  EXPECT_EQ(interpolateFrame(a, b, 0, 4, 4), b);
}

// Total squared interpolation error of a keyframe set.
double totalError(const std::vector<std::vector<Vec3i>>& frames, const std::vector<int>& keys) {
  double total = 0;
  for (size_t i = 0; i + 1 < keys.size(); ++i)
    for (int f = keys[i] + 1; f < keys[i + 1]; ++f) {
      const std::vector<Vec3i> p =
          interpolateFrame(frames[keys[i]], frames[keys[i + 1]], keys[i], keys[i + 1], f);
      for (size_t v = 0; v < p.size(); ++v)
        for (int c = 0; c < 3; ++c)
          total += std::pow(p[v][c] - frames[f][v][c], 2);
    }
  return total;
}

std::vector<std::vector<Vec3i>> randomTrajectories(int frames, int vertices, unsigned seed) {
  std::mt19937 random(seed);
  std::vector<std::vector<Vec3i>> out(frames, std::vector<Vec3i>(vertices));
  for (int v = 0; v < vertices; ++v) {
    Vec3i p = {2000, 2000, 2000};
    for (int f = 0; f < frames; ++f) {
      for (int c = 0; c < 3; ++c)
        p[c] += static_cast<int32_t>(random() % 41) - 20;
      out[f][v] = p;
    }
  }
  return out;
}

TEST(SelectKeyframes, CountIsOptimalAgainstBruteForce) {
  const int n = 9;
  const auto frames = randomTrajectories(n, 5, 3);
  for (int count = 2; count <= 5; ++count) {
    const std::vector<int> keys = selectKeyframes(frames, count, 0);
    ASSERT_EQ(static_cast<int>(keys.size()), count);
    EXPECT_EQ(keys.front(), 0);
    EXPECT_EQ(keys.back(), n - 1);
    // Every subset of the inner frames of the right size.
    double best = 1e300;
    for (int mask = 0; mask < (1 << (n - 2)); ++mask) {
      if (__builtin_popcount(mask) != count - 2) continue;
      std::vector<int> subset = {0};
      for (int f = 1; f < n - 1; ++f)
        if (mask >> (f - 1) & 1) subset.push_back(f);
      subset.push_back(n - 1);
      best = std::min(best, totalError(frames, subset));
    }
    EXPECT_DOUBLE_EQ(totalError(frames, keys), best) << count << " keyframes";
  }
}

TEST(SelectKeyframes, MaxErrorBoundHolds) {
  const auto frames = randomTrajectories(20, 8, 5);
  for (double bound : {5.0, 20.0, 60.0}) {
    const std::vector<int> keys = selectKeyframes(frames, 0, bound);
    for (size_t i = 0; i + 1 < keys.size(); ++i)
      for (int f = keys[i] + 1; f < keys[i + 1]; ++f) {
        const auto p =
            interpolateFrame(frames[keys[i]], frames[keys[i + 1]], keys[i], keys[i + 1], f);
        for (size_t v = 0; v < p.size(); ++v)
          for (int c = 0; c < 3; ++c)
            EXPECT_LE(std::abs(p[v][c] - frames[f][v][c]), bound);
      }
  }
  EXPECT_EQ(selectKeyframes(frames, 0, 0).size(), 20u);  // neither set: every frame
  EXPECT_EQ(selectKeyframes(frames, 1, 0).size(), 2u);   // at least first and last
}

class KeyframeCoding : public ::testing::TestWithParam<PMeshMode> {};

TEST_P(KeyframeCoding, EncoderAndDecoderAgreeOnEveryFrame) {
  const std::vector<Mesh> frames = deformingBlob(2, 23);
  EncoderParams params;
  params.pmeshMode = GetParam();
  params.gomSize = 10;  // GOMs of 10, 10 and 3 frames
  params.keyframeCount = 4;
  params.motionQuantStep = 2;
  const Grid grid = gridForSequence(frames, params.gridBits);
  std::vector<std::string> encoderLines, decoderLines;
  std::vector<int> order;
  const EncodedSequence coded =
      encodeSequence(params, grid, frames, {}, [&](int f, const IntMesh& m) {
        encoderLines.push_back(geometryHashLine(f, m));
        order.push_back(f);
      });
  StreamDecoder decoder(coded.stream.data(), coded.stream.size(), "keyframe stream");
  decoder.decode([&](int f, const IntMesh& m) { decoderLines.push_back(geometryHashLine(f, m)); });
  ASSERT_EQ(encoderLines.size(), frames.size());  // frame count preserved
  EXPECT_EQ(encoderLines, decoderLines);
  for (size_t f = 0; f < order.size(); ++f)
    EXPECT_EQ(order[f], static_cast<int>(f));
  EXPECT_GT(coded.maxAbsError, 0);  // interpolated frames are not exact on this motion
}

INSTANTIATE_TEST_SUITE_P(Modes, KeyframeCoding,
                         ::testing::Values(PMeshMode::kD3dmc, PMeshMode::kAfxic));

}  // namespace
}  // namespace tdvo
