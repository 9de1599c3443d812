// Issue 17, point 1: the decoder outputs every frame in the input's vertex order with the
// input's triangle list (same triangles, same order, same corner rotation), in every GOM and in
// intra mode; GOMs that are no random access point continue the previous GOM's connectivity
// without an I mesh, while a random access point decodes on its own. Checked by index, with no
// matching: vertex j of a decoded frame is vertex j of the input frame, within half a grid step
// (MotionQuantStep 1). The real-data cases (horse-gallop, tvmc-varying) are skipped, saying so,
// when ../shared/data is absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "bitstream/syntax.h"
#include "bitstream/units.h"
#include "common/core/error.h"
#include "common/core/obj_io.h"
#include "common/core/sequence.h"
#include "decoder/stream_decoder.h"
#include "encoder/sequence_encoder.h"
#include "tests/stream_units.h"
#include "tests/test_support.h"

namespace tdvo {
namespace {

// A wobbling sphere whose vertices are shuffled and whose triangles are shuffled and rotated,
// the same way in every frame: an input order far from Draco's.
std::vector<Mesh> shuffledSphere(int frames, unsigned seed) {
  std::vector<Mesh> in = test::wobblingSphere(2, frames);
  std::mt19937 rng(seed);
  const size_t n = in[0].positions.size(), numTriangles = in[0].triangles.size();
  std::vector<uint32_t> vertex(n);
  std::iota(vertex.begin(), vertex.end(), 0u);
  std::shuffle(vertex.begin(), vertex.end(), rng);
  std::vector<size_t> triangle(numTriangles);
  std::iota(triangle.begin(), triangle.end(), size_t{0});
  std::shuffle(triangle.begin(), triangle.end(), rng);
  std::vector<int> rotation(numTriangles);
  for (int& r : rotation)
    r = static_cast<int>(rng() % 3);
  std::vector<Mesh> out(in.size());
  for (size_t f = 0; f < in.size(); ++f) {
    out[f].positions.resize(n);
    for (size_t i = 0; i < n; ++i)
      out[f].positions[vertex[i]] = in[f].positions[i];
    for (size_t k = 0; k < numTriangles; ++k) {
      const Triangle& t = in[f].triangles[triangle[k]];
      const int r = rotation[k];
      out[f].triangles.push_back({vertex[t[r]], vertex[t[(r + 1) % 3]], vertex[t[(r + 2) % 3]]});
    }
  }
  return out;
}

struct Decoded {
  std::vector<IntMesh> frames;
  std::vector<uint32_t> gomStarts;
  Grid grid;
};

Decoded decodeAll(const std::vector<uint8_t>& stream) {
  Decoded d;
  StreamDecoder decoder(stream.data(), stream.size(), "order.3dvo");
  decoder.decode([&](int, const IntMesh& mesh) { d.frames.push_back(mesh); });
  d.gomStarts = decoder.gomStarts();
  d.grid = decoder.grid();
  return d;
}

// Every decoded frame, vertex by vertex by index, within half a grid step of the input, and
// its triangles exactly the input's.
void expectInputOrder(const std::vector<Mesh>& input, const Decoded& d) {
  ASSERT_EQ(d.frames.size(), input.size());
  const double bound = d.grid.step / 2 * (1 + 1e-9) + 1e-12;
  for (size_t f = 0; f < input.size(); ++f) {
    const IntMesh& dec = d.frames[f];
    ASSERT_EQ(dec.positions.size(), input[f].positions.size()) << "frame " << f;
    for (size_t j = 0; j < dec.positions.size(); ++j) {
      const Vec3d p = d.grid.dequantise(dec.positions[j]);
      for (int a = 0; a < 3; ++a)
        ASSERT_LE(std::fabs(p[a] - input[f].positions[j][a]), bound)
            << "frame " << f << " vertex " << j << " axis " << a;
    }
    ASSERT_EQ(dec.triangles.size(), input[f].triangles.size()) << "frame " << f;
    size_t differ = 0;
    for (size_t t = 0; t < dec.triangles.size(); ++t)
      differ += dec.triangles[t] != input[f].triangles[t];
    EXPECT_EQ(differ, 0u) << "frame " << f;
  }
}

EncodedSequence encode(const std::vector<Mesh>& frames, PMeshMode mode, int gomSize, int period,
                       int gridBits = 12) {
  EncoderParams params;
  params.gridBits = gridBits;
  params.gomSize = gomSize;
  params.frameCount = static_cast<int>(frames.size());
  params.pmeshMode = mode;
  params.randomAccessPeriod = period;
  return encodeSequence(params, gridForSequence(frames, gridBits), frames, {},
                        [](int, const IntMesh&) {});
}

TEST(InputOrder, ShuffledSphereComesBackInInputOrderInEveryMode) {
  const std::vector<Mesh> frames = shuffledSphere(8, 17);
  struct Case {
    PMeshMode mode;
    int period;
    size_t iMeshes;
    std::vector<uint32_t> starts;
  };
  const Case cases[] = {{PMeshMode::kIntra, 1, 8, {0, 2, 4, 6}},
                        {PMeshMode::kD3dmc, 1, 4, {0, 2, 4, 6}},
                        {PMeshMode::kD3dmc, 2, 2, {0, 4}},
                        {PMeshMode::kD3dmc, 0, 1, {0}},
                        {PMeshMode::kAfxic, 3, 2, {0, 6}}};
  for (const Case& c : cases) {
    SCOPED_TRACE("mode " + std::to_string(static_cast<int>(c.mode)) + ", RandomAccessPeriod " +
                 std::to_string(c.period));
    const EncodedSequence coded = encode(frames, c.mode, 2, c.period);
    const Decoded d = decodeAll(coded.stream);
    expectInputOrder(frames, d);
    EXPECT_EQ(test::countUnits(coded.stream, UnitType::kIMesh), c.iMeshes);
    EXPECT_EQ(test::countUnits(coded.stream, UnitType::kVertexOrder), c.iMeshes);
    EXPECT_EQ(d.gomStarts, c.starts);  // the random access points
  }
}

TEST(InputOrder, TriangleListInCodingOrderWhenAskedFor) {
  // InputTriangleOrder 0: vertices still in the input's order, the same triangles (as sets of
  // oriented triangles) in Draco's order, and a smaller VERTEX_ORDER unit.
  const std::vector<Mesh> frames = shuffledSphere(2, 5);
  EncoderParams params;
  params.gridBits = 12;
  params.gomSize = 2;
  params.frameCount = 2;
  const Grid grid = gridForSequence(frames, 12);
  const EncodedSequence full = encodeSequence(params, grid, frames, {}, [](int, const IntMesh&) {});
  params.inputTriangleOrder = false;
  const EncodedSequence cheap =
      encodeSequence(params, grid, frames, {}, [](int, const IntMesh&) {});
  EXPECT_LT(cheap.orderBytes, full.orderBytes);
  const Decoded d = decodeAll(cheap.stream);
  ASSERT_EQ(d.frames.size(), 2u);
  auto canonical = [](std::vector<Triangle> ts) {
    for (Triangle& t : ts)
      std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    std::sort(ts.begin(), ts.end());
    return ts;
  };
  EXPECT_EQ(canonical(d.frames[0].triangles), canonical(frames[0].triangles));
  EXPECT_NE(d.frames[0].triangles, frames[0].triangles);
  for (size_t j = 0; j < frames[0].positions.size(); ++j)
    for (int a = 0; a < 3; ++a)
      ASSERT_LE(
          std::fabs(d.grid.dequantise(d.frames[0].positions[j])[a] - frames[0].positions[j][a]),
          d.grid.step / 2 * (1 + 1e-9));
}

// The units of `stream` from the GOM starting at `first` on, behind a sequence header for the
// frames left, renumbered from 0: what a player seeking to `first` decodes.
std::vector<uint8_t> seekTo(const std::vector<uint8_t>& stream, uint32_t first) {
  UnitReader reader(stream.data(), stream.size(), "order.3dvo");
  UnitWriter writer;
  UnitView unit;
  bool copying = false;
  auto u32 = [](const uint8_t* p) {
    return uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24;
  };
  auto put = [](std::vector<uint8_t>& p, size_t at, uint32_t v) {
    for (int i = 0; i < 4; ++i)
      p[at + i] = static_cast<uint8_t>(v >> (8 * i));
  };
  while (reader.next(unit)) {
    std::vector<uint8_t> payload(unit.payload, unit.payload + unit.size);
    if (unit.type == static_cast<uint8_t>(UnitType::kSequenceHeader)) {
      // sh_frame_count, after sh_syntax_version (u16) and sh_first_frame (u32).
      put(payload, 6, u32(unit.payload + 6) - first);
      writer.write(UnitType::kSequenceHeader, payload);
      continue;
    }
    if (unit.type == static_cast<uint8_t>(UnitType::kGomHeader) && u32(unit.payload) == first)
      copying = true;
    if (!copying) continue;
    put(payload, 0, u32(unit.payload) - first);  // gh_first_frame, im/vo/pm_frame
    writer.write(static_cast<UnitType>(unit.type), payload);
  }
  return writer.bytes();
}

TEST(RandomAccess, ContinuingGomsAreSmallerAndRandomAccessPointsDecodeOnTheirOwn) {
  const std::vector<Mesh> frames = shuffledSphere(12, 3);
  const EncodedSequence everyGom = encode(frames, PMeshMode::kD3dmc, 3, 1);
  const EncodedSequence everyTwo = encode(frames, PMeshMode::kD3dmc, 3, 2);
  const EncodedSequence firstOnly = encode(frames, PMeshMode::kD3dmc, 3, 0);
  EXPECT_LT(everyTwo.stream.size(), everyGom.stream.size());
  EXPECT_LT(firstOnly.stream.size(), everyTwo.stream.size());
  EXPECT_EQ(test::countUnits(firstOnly.stream, UnitType::kIMesh), 1u);  // of 4 GOMs
  EXPECT_LT(firstOnly.iMeshBytes + firstOnly.orderBytes,
            (everyGom.iMeshBytes + everyGom.orderBytes) / 2);

  const Decoded whole = decodeAll(everyTwo.stream);
  expectInputOrder(frames, whole);
  ASSERT_EQ(whole.gomStarts, (std::vector<uint32_t>{0, 6}));
  // Seeking to the random access point at frame 6 gives the same frames 6..11.
  const Decoded seeked = decodeAll(seekTo(everyTwo.stream, 6));
  ASSERT_EQ(seeked.frames.size(), 6u);
  for (size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(seeked.frames[k].positions, whole.frames[6 + k].positions) << k;
    EXPECT_EQ(seeked.frames[k].triangles, whole.frames[6 + k].triangles) << k;
  }
  // A GOM that continues the previous one cannot start a stream.
  const std::vector<uint8_t> cut = seekTo(everyTwo.stream, 3);
  try {
    decodeAll(cut);
    ADD_FAILURE() << "decoded from a GOM that is no random access point";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("gh_random_access 0, but no previous GOM"),
              std::string::npos)
        << e.what();
  }
}

TEST(RandomAccess, ChangedConnectivityStartsARandomAccessPointAnyway) {
  // GOMs 0-1 one mesh, GOMs 2-3 another: with RandomAccessPeriod 0, GOM 2 still gets an I mesh.
  std::vector<Mesh> frames = shuffledSphere(4, 1);
  const std::vector<Mesh> other = shuffledSphere(4, 2);
  frames.insert(frames.end(), other.begin(), other.end());
  const EncodedSequence coded = encode(frames, PMeshMode::kD3dmc, 2, 0);
  const Decoded d = decodeAll(coded.stream);
  expectInputOrder(frames, d);
  EXPECT_EQ(test::countUnits(coded.stream, UnitType::kIMesh), 2u);
  EXPECT_EQ(d.gomStarts, (std::vector<uint32_t>{0, 4}));
}

// Through the apps: 3dvo-enc, 3dvo-dec, then 3dvo-metrics with its default correspondence
// (identity, no matching): every decoded vertex is its input vertex, so the vertex RMSE is at
// most the grid's half-step diagonal (docs/metrics.md, "Vertex correspondence").
TEST(InputOrder, MetricsNeedNoMatchingForDecodedFrames) {
  const std::vector<Mesh> frames = shuffledSphere(4, 9);
  test::TempDir dir("order-metrics");
  std::filesystem::create_directories(dir.file("in"));
  for (size_t k = 0; k < frames.size(); ++k)
    writeObj(framePath(dir.file("in") + "/%04d.obj", static_cast<int>(k)), frames[k]);
  const std::string bin = TDVO_BIN_DIR;
  const test::CommandResult enc =
      test::run(dir, bin + "/3dvo-enc",
                {"--InputMeshPattern=in/%04d.obj", "--FrameCount=4", "--GOMSize=2",
                 "--RandomAccessPeriod=0", "--GridBits=12", "-o", "x.3dvo"});
  ASSERT_EQ(enc.exitCode, 0) << enc.err;
  const test::CommandResult dec = test::run(dir, bin + "/3dvo-dec", {"-i", "x.3dvo", "-o", "out"});
  ASSERT_EQ(dec.exitCode, 0) << dec.err;
  const test::CommandResult metrics =
      test::run(dir, bin + "/3dvo-metrics", {"-r", "in/%04d.obj", "-t", "out/%04d.obj"});
  ASSERT_EQ(metrics.exitCode, 0) << metrics.err;
  const std::vector<std::string> rmse = test::linesStartingWith(metrics.out, "vertex RMSE");
  ASSERT_EQ(rmse.size(), 1u) << metrics.out;
  const double value = std::stod(rmse[0].substr(rmse[0].find(':') + 1));
  const double step = gridForSequence(frames, 12).step;
  EXPECT_LE(value, step * std::sqrt(3.0) / 2) << metrics.out;
}

// The decoding-work limit (docs/robustness.md) counts the frames of a GOM that continues the
// previous one (no I mesh) at its GOM header: a static sequence of two GOMs of 50 frames with
// two keyframes each, the second GOM costing a few bytes, declares twice the output from
// hardly more bytes.
TEST(RandomAccess, DecodingWorkLimitCountsContinuingGoms) {
  const std::vector<Mesh> frames(100, shuffledSphere(1, 4)[0]);
  EncoderParams params;
  params.gomSize = 50;
  params.frameCount = 100;
  params.randomAccessPeriod = 0;
  params.keyframeCount = 2;  // the first and last frame of each GOM
  const EncodedSequence coded = encodeSequence(params, gridForSequence(frames, params.gridBits),
                                               frames, {}, [](int, const IntMesh&) {});
  ASSERT_EQ(test::countUnits(coded.stream, UnitType::kIMesh), 1u);
  // Bytes through the I mesh and through the second GOM header.
  UnitReader reader(coded.stream.data(), coded.stream.size(), "order.3dvo");
  UnitView unit;
  uint64_t bytes0 = 0, bytes1 = 0, offset1 = 0, index1 = 0;
  size_t headers = 0;
  while (reader.next(unit)) {
    const uint64_t through = unit.payloadOffset + unit.size + 4;
    if (unit.type == static_cast<uint8_t>(UnitType::kIMesh)) bytes0 = through;
    if (unit.type == static_cast<uint8_t>(UnitType::kGomHeader) && ++headers == 2) {
      bytes1 = through;
      offset1 = unit.offset;
      index1 = unit.index;
    }
  }
  const uint64_t n = frames[0].positions.size();
  const uint64_t need0 = (50 * n + bytes0 - 1) / bytes0, need1 = (100 * n + bytes1 - 1) / bytes1;
  ASSERT_GT(need1, need0);
  auto decodeWithLimit = [&](uint64_t limit, std::string& error) {
    int decoded = 0;
    try {
      StreamDecoder decoder(coded.stream.data(), coded.stream.size(), "order.3dvo");
      decoder.setMaxVertexFramesPerByte(limit);
      decoder.decode([&](int, const IntMesh&) { ++decoded; });
    } catch (const Error& e) {
      error = e.what();
    }
    return decoded;
  };
  std::string error;
  EXPECT_EQ(decodeWithLimit(need1, error), 100) << error;
  EXPECT_EQ(decodeWithLimit(need1 - 1, error), 50);
  EXPECT_NE(
      error.find("order.3dvo: unit " + std::to_string(index1) + " (GOM_HEADER) at byte " +
                 std::to_string(offset1) + ": 50 frames x " + std::to_string(n) + " vertices"),
      std::string::npos)
      << error;
}

// ---- Real data ----

std::vector<Mesh> readFrames(const std::string& pattern, int first, int count) {
  std::vector<Mesh> out;
  for (int k = 0; k < count; ++k) {
    const std::string path = framePath(pattern, first + k);
    if (!std::filesystem::exists(path)) return {};
    out.push_back(readObj(path));
  }
  return out;
}

// Acceptance: horse-gallop, GOMSize 16 (3 GOMs), MotionQuantStep 1: every frame by index
// within half a grid step, triangles as input; with a random access point at every GOM and
// with the later GOMs continuing the first one's connectivity.
TEST(InputOrderData, HorseGallopThreeGoms) {
  const std::string pattern =
      std::string(TDVO_SHARED_DATA_DIR) + "/meshseq/horse-gallop/%04d.obj.gz";
  const std::vector<Mesh> frames = readFrames(pattern, 1, 48);
  if (frames.empty()) GTEST_SKIP() << "horse-gallop data not found (" << pattern << ")";
  for (int period : {1, 0}) {
    SCOPED_TRACE("RandomAccessPeriod " + std::to_string(period));
    const EncodedSequence coded = encode(frames, PMeshMode::kD3dmc, 16, period);
    const Decoded d = decodeAll(coded.stream);
    expectInputOrder(frames, d);
    EXPECT_EQ(test::countUnits(coded.stream, UnitType::kIMesh), period == 1 ? 3u : 1u);
  }
}

// Acceptance: a tvmc-varying sequence in intra mode, each frame its own connectivity and
// order, degenerate triangles included (frames 11, 12, 15 and 16 have two each: issue 17 point
// 6; they come back in place). Frame 17 has a patch of 18 vertices, every one at the position of
// another vertex, triangulated differently on top of each other: position and connectivity
// cannot tell those copies apart, Draco's own record of the coded corners can (imesh_encoder.h).
// Vertices and triangles are exact by index in every frame.
TEST(InputOrderData, TvmcVaryingIntra) {
  const std::string pattern =
      std::string(TDVO_SHARED_DATA_DIR) + "/meshseq/tvmc-varying/basketball_player_fr%04d.obj.gz";
  std::vector<Mesh> frames;
  size_t degenerate = 0;
  for (int f = 11; f <= 17; ++f) {
    const std::string path = framePath(pattern, f);
    if (!std::filesystem::exists(path)) break;
    frames.push_back(readObj(path));
    for (const Triangle& t : frames.back().triangles)
      degenerate += t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
  }
  if (frames.size() < 7) GTEST_SKIP() << "tvmc-varying data not found (" << pattern << ")";
  EXPECT_EQ(degenerate, 8u);
  ASSERT_NE(frames[0].positions.size(), frames[1].positions.size());  // varying connectivity
  const EncodedSequence coded = encode(frames, PMeshMode::kIntra, 1, 1);
  expectInputOrder(frames, decodeAll(coded.stream));
}

}  // namespace
}  // namespace tdvo
