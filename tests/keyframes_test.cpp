// Keyframes: integer interpolation, keyframe selection, and bit-exact coding of GOMs whose
// frames are partly interpolated, in both P-mesh modes.
#include <gtest/gtest.h>

#include <random>

#include "common/core/error.h"
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

// Every span (powers of two take a shift, the others a division) gives
// ka + roundDiv((kb - ka) * t, span) as bitstream.md says, for coordinates over the whole grid
// range, negative differences and both halves' rounding included.
TEST(InterpolateFrame, EverySpanMatchesTheDefinition) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int32_t> coordinate(0, (1 << 20) - 1), small(0, 9);
  std::vector<Vec3i> ka(600), kb(600);
  for (size_t v = 0; v < ka.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      ka[v][c] = v < 300 ? coordinate(rng) : small(rng);
      kb[v][c] = v < 300 ? coordinate(rng) : small(rng);
    }
  for (int a : {0, 5, 1000})
    for (int span = 1; span <= 70; ++span)
      for (int t = 0; t <= span; ++t) {
        const std::vector<Vec3i> out = interpolateFrame(ka, kb, a, a + span, a + t);
        for (size_t v = 0; v < ka.size(); ++v)
          for (int c = 0; c < 3; ++c) {
            const int64_t n = (int64_t{kb[v][c]} - ka[v][c]) * t;
            const int64_t q = n * 2 + span;  // floor(q / (2 span))
            const int64_t expect =
                ka[v][c] + (q >= 0 ? q / (2 * span) : -((-q + 2 * span - 1) / (2 * span)));
            ASSERT_EQ(out[v][c], expect) << "span " << span << " t " << t << " v " << v;
          }
      }
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

// The searches' work is bounded (kMaxKeyframeSearchWork): past it an Error, at once, before
// the n x n table or any interpolation (a 241 KB glTF of 20,000 frames of a tetrahedron took
// 3.2 GB with KeyframeCount 2; KeyframeMaxError is quadratic). Just below, they run.
TEST(SelectKeyframes, SearchWorkIsBounded) {
  const std::vector<std::vector<Vec3i>> big(2049, std::vector<Vec3i>(3, Vec3i{0, 0, 0}));
  try {
    selectKeyframes(big, 3, 0);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("KeyframeCount: choosing the keyframes of a GOM of 2049 "
                                         "frames of 3 vertices would interpolate 4.3e+09 "
                                         "vertices (more than 2^32)"),
              std::string::npos)
        << e.what();
  }
  const std::vector<std::vector<Vec3i>> longer(3000, std::vector<Vec3i>(1000, Vec3i{0, 0, 0}));
  try {
    selectKeyframes(longer, 0, 1.0);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("KeyframeMaxError: choosing the keyframes of a GOM of "
                                         "3000 frames"),
              std::string::npos)
        << e.what();
  }
  const std::vector<std::vector<Vec3i>> fits(200, std::vector<Vec3i>(3, Vec3i{0, 0, 0}));
  EXPECT_EQ(selectKeyframes(fits, 3, 0).size(), 3u);
  EXPECT_EQ(selectKeyframes(fits, 0, 1.0).size(), 2u);  // static: first and last
}

// The DP of the RD choice against every keyframe set, on a made-up interval cost.
TEST(SelectKeyframesRd, OptimalAgainstBruteForce) {
  const int n = 10, maxGap = 4;
  const auto cost = [](int a, int b) { return 3.0 + (b - a) * (b - a) * (1 + (a * 7 + b) % 3); };
  const std::vector<int> keys = selectKeyframesRd(
      n, maxGap, [](int, int) { return 0.0; }, cost);
  double best = 1e300;
  for (int mask = 0; mask < (1 << (n - 2)); ++mask) {
    std::vector<int> subset = {0};
    for (int f = 1; f < n - 1; ++f)
      if (mask >> (f - 1) & 1) subset.push_back(f);
    subset.push_back(n - 1);
    double total = 0;
    for (size_t i = 0; i + 1 < subset.size(); ++i)
      total += subset[i + 1] - subset[i] > maxGap ? 1e300 : cost(subset[i], subset[i + 1]);
    best = std::min(best, total);
  }
  double total = 0;
  for (size_t i = 0; i + 1 < keys.size(); ++i) {
    EXPECT_LE(keys[i + 1] - keys[i], maxGap);
    total += cost(keys[i], keys[i + 1]);
  }
  EXPECT_DOUBLE_EQ(total, best);
  EXPECT_EQ(keys.front(), 0);
  EXPECT_EQ(keys.back(), n - 1);
}

// KeyframeLambda on whole GOMs: J = D + lambda * R of the coded stream (D: squared error against
// the quantised input, R: P-mesh bits).
struct RdCoding {
  EncodedSequence coded;
  double j = 0;
};

RdCoding codeWithKeyframeLambda(const std::vector<Mesh>& frames, double keyframeLambda,
                                double lambdaForJ, int threads = 1, int quantStep = 4) {
  EncoderParams params;
  params.gomSize = 12;  // GOMs of 12, 12 and 6 frames
  params.motionQuantStep = quantStep;
  params.keyframeLambda = keyframeLambda;
  params.threads = threads;
  const Grid grid = gridForSequence(frames, params.gridBits);
  RdCoding out;
  out.coded = encodeSequence(params, grid, frames, {}, [](int, const IntMesh&) {});
  out.j = out.coded.sumSquaredError + lambdaForJ * 8.0 * double(out.coded.pMeshBytes);
  return out;
}

size_t keyframeCount(const EncodedSequence& coded) {
  size_t k = 0;
  for (size_t g : coded.gomKeyframes)
    k += g;
  return k;
}

TEST(RdKeyframes, NeverWorseInJThanEveryFrame) {
  const std::vector<Mesh> frames = deformingBlob(2, 30);
  for (double lambda : {0.5, 4.0, 40.0, 400.0}) {
    const RdCoding all = codeWithKeyframeLambda(frames, 0, lambda);
    const RdCoding rd = codeWithKeyframeLambda(frames, lambda, lambda);
    EXPECT_EQ(keyframeCount(all.coded), frames.size());
    EXPECT_LE(rd.j, all.j) << "lambda " << lambda;
  }
}

TEST(RdKeyframes, TinyLambdaKeepsEveryFrameHugeLambdaOnlyFirstAndLast) {
  const std::vector<Mesh> frames = deformingBlob(2, 30);
  // Lossless P meshes (MotionQuantStep 1): every frame exact, which interpolation is not here.
  EXPECT_EQ(keyframeCount(codeWithKeyframeLambda(frames, 1e-9, 0, 1, 1).coded), frames.size());
  const RdCoding huge = codeWithKeyframeLambda(frames, 1e9, 0);
  EXPECT_EQ(huge.coded.gomKeyframes, (std::vector<size_t>{2, 2, 2}));
}

TEST(RdKeyframes, AutomaticLambdaFollowsMotionQuantStep) {
  EncoderParams params;
  EXPECT_EQ(params.effectiveKeyframeLambda(), 0);  // off by default
  params.keyframeLambda = -1;
  params.motionQuantStep = 8;
  EXPECT_DOUBLE_EQ(params.effectiveKeyframeLambda(), EncoderParams::kAutoKeyframeLambdaFactor * 64);
  params.keyframeLambda = 3;
  EXPECT_EQ(params.effectiveKeyframeLambda(), 3);
}

TEST(RdKeyframes, SameStreamForAnyThreads) {
  const std::vector<Mesh> frames = deformingBlob(2, 30);
  const RdCoding one = codeWithKeyframeLambda(frames, 40, 0, 1);
  const RdCoding three = codeWithKeyframeLambda(frames, 40, 0, 3);
  EXPECT_EQ(one.coded.stream, three.coded.stream);
  EXPECT_LT(keyframeCount(one.coded), frames.size());  // a subset pays on this motion
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
