// P-mesh coding: the shared prediction code, the closed loop of encoder and decoder for many
// parameter combinations, and robustness against corrupt payloads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "common/core/error.h"
#include "common/core/grid.h"
#include "common/core/obj_io.h"
#include "decoder/pmesh_decoder.h"
#include "encoder/imesh_encoder.h"
#include "encoder/pmesh_encoder.h"
#include "encoder/sequence_encoder.h"
#include "tests/test_support.h"
#include "tools/eval/sample_mesh.h"

namespace tdvo {
namespace {

TEST(RoundDiv, RoundsHalvesUpForBothSigns) {
  EXPECT_EQ(roundDiv(5, 2), 3);    // 2.5 -> 3
  EXPECT_EQ(roundDiv(-5, 2), -2);  // -2.5 -> -2
  EXPECT_EQ(roundDiv(7, 3), 2);    // 2.33 -> 2
  EXPECT_EQ(roundDiv(-7, 3), -2);  // -2.33 -> -2
  EXPECT_EQ(roundDiv(-8, 3), -3);  // -2.67 -> -3
  EXPECT_EQ(roundDiv(0, 7), 0);
  EXPECT_EQ(roundDiv(6, 3), 2);
  EXPECT_EQ(roundDiv(-6, 3), -2);
}

// floorDiv divides by multiplying for small divisors; it must be floor(a / b) exactly, for
// every divisor around and beyond that range and numerators up to the int64 extremes.
TEST(FloorDiv, IsExactForSmallAndLargeDivisorsAndAnyNumerator) {
  std::mt19937_64 rng(11);
  auto reference = [](int64_t a, int64_t b) {
    const __int128 q = __int128{a} / b, r = __int128{a} % b;
    return int64_t(q - (r < 0 ? 1 : 0));
  };
  const int64_t big = int64_t{1} << 62;
  std::vector<int64_t> numerators = {0, 1, -1, 2, -2, big, -big, INT64_MAX, INT64_MIN};
  for (int i = 0; i < 200; ++i) {
    const int64_t r = int64_t(rng());
    numerators.push_back(r);
    numerators.push_back(r >> (rng() % 63));  // every magnitude
  }
  for (int64_t b = 1; b <= SmallReciprocals::kCount + 8; ++b)
    for (int64_t a : numerators) {
      ASSERT_EQ(floorDiv(a, b), reference(a, b)) << a << " / " << b;
      // Around the multiples of b, where a neighbouring quotient would show.
      const int64_t m = (a / b) * b;
      for (int64_t d : {-1, 0, 1}) {
        if ((d < 0 && m == INT64_MIN) || (d > 0 && m == INT64_MAX)) continue;
        ASSERT_EQ(floorDiv(m + d, b), reference(m + d, b)) << m + d << " / " << b;
      }
    }
  for (int i = 0; i < 1000; ++i) {
    const int64_t a = int64_t(rng()), b = int64_t(rng() >> (1 + rng() % 62)) + 1;
    ASSERT_EQ(floorDiv(a, b), reference(a, b)) << a << " / " << b;
  }
}

// residualClass is written without branches; it must be its definition (pmesh_syntax.h).
TEST(ResidualClass, IsTheDefinition) {
  for (int64_t count = 0; count <= 40; ++count)
    for (int64_t sumAbs = 0; sumAbs <= 400; ++sumAbs) {
      const int expected = count == 0           ? 0
                           : sumAbs == 0        ? 1
                           : sumAbs < 2 * count ? 2
                           : sumAbs < 6 * count ? 3
                                                : 4;
      ASSERT_EQ(residualClass(count, sumAbs), expected) << count << ", " << sumAbs;
    }
}

// Two triangles sharing edge 1-2: (0, 1, 2) and (2, 1, 3).
IntMesh quad() {
  IntMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  m.triangles = {{0, 1, 2}, {2, 1, 3}};
  return m;
}

TEST(GomTopology, RingsWingsAndBreadthFirstOrder) {
  const GomTopology t = GomTopology::build(quad());
  ASSERT_EQ(t.numVertices, 4u);
  const std::vector<uint32_t> ring0(t.neighbours.begin() + t.neighbourStart[0],
                                    t.neighbours.begin() + t.neighbourStart[1]);
  EXPECT_EQ(ring0, (std::vector<uint32_t>{1, 2}));
  const std::vector<uint32_t> ring1(t.neighbours.begin() + t.neighbourStart[1],
                                    t.neighbours.begin() + t.neighbourStart[2]);
  EXPECT_EQ(ring1, (std::vector<uint32_t>{0, 2, 3}));
  // Vertex 0's only wing: triangle (0, 1, 2), opposite vertex 3 across edge 1-2.
  ASSERT_EQ(t.wingStart[1] - t.wingStart[0], 1u);
  EXPECT_EQ(t.wings[t.wingStart[0]], (std::array<uint32_t, 3>{1, 2, 3}));
  ASSERT_EQ(t.wingStart[4] - t.wingStart[3], 1u);
  EXPECT_EQ(t.wings[t.wingStart[3]], (std::array<uint32_t, 3>{2, 1, 0}));
  EXPECT_EQ(t.order, (std::vector<uint32_t>{0, 1, 2, 3}));
}

TEST(PredictMotion, FallbackMeanAndParallelogram) {
  const GomTopology t = GomTopology::build(quad());
  std::vector<Vec3i> motion = {{0, 0, 0}, {10, 0, 4}, {2, 6, 0}, {1, 1, 1}};
  std::vector<uint8_t> available = {0, 0, 0, 0};
  EXPECT_EQ(predictMotion(t, 0, motion, available, {7, 8, 9}), (Vec3i{7, 8, 9}));
  available = {0, 1, 0, 0};  // one neighbour, no wing
  EXPECT_EQ(predictMotion(t, 0, motion, available, {7, 8, 9}), (Vec3i{10, 0, 4}));
  available = {0, 1, 1, 0};  // mean of 1 and 2: (6, 3, 2)
  EXPECT_EQ(predictMotion(t, 0, motion, available, {}), (Vec3i{6, 3, 2}));
  available = {0, 1, 1, 1};  // mean (6, 3, 2) and parallelogram 1 + 2 - 3 = (11, 5, 3)
  // roundDiv(kp*sN + k*sP, 2 k kp) with k = 2, kp = 1: ((12 + 22) / 4, (6 + 10) / 4, (4 + 6) / 4)
  EXPECT_EQ(predictMotion(t, 0, motion, available, {}), (Vec3i{9, 4, 3}));
}

TEST(OctreePartition, SplitsByTheDepthBitStably) {
  std::vector<Vec3i> positions = {{0, 0, 0}, {8, 0, 0}, {0, 8, 8}, {15, 15, 15}, {1, 1, 1}};
  std::vector<uint32_t> cells = {0, 1, 2, 3, 4}, scratch;
  std::array<uint32_t, 9> bounds;
  OctreePartition::split(positions, cells.data(), cells.data() + cells.size(), 4, 0, bounds,
                         scratch);
  EXPECT_EQ(cells, (std::vector<uint32_t>{0, 4, 2, 1, 3}));
  EXPECT_EQ(bounds, (std::array<uint32_t, 9>{0, 2, 2, 2, 3, 4, 4, 4, 5}));
}

TEST(ApplyMotion, ClampsIntoTheGrid) {
  EXPECT_EQ(applyMotion({5, 5, 5}, {-10, 3, 2000}, 10), (Vec3i{0, 8, 1023}));
}

struct Gom {
  GomTopology topology;
  std::vector<std::vector<Vec3i>> frames;  // GOM order, frame 0 = decoded I mesh
};

Gom makeGom(int subdivisions, int frames, int gridBits) {
  const std::vector<Mesh> sequence = deformingBlob(subdivisions, frames);
  Vec3d lo, hi;
  boundingBox(sequence, lo, hi);
  const Grid grid = Grid::fromBounds(lo, hi, gridBits);
  const IMeshEncoding i = encodeIMesh(grid.quantise(sequence[0]), gridBits, 5);
  Gom gom;
  gom.topology = GomTopology::build(i.decoded);
  for (const Mesh& m : sequence) {
    const IntMesh q = grid.quantise(m);
    std::vector<Vec3i> ordered(i.inputIndex.size());
    for (size_t j = 0; j < ordered.size(); ++j)
      ordered[j] = q.positions[i.inputIndex[j]];
    gom.frames.push_back(ordered);
  }
  EXPECT_EQ(gom.frames[0], i.decoded.positions);
  return gom;
}

struct ClosedLoopCase {
  int quantStep;
  double lambda;
  int maxDepth;
};

class PMeshClosedLoop : public ::testing::TestWithParam<ClosedLoopCase> {};

TEST_P(PMeshClosedLoop, DecoderReproducesEncoderAndErrorIsBounded) {
  const ClosedLoopCase c = GetParam();
  const int gridBits = 12;
  const Gom gom = makeGom(3, 6, gridBits);
  PMeshParams params;
  params.gridBits = gridBits;
  params.quantStep = c.quantStep;
  params.maxDepth = c.maxDepth;
  std::vector<Vec3i> previous = gom.frames[0];
  for (size_t f = 1; f < gom.frames.size(); ++f) {
    const PMeshEncoding e = encodePMesh(gom.topology, previous, gom.frames[f], params, c.lambda);
    const std::vector<Vec3i> decoded =
        decodePMesh(e.payload, gom.topology, previous, params, "test");
    ASSERT_EQ(decoded, e.reconstruction) << "frame " << f;
    if (c.lambda == 0) {
      // Without clustering trade-offs every coordinate is within half a quantiser step.
      for (size_t v = 0; v < decoded.size(); ++v)
        for (int k = 0; k < 3; ++k)
          ASSERT_LE(std::abs(decoded[v][k] - gom.frames[f][v][k]), c.quantStep / 2)
              << "frame " << f << " vertex " << v;
    }
    previous = decoded;
  }
}

INSTANTIATE_TEST_SUITE_P(Params, PMeshClosedLoop,
                         ::testing::Values(ClosedLoopCase{1, 0, 12}, ClosedLoopCase{4, 0, 12},
                                           ClosedLoopCase{16, 0, 12}, ClosedLoopCase{1, 50, 12},
                                           ClosedLoopCase{8, 6.4, 12}, ClosedLoopCase{8, 5000, 12},
                                           ClosedLoopCase{1, 0, 0}, ClosedLoopCase{3, 100, 4}));

TEST(PMesh, LosslessAtStepOneIsExact) {
  const Gom gom = makeGom(3, 4, 12);
  PMeshParams params;
  std::vector<Vec3i> previous = gom.frames[0];
  for (size_t f = 1; f < gom.frames.size(); ++f) {
    const PMeshEncoding e = encodePMesh(gom.topology, previous, gom.frames[f], params, 0);
    EXPECT_EQ(e.reconstruction, gom.frames[f]);
    previous = e.reconstruction;
  }
}

TEST(PMesh, StaticFrameCostsAlmostNothing) {
  const Gom gom = makeGom(3, 2, 12);
  PMeshParams params;
  const PMeshEncoding e = encodePMesh(gom.topology, gom.frames[0], gom.frames[0], params, 0);
  EXPECT_EQ(e.reconstruction, gom.frames[0]);
  EXPECT_LE(e.payload.size(), 4u);  // one ZERO leaf for the whole mesh
}

TEST(PMesh, CorruptPayloadsGiveErrorsNeverCrashes) {
  const Gom gom = makeGom(2, 2, 12);
  PMeshParams params;
  params.quantStep = 2;
  const PMeshEncoding e = encodePMesh(gom.topology, gom.frames[0], gom.frames[1], params, 0);
  std::mt19937 random(7);
  int errors = 0, accepted = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::vector<uint8_t> payload = e.payload;
    const int kind = trial % 3;
    if (kind == 0) {
      payload[random() % payload.size()] ^= static_cast<uint8_t>(1 + random() % 255);
    } else if (kind == 1) {
      payload.resize(random() % payload.size());
    } else {
      for (auto& b : payload)
        b = static_cast<uint8_t>(random());
    }
    try {
      const std::vector<Vec3i> d = decodePMesh(payload, gom.topology, gom.frames[0], params, "t");
      ASSERT_EQ(d.size(), gom.frames[0].size());
      for (const Vec3i& p : d)
        for (int32_t c : p)
          ASSERT_TRUE(c >= 0 && c < 4096);
      ++accepted;
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find("t, payload byte"), std::string::npos);
      ++errors;
    }
  }
  // The end-of-payload checks reject most damage (CRC catches the rest in a stream).
  EXPECT_GT(errors, 2000);
  std::printf("corrupt payloads: %d rejected, %d decoded to some in-grid mesh\n", errors, accepted);
}

// ---- One predictor (pmesh_prediction.h), checked against the formula ----
//
// predictMotion over MotionRecords is the only motion predictor: codePMesh (encoder and
// decoder) calls it in rank space with the ring's residual sums, the encoder's rate estimate
// in vertex space. The tests below check it, in both spaces, against the formula of
// docs/bitstream.md written plainly (int64 sums, vertex by vertex), on every shared sequence
// and on generated meshes, including rings longer than its int32 runs and motions at the
// largest magnitude a stream allows.

// What each vertex is while a P mesh is decoded: not final yet, final (ZERO or REPRESENTATIVE
// leaves, or decoded in pass 2), and, once decoded in pass 2, its |residual| per component.
struct VertexStates {
  std::vector<Vec3i> motion;
  std::vector<uint8_t> available;
  std::vector<uint8_t> hasResidual;
  std::vector<Vec3i> absResidual;
};

Vec3i formulaPrediction(const GomTopology& t, uint32_t v, const VertexStates& s,
                        const Vec3i& fallback) {
  int64_t k = 0, kp = 0, sN[3] = {0, 0, 0}, sP[3] = {0, 0, 0};
  for (uint32_t i = t.neighbourStart[v]; i < t.neighbourStart[v + 1]; ++i) {
    const uint32_t u = t.neighbours[i];
    if (!s.available[u]) continue;
    ++k;
    for (int c = 0; c < 3; ++c)
      sN[c] += s.motion[u][c];
  }
  if (k == 0) return fallback;
  for (uint32_t i = t.wingStart[v]; i < t.wingStart[v + 1]; ++i) {
    const std::array<uint32_t, 3>& w = t.wings[i];
    if (!s.available[w[0]] || !s.available[w[1]] || !s.available[w[2]]) continue;
    ++kp;
    for (int c = 0; c < 3; ++c)
      sP[c] += int64_t{s.motion[w[0]][c]} + s.motion[w[1]][c] - s.motion[w[2]][c];
  }
  Vec3i p;
  for (int c = 0; c < 3; ++c) {
    // round(x / d), halves up, in exact integer arithmetic.
    const int64_t num = kp == 0 ? sN[c] : kp * sN[c] + k * sP[c], den = kp == 0 ? k : 2 * k * kp;
    const __int128 twice = __int128{2} * num + den, q = twice / (2 * den), r = twice % (2 * den);
    p[c] = static_cast<int32_t>(q - (r < 0 ? 1 : 0));
  }
  return p;
}

MotionRecord recordOf(const VertexStates& s, uint32_t v) {
  MotionRecord r;
  const Vec3i& m = s.motion[v];
  r.motion = s.available[v] ? Lanes4{m[0], m[1], m[2], -1} : Lanes4{0, 0, 0, 0};
  const Vec3i& a = s.absResidual[v];
  r.absResidual = s.hasResidual[v] ? Lanes4{a[0], a[1], a[2], 1} : Lanes4{0, 0, 0, 0};
  return r;
}

// Random states: each vertex final with probability `pAvailable`, a final one decoded in
// pass 2 (with a residual) with probability 1/2; motions from `motion` (kept for final ones).
VertexStates randomStates(const std::vector<Vec3i>& motion, double pAvailable, int32_t maxResidual,
                          std::mt19937& rng) {
  const size_t n = motion.size();
  VertexStates s{motion, std::vector<uint8_t>(n), std::vector<uint8_t>(n), std::vector<Vec3i>(n)};
  std::uniform_real_distribution<double> unit(0, 1);
  std::uniform_int_distribution<int32_t> residual(0, maxResidual);
  for (size_t v = 0; v < n; ++v) {
    s.available[v] = unit(rng) < pAvailable;
    s.hasResidual[v] = s.available[v] && unit(rng) < 0.5;
    if (s.hasResidual[v]) s.absResidual[v] = {residual(rng), residual(rng), residual(rng)};
  }
  return s;
}

// Every vertex: predictMotion in vertex space and in rank space (with the residual sums) equals
// the formula; the residual sums equal theirs. Returns the vertices checked.
size_t checkPredictor(const GomTopology& t, const VertexStates& s) {
  const uint32_t n = t.numVertices;
  std::vector<MotionRecord> byVertex(n), byRank(n);
  for (uint32_t v = 0; v < n; ++v) {
    byVertex[v] = recordOf(s, v);
    byRank[t.rank[v]] = byVertex[v];
  }
  const RingView vertexRings = t.vertexRings(), rankRings = t.rankRings();
  for (uint32_t v = 0; v < n; ++v) {
    const Vec3i fallback{static_cast<int32_t>(v), -7, 3};
    const Vec3i expected = formulaPrediction(t, v, s, fallback);
    EXPECT_EQ(predictMotion(vertexRings, byVertex.data(), v, fallback), expected) << "vertex " << v;
    RingResiduals around;
    EXPECT_EQ(predictMotion(rankRings, byRank.data(), t.rank[v], fallback, around), expected)
        << "vertex " << v << " (rank space)";
    int64_t sums[4] = {0, 0, 0, 0};
    for (uint32_t i = t.neighbourStart[v]; i < t.neighbourStart[v + 1]; ++i) {
      const uint32_t u = t.neighbours[i];
      if (!s.hasResidual[u]) continue;
      for (int c = 0; c < 3; ++c)
        sums[c] += s.absResidual[u][c];
      ++sums[3];
    }
    for (int c = 0; c < 4; ++c)
      EXPECT_EQ(around.sums[c], sums[c]) << "vertex " << v << ", lane " << c;
    if (::testing::Test::HasFailure()) return v;
  }
  return n;
}

// The states a P mesh's decoding goes through, from none final to all final, on `t` with
// motions `motion`.
void checkAllStates(const GomTopology& t, const std::vector<Vec3i>& motion, int32_t maxResidual,
                    uint32_t seed) {
  std::mt19937 rng(seed);
  for (double p : {0.0, 0.2, 0.5, 0.8, 1.0})
    ASSERT_EQ(checkPredictor(t, randomStates(motion, p, maxResidual, rng)), t.numVertices)
        << "P(final) " << p;
}

TEST(PredictMotion, IsTheFormulaOnEverySharedSequence) {
  const std::filesystem::path root = std::filesystem::path(TDVO_SHARED_DATA_DIR) / "meshseq";
  if (!std::filesystem::is_directory(root))
    GTEST_SKIP() << "../shared/data/meshseq is absent: the shared sequences were not checked";
  std::vector<std::filesystem::path> sequences;
  for (const auto& entry : std::filesystem::directory_iterator(root))
    if (entry.is_directory()) sequences.push_back(entry.path());
  std::sort(sequences.begin(), sequences.end());
  ASSERT_FALSE(sequences.empty());
  for (const std::filesystem::path& folder : sequences) {
    SCOPED_TRACE(folder.string());
    std::vector<std::string> files;
    for (const auto& entry : std::filesystem::directory_iterator(folder))
      if (entry.path().string().find(".obj") != std::string::npos)
        files.push_back(entry.path().string());
    std::sort(files.begin(), files.end());
    ASSERT_GE(files.size(), 2u);
    // Two frames on a 12-bit grid; frame 0 through Draco as an I mesh, as the codec sees it.
    const std::vector<Mesh> frames = {readObj(files[0]), readObj(files[1])};
    const Grid grid = gridForSequence(frames, 12);
    const IntMesh first = grid.quantise(frames[0]), second = grid.quantise(frames[1]);
    const IMeshEncoding i = encodeIMesh(first, 12, 0);
    const GomTopology t = GomTopology::build(i.decoded);
    // The real motion when the frames share their vertices, else random motion.
    std::vector<Vec3i> motion(t.numVertices);
    std::mt19937 rng(5);
    std::uniform_int_distribution<int32_t> random(-300, 300);
    const bool real = second.positions.size() == first.positions.size();
    for (uint32_t v = 0; v < t.numVertices; ++v)
      for (int c = 0; c < 3; ++c)
        motion[v][c] =
            real ? second.positions[i.inputIndex[v]][c] - i.decoded.positions[v][c] : random(rng);
    std::printf("%s: %u vertices, %zu wings, %s motion\n", folder.filename().c_str(), t.numVertices,
                t.wings.size(), real ? "real" : "random");
    checkAllStates(t, motion, 300, 7);
  }
}

TEST(PredictMotion, IsTheFormulaOnGeneratedMeshes) {
  const Grid grid = gridForSequence(test::wobblingSphere(3, 2), 12);
  const std::vector<Mesh> sphere = test::wobblingSphere(3, 2);
  const IntMesh a = grid.quantise(sphere[0]), b = grid.quantise(sphere[1]);
  const GomTopology t = GomTopology::build(a);
  std::vector<Vec3i> motion(a.positions.size());
  for (size_t v = 0; v < motion.size(); ++v)
    for (int c = 0; c < 3; ++c)
      motion[v][c] = b.positions[v][c] - a.positions[v][c];
  checkAllStates(t, motion, 40, 1);

  // The convenience form is the same predictor.
  std::mt19937 rng(3);
  const VertexStates s = randomStates(motion, 0.6, 0, rng);
  for (uint32_t v = 0; v < t.numVertices; ++v)
    ASSERT_EQ(predictMotion(t, v, s.motion, s.available, {1, 2, 3}),
              formulaPrediction(t, v, s, {1, 2, 3}));

  // A sheet (borders: vertices with few wings) with motions of the largest magnitude.
  const std::vector<Mesh> sheet = test::waveSheet(12, 9, 1);
  const GomTopology ts = GomTopology::build(gridForSequence(sheet, 12).quantise(sheet[0]));
  std::uniform_int_distribution<int32_t> extreme(-kMaxMotion, kMaxMotion);
  std::vector<Vec3i> large(ts.numVertices);
  for (Vec3i& m : large)
    m = {extreme(rng), extreme(rng) < 0 ? -kMaxMotion : kMaxMotion, extreme(rng)};
  checkAllStates(ts, large, kMaxMotion, 2);
}

// A double cone: a hub with a ring of 1500 vertices and as many wings (the apex opposite),
// longer than the predictor's int32 runs of 256 terms. With motions of the largest magnitude
// a ring's sums (1500 x 2^21) and wing sums (1500 x 3 x 2^21) pass 2^31: they must still be
// exact.
TEST(PredictMotion, IsTheFormulaOnRingsLongerThanItsRuns) {
  const uint32_t rim = 1500, apex = rim + 1;
  IntMesh cone;
  cone.positions.resize(rim + 2);
  for (uint32_t i = 0; i < rim; ++i) {
    const uint32_t a = 1 + i, b = 1 + (i + 1) % rim;
    cone.triangles.push_back({0, a, b});
    cone.triangles.push_back({apex, b, a});
  }
  const GomTopology t = GomTopology::build(cone);
  ASSERT_EQ(t.neighbourStart[1] - t.neighbourStart[0], rim);
  ASSERT_EQ(t.wingStart[1] - t.wingStart[0], rim);
  std::vector<Vec3i> motion(rim + 2, Vec3i{kMaxMotion, -kMaxMotion, kMaxMotion});
  motion[0] = {1, 2, 3};
  motion[apex] = {-kMaxMotion, kMaxMotion, -kMaxMotion};
  checkAllStates(t, motion, kMaxMotion, 4);
}

}  // namespace
}  // namespace tdvo
