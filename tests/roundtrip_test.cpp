// Encode → decode round trips at library level (encoder/sequence_encoder.h,
// decoder/stream_decoder.h) on generated deforming mesh sequences: the encoder's reconstruction
// equals the decoder's output (MD5 lines and meshes), every decoded vertex lies within half a
// grid step of its input vertex, and the decoded connectivity is the input's up to Draco's
// vertex permutation. Also: the stream decoder rejects every truncation and every flipped byte.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "bitstream/units.h"
#include "common/core/error.h"
#include "common/core/md5.h"
#include "decoder/imesh_decoder.h"
#include "decoder/stream_decoder.h"
#include "encoder/imesh_encoder.h"
#include "encoder/sequence_encoder.h"
#include "tests/roundtrip_check.h"
#include "tests/test_support.h"

namespace tdvo {
namespace {

using test::canonicalSorted;
using test::checkRoundTrip;
using test::decodedAsInput;
using test::encodeAndDecode;
using test::RoundTrip;

EncoderParams paramsFor(int gridBits, int gomSize, PMeshMode mode) {
  EncoderParams p;
  p.gridBits = gridBits;
  p.gomSize = gomSize;
  p.pmeshMode = mode;
  p.frameRate = 30;
  return p;
}

struct Case {
  const char* mesh;
  int gridBits;
  int gomSize;
  PMeshMode mode;
};

std::string caseName(const testing::TestParamInfo<Case>& info) {
  return std::string(info.param.mesh) + "_bits" + std::to_string(info.param.gridBits) + "_gom" +
         std::to_string(info.param.gomSize) +
         (info.param.mode == PMeshMode::kIntra ? "_intra" : "_d3dmc");
}

std::vector<Mesh> meshesFor(const std::string& name) {
  if (name == "sphere") return test::wobblingSphere(3, 12, 2.0, {1, -4, 0.5});  // 642 vertices
  return test::waveSheet(20, 15, 14);                                           // 300 vertices
}

class RoundTripTest : public testing::TestWithParam<Case> {};

TEST_P(RoundTripTest, EncoderAndDecoderAgree) {
  const Case& c = GetParam();
  const std::vector<Mesh> frames = meshesFor(c.mesh);
  const RoundTrip r = encodeAndDecode(frames, paramsFor(c.gridBits, c.gomSize, c.mode));
  checkRoundTrip(frames, r);
  // GOM structure: one I mesh per GOM, P meshes (if any) for the rest.
  const size_t goms = (frames.size() + c.gomSize - 1) / c.gomSize;
  if (c.mode == PMeshMode::kIntra || c.gomSize == 1) {
    EXPECT_EQ(r.coded.pMeshBytes, 0u);
  } else {
    EXPECT_GT(r.coded.pMeshBytes, 0u);
  }
  // Magic, sequence header (54 bytes without cameras: version 3 has sh_attributes_present)
  // and one GOM header per GOM (7 bytes when intra).
  if (c.mode == PMeshMode::kIntra) {
    EXPECT_EQ(r.coded.headerBytes, 4 + kUnitOverhead * (1 + goms) + 54 + goms * 7);
  }
}

INSTANTIATE_TEST_SUITE_P(Generated, RoundTripTest,
                         testing::Values(Case{"sphere", 8, 1, PMeshMode::kIntra},
                                         Case{"sphere", 12, 5, PMeshMode::kIntra},
                                         Case{"sphere", 16, 12, PMeshMode::kIntra},
                                         Case{"sphere", 20, 100, PMeshMode::kIntra},
                                         Case{"sheet", 10, 1, PMeshMode::kIntra},
                                         Case{"sheet", 12, 4, PMeshMode::kIntra},
                                         Case{"sphere", 8, 4, PMeshMode::kD3dmc},
                                         Case{"sphere", 12, 12, PMeshMode::kD3dmc},
                                         Case{"sphere", 20, 5, PMeshMode::kD3dmc},
                                         Case{"sheet", 12, 16, PMeshMode::kD3dmc},
                                         Case{"sheet", 16, 3, PMeshMode::kD3dmc}),
                         caseName);

// ---- Duplicate vertex positions (recoverVertexOrder, encoder/imesh_encoder.h) ----

// A wave sheet cut along the column x = cut: the vertices of that column are duplicated and the
// triangles right of the cut use the copies. At frame 0 both sides meet exactly (every seam
// position occurs twice); with `open`, the right side lifts off in later frames.
std::vector<Mesh> seamSheet(int nx, int ny, int cut, int frames, bool open) {
  std::vector<Mesh> out = test::waveSheet(nx, ny, frames);
  for (int f = 0; f < frames; ++f) {
    Mesh& m = out[f];
    std::vector<uint32_t> copy(m.positions.size(), UINT32_MAX);
    for (int y = 0; y < ny; ++y) {
      const uint32_t v = static_cast<uint32_t>(y * nx + cut);
      copy[v] = static_cast<uint32_t>(m.positions.size());
      m.positions.push_back(m.positions[v]);
    }
    for (Triangle& t : m.triangles) {
      bool right = false;
      for (uint32_t v : t)
        right = right || static_cast<int>(v % nx) > cut;
      if (right)
        for (uint32_t& v : t)
          if (copy[v] != UINT32_MAX) v = copy[v];
    }
    if (open)
      for (size_t v = 0; v < m.positions.size(); ++v)
        if (v >= static_cast<size_t>(nx * ny) || static_cast<int>(v % nx) > cut)
          m.positions[v][2] += 0.02 * f;
  }
  return out;
}

TEST(DuplicatePositions, SeamResolvedThroughConnectivity) {
  for (PMeshMode mode : {PMeshMode::kIntra, PMeshMode::kD3dmc})
    for (bool open : {false, true}) {
      SCOPED_TRACE(std::string(mode == PMeshMode::kIntra ? "intra" : "d3dmc") +
                   (open ? ", seam opens" : ", seam stays closed"));
      const std::vector<Mesh> frames = seamSheet(16, 12, 7, 10, open);
      ASSERT_EQ(frames[0].positions.size(), 16u * 12 + 12);
      const RoundTrip r = encodeAndDecode(frames, paramsFor(12, 10, mode));
      checkRoundTrip(frames, r);
    }
}

// Two identical copies of a sphere at the same place in the first frame: no vertex has a unique
// position, so only step 3 of recoverVertexOrder can resolve them. The copies then drift apart.
TEST(DuplicatePositions, CoincidentComponents) {
  const std::vector<Mesh> a = test::wobblingSphere(2, 8);
  std::vector<Mesh> frames;
  for (size_t f = 0; f < a.size(); ++f) {
    Mesh m = a[f];
    const uint32_t n = static_cast<uint32_t>(m.positions.size());
    for (uint32_t v = 0; v < n; ++v)
      m.positions.push_back(
          {a[f].positions[v][0], a[f].positions[v][1] + 0.3 * f, a[f].positions[v][2]});
    for (size_t t = 0, count = m.triangles.size(); t < count; ++t)
      m.triangles.push_back({m.triangles[t][0] + n, m.triangles[t][1] + n, m.triangles[t][2] + n});
    frames.push_back(std::move(m));
  }
  for (PMeshMode mode : {PMeshMode::kIntra, PMeshMode::kD3dmc}) {
    SCOPED_TRACE(mode == PMeshMode::kIntra ? "intra" : "d3dmc");
    checkRoundTrip(frames, encodeAndDecode(frames, paramsFor(12, 8, mode)));
  }
}

TEST(DuplicatePositions, RecoverVertexOrderDirectly) {
  // Two triangles sharing an edge, and a third vertex position used twice: 0 and 4 coincide.
  IntMesh input;
  input.positions = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {10, 10, 0}, {0, 0, 0}, {20, 0, 0}};
  input.triangles = {{0, 1, 2}, {1, 3, 2}, {4, 5, 1}};
  // The same mesh with its vertices in another order: decoded j is input perm[j].
  const std::vector<uint32_t> perm = {5, 4, 3, 2, 1, 0};
  std::vector<uint32_t> inverse(perm.size());
  for (uint32_t j = 0; j < perm.size(); ++j)
    inverse[perm[j]] = j;
  IntMesh decoded;
  for (uint32_t j = 0; j < perm.size(); ++j)
    decoded.positions.push_back(input.positions[perm[j]]);
  for (const Triangle& t : input.triangles)
    decoded.triangles.push_back({inverse[t[1]], inverse[t[2]], inverse[t[0]]});
  size_t unmatched = 99;
  EXPECT_EQ(recoverVertexOrder(input, decoded, &unmatched), perm);
  EXPECT_EQ(unmatched, 0u);
}

TEST(DuplicatePositions, DracoRoundTripOfTheSeam) {
  const std::vector<Mesh> frames = seamSheet(10, 8, 4, 1, false);
  const Grid grid = gridForSequence(frames, 12);
  const IntMesh input = grid.quantise(frames[0]);
  const IMeshEncoding coded = encodeIMesh(input, 12, 0);
  EXPECT_EQ(coded.unmatchedTriangles, 0u);
  ASSERT_EQ(coded.decoded.positions.size(), input.positions.size());
  for (size_t j = 0; j < coded.inputIndex.size(); ++j)
    EXPECT_EQ(coded.decoded.positions[j], input.positions[coded.inputIndex[j]]);
  EXPECT_EQ(decodedAsInput(coded.decoded, coded.inputIndex), canonicalSorted(input.triangles));
}

// IMeshQuantStep (im_quant_step): the I mesh rounded to multiples of the step, at most
// 2^gridBits - 1, in the input's vertex order, decoded alike by the decoder, and smaller.
TEST(IMeshQuantStep, RoundsToMultiplesOfTheStepInTheInputsOrder) {
  EXPECT_EQ(iMeshQuantise(4095, 12, 4), 1023);  // 4096 would leave the grid: 4092
  EXPECT_EQ(iMeshQuantise(4095, 12, 2), 2047);
  EXPECT_EQ(iMeshQuantise(4094, 12, 3), 1365);  // 4095
  EXPECT_EQ(iMeshQuantise(5, 12, 4), 1);
  EXPECT_EQ(iMeshQuantise(6, 12, 4), 2);  // ties round up
  EXPECT_EQ(iMeshQuantise(0, 12, 7), 0);
  const std::vector<Mesh> frames = seamSheet(10, 8, 4, 1, false);
  const Grid grid = gridForSequence(frames, 12);
  const IntMesh input = grid.quantise(frames[0]);
  const IMeshEncoding lossless = encodeIMesh(input, 12, 0);
  for (int step : {3, 4, 7}) {
    SCOPED_TRACE("step " + std::to_string(step));
    const IMeshEncoding coded = encodeIMesh(input, 12, 0, true, step);
    EXPECT_EQ(coded.quantStep, step);
    EXPECT_EQ(coded.unmatchedTriangles, 0u);
    EXPECT_EQ(coded.inputIndex, lossless.inputIndex);
    EXPECT_EQ(coded.orderPayload, lossless.orderPayload);
    ASSERT_EQ(coded.decoded.positions.size(), input.positions.size());
    for (size_t j = 0; j < coded.inputIndex.size(); ++j)
      for (int a = 0; a < 3; ++a) {
        const int32_t c = input.positions[coded.inputIndex[j]][a];
        const int32_t d = coded.decoded.positions[j][a];
        EXPECT_EQ(d, iMeshQuantise(c, 12, step) * step);
        // The nearest multiple, unless that is past the grid's last point 4095.
        EXPECT_LE(std::abs(d - c), d + step > 4095 ? step - 1 : step / 2);
      }
    // The payload holds the values divided by the step: read with step 1, they are.
    IntMesh values = decodeIMesh(coded.payload, 12, "x", 0, 0, 1);
    for (Vec3i& p : values.positions)
      for (int32_t& c : p)
        c *= step;
    EXPECT_EQ(values.positions, coded.decoded.positions);
    EXPECT_LT(coded.payload.size(), lossless.payload.size());
  }
  // Draco's values times the step must stay on the grid: the lossless payload's values reach
  // 4095, more than 4095 / 2.
  EXPECT_NE(test::errorOf([&] {
              decodeIMesh(lossless.payload, 12, "x", 0, 0, 2);
            }).find("outside the grid [0, 2047] (divided by im_quant_step 2)"),
            std::string::npos);
}

// An edge used by three triangles, two of them in the same direction (0->1), and a triangle
// over the same positions as one of them built from a copy (4) of vertex 1: the directed edge
// 2->0 has two third vertices at one position (1 and 4). Both the exact mapping's check and the
// matcher once kept one third vertex per directed edge: the check rejected the exact mapping
// and the matcher merged 4 into 1 (4 output vertices, triangle {0, 4, 2} output as {0, 1, 2}).
TEST(DuplicatePositions, NonManifoldEdgeWithCoincidentThirdVertices) {
  IntMesh input;
  input.positions = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}, {10, 0, 0}};
  input.triangles = {{0, 1, 2}, {0, 1, 3}, {1, 0, 2}, {0, 4, 2}};
  for (int speed : {0, 5, 10})
    for (bool triangleOrder : {true, false}) {
      SCOPED_TRACE("Draco speed " + std::to_string(speed) +
                   (triangleOrder ? ", triangle order" : ", coding order"));
      const IMeshEncoding coded = encodeIMesh(input, 12, speed, triangleOrder);
      EXPECT_EQ(coded.unmatchedTriangles, 0u);
      EXPECT_EQ(decodedAsInput(coded.decoded, coded.inputIndex), canonicalSorted(input.triangles));
      EXPECT_EQ(coded.order.numVertices, 5u);
      if (triangleOrder) {
        EXPECT_EQ(coded.order.triangles, input.triangles);
      }
      size_t unmatched = 99;
      EXPECT_EQ(decodedAsInput(coded.decoded, recoverVertexOrder(input, coded.decoded, &unmatched)),
                canonicalSorted(input.triangles));
      EXPECT_EQ(unmatched, 0u);
    }
}

// A fin: three triangles on one edge in the same direction, their third vertices at one
// position. Each decoded triangle must be an input triangle of its own: the check once let all
// three pass as the first one (3 output vertices, the same triangle three times, no warning).
TEST(DuplicatePositions, FinOfThreeTrianglesWithCoincidentThirdVertices) {
  IntMesh input;
  input.positions = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 10, 0}, {0, 10, 0}};
  input.triangles = {{0, 1, 2}, {0, 1, 3}, {0, 1, 4}};
  for (int speed : {0, 10}) {
    SCOPED_TRACE("Draco speed " + std::to_string(speed));
    const IMeshEncoding coded = encodeIMesh(input, 12, speed, true);
    EXPECT_EQ(coded.unmatchedTriangles, 0u);
    EXPECT_EQ(coded.order.numVertices, 5u);
    EXPECT_EQ(coded.order.triangles, input.triangles);
  }
}

// Two copies of a sheet at the same place, triangulated with opposite diagonals (as in frame 17
// of tvmc-varying): every vertex has a twin at its position in the same surroundings of
// positions, so position and connectivity cannot tell the copies apart (the matcher,
// recoverVertexOrder, gets some triangles wrong). The encoder takes the mapping from Draco's own
// encoder instead: exact, every decoded triangle is an input triangle.
TEST(DuplicatePositions, DoubledSurfaceTriangulatedTwoWays) {
  IntMesh input;
  const uint32_t w = 6;
  for (int copy = 0; copy < 2; ++copy)
    for (uint32_t y = 0; y < w; ++y)
      for (uint32_t x = 0; x < w; ++x)
        input.positions.push_back({int32_t(10 * x), int32_t(10 * y), int32_t((x * y) % 3)});
  for (uint32_t copy = 0; copy < 2; ++copy)
    for (uint32_t y = 0; y + 1 < w; ++y)
      for (uint32_t x = 0; x + 1 < w; ++x) {
        const uint32_t o = copy * w * w, a = o + y * w + x, b = a + 1, c = a + w, d = c + 1;
        if (copy == 0) {
          input.triangles.push_back({a, b, d});
          input.triangles.push_back({a, d, c});
        } else {
          input.triangles.push_back({a, b, c});
          input.triangles.push_back({b, d, c});
        }
      }
  IMeshEncoding coded;
  for (int speed : {0, 5, 10}) {
    SCOPED_TRACE("Draco speed " + std::to_string(speed));
    coded = encodeIMesh(input, 12, speed);
    EXPECT_EQ(coded.unmatchedTriangles, 0u);
    ASSERT_EQ(coded.decoded.positions.size(), input.positions.size());
    EXPECT_EQ(decodedAsInput(coded.decoded, coded.inputIndex), canonicalSorted(input.triangles));
    EXPECT_EQ(coded.order.triangles, input.triangles);
  }
  size_t unmatched = 0;
  recoverVertexOrder(input, coded.decoded, &unmatched);
  EXPECT_GT(unmatched, 0u) << "the matcher alone tells the copies apart: this test no longer "
                              "shows what the exact mapping adds";
}

// Draco's Edgebreaker coder keeps only vertices that some triangle uses: an unreferenced input
// vertex is not decoded (the frame's decoded vertex count is one less), and every decoded vertex
// still maps to its own input vertex.
TEST(UnreferencedVertices, AreNotDecoded) {
  std::vector<Mesh> frames = test::waveSheet(8, 6, 3);
  for (Mesh& m : frames)
    m.positions.push_back({0.3, 0.2, 0.5});  // used by no triangle
  const uint32_t unused = static_cast<uint32_t>(frames[0].positions.size() - 1);
  const RoundTrip r = encodeAndDecode(frames, paramsFor(12, 3, PMeshMode::kIntra));
  ASSERT_EQ(r.decoderFrames.size(), frames.size());
  EXPECT_EQ(r.encoderLines, r.decoderLines);
  for (size_t f = 0; f < frames.size(); ++f) {
    EXPECT_EQ(r.decoderFrames[f].positions.size(), frames[f].positions.size() - 1);
    const std::vector<uint32_t>& index = r.coded.frameInputIndex[f];
    EXPECT_EQ(std::count(index.begin(), index.end(), unused), 0);
    EXPECT_EQ(decodedAsInput(r.decoderFrames[f], index), canonicalSorted(frames[f].triangles));
  }
}

// ---- Corrupted and truncated streams ----

struct SmallStream {
  std::vector<uint8_t> bytes;
  std::vector<std::string> lines;
};

// Three frames of a small sphere in two GOMs (I, P | I with d3dmc).
const SmallStream& smallStream(PMeshMode mode) {
  static SmallStream streams[2];
  SmallStream& s = streams[mode == PMeshMode::kIntra ? 0 : 1];
  if (s.bytes.empty()) {
    const std::vector<Mesh> frames = test::wobblingSphere(1, 3);
    const EncoderParams params = paramsFor(10, 2, mode);
    s.bytes = encodeSequence(params, gridForSequence(frames, 10), frames, {},
                             [&](int frame, const IntMesh& mesh) {
                               s.lines.push_back(geometryHashLine(frame, mesh));
                             })
                  .stream;
  }
  return s;
}

// Decodes; returns the error message, or "" when the stream decoded.
std::string decodeError(const std::vector<uint8_t>& stream, size_t size,
                        std::vector<std::string>* lines = nullptr) {
  try {
    StreamDecoder decoder(stream.data(), size, "c.3dvo");
    decoder.decode([&](int frame, const IntMesh& mesh) {
      if (lines) lines->push_back(geometryHashLine(frame, mesh));
    });
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

class CorruptStreamTest : public testing::TestWithParam<PMeshMode> {};

TEST_P(CorruptStreamTest, Intact) {
  const SmallStream& s = smallStream(GetParam());
  std::vector<std::string> lines;
  EXPECT_EQ(decodeError(s.bytes, s.bytes.size(), &lines), "");
  EXPECT_EQ(lines, s.lines);
  ASSERT_EQ(lines.size(), 3u);
}

TEST_P(CorruptStreamTest, EveryTruncationIsAnError) {
  const SmallStream& s = smallStream(GetParam());
  for (size_t length = 0; length < s.bytes.size(); ++length) {
    const std::string message = decodeError(s.bytes, length);
    ASSERT_NE(message, "") << "stream cut to " << length << " bytes decoded without error";
    EXPECT_EQ(message.rfind("c.3dvo: ", 0), 0u) << message;
    if (length >= 4) {
      EXPECT_NE(message.find("truncated"), std::string::npos)
          << "cut to " << length << ": " << message;
    }
  }
}

// A stream that starts at input frame 7 (FirstFrame), cut after its first frame's units: the
// error names the missing frame as the MD5 lines and the output files do (frame 8), with the
// stream's own index beside it, not as "frame 1", which would read as an earlier frame.
TEST_P(CorruptStreamTest, TruncationNamesTheInputFrameNumber) {
  const std::vector<Mesh> frames = test::wobblingSphere(1, 3);
  EncoderParams params = paramsFor(10, 3, GetParam());
  params.firstFrame = 7;
  const std::vector<uint8_t> stream =
      encodeSequence(params, gridForSequence(frames, 10), frames, {}, [](int, const IntMesh&) {
      }).stream;
  // The units' ends: SEQUENCE_HEADER, GOM_HEADER, then frame 7's I mesh and vertex order.
  std::vector<size_t> ends;
  {
    UnitReader reader(stream.data(), stream.size(), "c.3dvo");
    UnitView view;
    while (reader.next(view))
      ends.push_back(view.end());
  }
  ASSERT_GE(ends.size(), 5u);
  std::vector<std::string> lines;
  const std::string message = decodeError(stream, ends[3], &lines);
  ASSERT_EQ(lines.size(), 1u);  // frame 7 was decoded
  const std::string expected = GetParam() == PMeshMode::kIntra
                                   ? "stream ends for frame 8 (stream frame 1) (expected an I_MESH"
                                   : "stream ends for frame 8 (stream frame 1) (expected a P_MESH";
  EXPECT_NE(message.find(expected), std::string::npos) << message;
  // Before the first GOM header: "frame 7 (stream frame 0 of 3)".
  EXPECT_NE(decodeError(stream, ends[0]).find("stream ends before frame 7 (stream frame 0 of 3)"),
            std::string::npos)
      << decodeError(stream, ends[0]);
}

TEST_P(CorruptStreamTest, EveryFlippedByteIsAnErrorNamingTheUnit) {
  const SmallStream& s = smallStream(GetParam());
  for (size_t position = 0; position < s.bytes.size(); ++position)
    for (uint8_t mask : {0x01, 0x80, 0xFF}) {
      std::vector<uint8_t> bad = s.bytes;
      bad[position] ^= mask;
      const std::string message = decodeError(bad, bad.size());
      ASSERT_NE(message, "") << "byte " << position << " ^ " << int(mask) << " not detected";
      if (position >= 4) {
        EXPECT_EQ(message.rfind("c.3dvo: unit ", 0), 0u) << message;
      } else {
        EXPECT_EQ(message.rfind("c.3dvo: not a 3DVO stream", 0), 0u) << message;
      }
    }
}

// Payload corruption that the CRC cannot see (the CRC is recomputed): the decoder must end in
// an Error or a decoded stream, never a crash, and the MD5 lines then differ or the stream was
// unchanged in effect.
TEST_P(CorruptStreamTest, CorruptPayloadWithValidCrcNeverCrashes) {
  const SmallStream& s = smallStream(GetParam());
  struct Unit {
    uint8_t type;
    std::vector<uint8_t> payload;
  };
  std::vector<Unit> units;
  {
    UnitReader reader(s.bytes.data(), s.bytes.size(), "c.3dvo");
    UnitView view;
    while (reader.next(view))
      units.push_back({view.type, std::vector<uint8_t>(view.payload, view.payload + view.size)});
  }
  int errors = 0, decoded = 0;
  for (size_t u = 0; u < units.size(); ++u)
    for (size_t position = 0; position < units[u].payload.size(); position += 1)
      for (uint8_t mask : {0x01, 0x10, 0xFF}) {
        UnitWriter writer;
        for (size_t k = 0; k < units.size(); ++k) {
          std::vector<uint8_t> payload = units[k].payload;
          if (k == u) payload[position] ^= mask;
          writer.write(static_cast<UnitType>(units[k].type), payload);
        }
        const std::string message = decodeError(writer.bytes(), writer.bytes().size());
        if (message.empty()) {
          ++decoded;
        } else {
          ++errors;
          EXPECT_EQ(message.rfind("c.3dvo: ", 0), 0u) << message;
          // Names the unit, or (a sequence header announcing more frames than the stream has)
          // says where the stream ended.
          EXPECT_TRUE(message.find("unit ") != std::string::npos ||
                      message.find("stream ends before frame") != std::string::npos)
              << message;
        }
      }
  EXPECT_GT(errors, 0);
  RecordProperty("decoded_despite_corruption", decoded);
}

INSTANTIATE_TEST_SUITE_P(Modes, CorruptStreamTest,
                         testing::Values(PMeshMode::kIntra, PMeshMode::kD3dmc),
                         [](const testing::TestParamInfo<PMeshMode>& info) {
                           return std::string(info.param == PMeshMode::kIntra ? "intra" : "d3dmc");
                         });

TEST(StreamDecoder, UnitAfterTheLastFrame) {
  const SmallStream& s = smallStream(PMeshMode::kIntra);
  UnitWriter writer;
  std::vector<uint8_t> stream = s.bytes;
  GomHeader gh;
  ByteWriter w;
  transfer(w, gh);
  writer.write(UnitType::kGomHeader, w.data());
  stream.insert(stream.end(), writer.bytes().begin() + 4, writer.bytes().end());
  EXPECT_EQ(decodeError(stream, stream.size()),
            "c.3dvo: unit " + std::to_string(9) + " (GOM_HEADER) at byte " +
                std::to_string(s.bytes.size()) + ": unit after the last frame (sh_frame_count 3)");
}

TEST(StreamDecoder, NotA3dvoStream) {
  const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const std::vector<uint8_t> bytes(text.begin(), text.end());
  EXPECT_EQ(decodeError(bytes, bytes.size()),
            "c.3dvo: not a 3DVO stream (the first four bytes are not \"3DVO\")");
}

// Triangles with a repeated vertex (real captures have them; Draco cannot code them) are kept
// in every mode, in place: the decoded triangle list is the input's, exactly, through I meshes,
// P meshes and GOMs that continue the previous GOM (no I mesh). One warning per I mesh counts
// them. With InputTriangleOrder false they follow the others, in the input's order.
TEST(SequenceEncoder, KeepsDegenerateTrianglesInEveryMode) {
  std::vector<Mesh> frames = test::waveSheet(5, 5, 4);
  for (Mesh& m : frames) {
    m.triangles.insert(m.triangles.begin(), {0, 1, 0});  // position 0
    m.triangles.insert(m.triangles.begin() + 3, {4, 4, 5});
    m.triangles.insert(m.triangles.begin() + 4, {6, 6, 6});  // two in a row
    m.triangles.push_back({7, 8, 7});                        // the last one
  }
  const std::string count = "4 of " + std::to_string(frames[0].triangles.size()) +
                            " triangles have a repeated vertex (degenerate); kept";
  struct Case {
    PMeshMode mode;
    int period;
    size_t warnings;  // one per I mesh
  };
  for (const Case& c :
       {Case{PMeshMode::kIntra, 1, 4}, Case{PMeshMode::kD3dmc, 1, 2}, Case{PMeshMode::kAfxic, 1, 2},
        Case{PMeshMode::kD3dmc, 0, 1}, Case{PMeshMode::kAfxic, 0, 1}}) {
    for (bool inputOrder : {true, false}) {
      SCOPED_TRACE(std::to_string(static_cast<int>(c.mode)) + " period " +
                   std::to_string(c.period) + (inputOrder ? " input order" : " coding order"));
      EncoderParams params = paramsFor(10, 2, c.mode);
      params.randomAccessPeriod = c.period;
      params.inputTriangleOrder = inputOrder;
      testing::internal::CaptureStderr();
      const RoundTrip r = encodeAndDecode(frames, params);
      const std::string err = testing::internal::GetCapturedStderr();
      if (inputOrder) checkRoundTrip(frames, r);  // which also compares the triangle lists
      ASSERT_EQ(r.decoderFrames.size(), frames.size());
      for (size_t f = 0; f < frames.size(); ++f) {
        const std::vector<Triangle>& out = r.decoderFrames[f].triangles;
        if (inputOrder) {
          EXPECT_EQ(out, frames[f].triangles) << "frame " << f;
        } else {
          EXPECT_EQ(out, r.encoderFrames[f].triangles) << "frame " << f;
          EXPECT_EQ(canonicalSorted(out), canonicalSorted(frames[f].triangles)) << "frame " << f;
          ASSERT_EQ(out.size(), frames[f].triangles.size());
          const std::vector<Triangle> last(out.end() - 4, out.end());
          EXPECT_EQ(last, (std::vector<Triangle>{{0, 1, 0}, {4, 4, 5}, {6, 6, 6}, {7, 8, 7}}))
              << "frame " << f;
        }
      }
      size_t warnings = 0;
      for (size_t at = err.find(count); at != std::string::npos; at = err.find(count, at + 1))
        ++warnings;
      EXPECT_EQ(warnings, c.warnings) << err;
    }
  }
}

// A vertex that only degenerate triangles use is not coded (Draco drops vertices no coded
// triangle uses): the triangles using it are dropped too, and the warnings say so.
TEST(SequenceEncoder, DegenerateTriangleOnAnUnusedVertexIsDropped) {
  std::vector<Mesh> frames = test::waveSheet(5, 5, 1);
  Mesh& m = frames[0];
  const uint32_t lone = static_cast<uint32_t>(m.positions.size());
  m.positions.push_back({0.5, 0.5, 0.5});
  m.triangles.insert(m.triangles.begin() + 2, {3, 3, 4});
  m.triangles.insert(m.triangles.begin() + 5, {lone, lone, 1});
  testing::internal::CaptureStderr();
  const RoundTrip r = encodeAndDecode(frames, paramsFor(10, 1, PMeshMode::kIntra));
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("2 of " + std::to_string(m.triangles.size()) +
                     " triangles have a repeated vertex (degenerate); kept (carried outside "
                     "Draco), except 1 using a vertex no other triangle uses: dropped"),
            std::string::npos)
      << err;
  std::vector<Triangle> expected = m.triangles;
  expected.erase(expected.begin() + 5);
  ASSERT_EQ(r.decoderFrames.size(), 1u);
  EXPECT_EQ(r.decoderFrames[0].triangles, expected);
  EXPECT_EQ(r.decoderFrames[0].positions.size(), m.positions.size() - 1);
}

// The dropped-vertex warning counts output vertices, not Draco's: a non-manifold vertex that
// Draco splits in two must not hide a vertex no triangle uses (the counts would agree), and a
// split alone, which the output order merges back, drops nothing.
TEST(SequenceEncoder, AnUnusedVertexIsWarnedAboutBesideANonManifoldOne) {
  Mesh bowtie;  // vertex 0 joins two fans that share nothing else; vertex 5 is unused
  bowtie.positions = {{0, 0, 0},   {1, 1, 0}, {1, -1, 0}, {-1, 1, 0},
                      {-1, -1, 0}, {7, 7, 7}, {2, 2, 2}};
  bowtie.triangles = {{0, 1, 2}, {0, 3, 4}, {1, 6, 2}};
  for (const bool unused : {true, false}) {
    Mesh m = bowtie;
    if (!unused) {
      m.positions.erase(m.positions.begin() + 5);
      m.triangles.back() = {1, 5, 2};
    }
    testing::internal::CaptureStderr();
    const RoundTrip r = encodeAndDecode({m}, paramsFor(10, 1, PMeshMode::kIntra));
    const std::string err = testing::internal::GetCapturedStderr();
    ASSERT_EQ(r.decoderFrames.size(), 1u);
    if (unused) {
      EXPECT_NE(err.find("7 vertices in, 6 out: 1 that no triangle uses are dropped"),
                std::string::npos)
          << err;
      EXPECT_EQ(r.decoderFrames[0].positions.size(), 6u);
      EXPECT_EQ(r.decoderFrames[0].triangles,
                (std::vector<Triangle>{{0, 1, 2}, {0, 3, 4}, {1, 5, 2}}));
    } else {
      EXPECT_EQ(err.find("vertices in"), std::string::npos) << err;
      EXPECT_EQ(r.decoderFrames[0].triangles, m.triangles);
    }
  }
}

// Copies of one triangle, in both orientations and corner rotations, among a sheet's: the
// output is the input's list (the order writer finds the next unused copy in the corner tree,
// not by stepping over the used ones).
TEST(SequenceEncoder, ManyCopiesOfOneTriangleKeepTheirOrder) {
  Mesh m = test::waveSheet(4, 4, 1)[0];
  for (int i = 0; i < 3000; ++i) {
    const Triangle t = i % 3 == 0   ? Triangle{0, 1, 5}
                       : i % 3 == 1 ? Triangle{1, 5, 0}
                                    : Triangle{0, 5, 1};
    m.triangles.insert(m.triangles.begin() + (i * 7) % m.triangles.size(), t);
  }
  testing::internal::CaptureStderr();
  const RoundTrip r = encodeAndDecode({m}, paramsFor(10, 1, PMeshMode::kIntra));
  testing::internal::GetCapturedStderr();
  ASSERT_EQ(r.decoderFrames.size(), 1u);
  EXPECT_EQ(r.decoderFrames[0].triangles, m.triangles);
}

// Nothing but degenerate triangles: no surface to code.
TEST(SequenceEncoder, OnlyDegenerateTrianglesAreRefused) {
  std::vector<Mesh> none = test::waveSheet(5, 5, 1);
  none[0].triangles = {{1, 1, 2}, {3, 4, 4}};
  try {
    encodeSequence(paramsFor(10, 1, PMeshMode::kIntra), gridForSequence(none, 10), none, {"a.obj"},
                   [](int, const IntMesh&) {});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "a.obj: every triangle has a repeated vertex: no triangle is left to code");
  }
}

TEST(SequenceEncoder, PMeshGomNeedsConstantVertexCount) {
  std::vector<Mesh> frames = test::waveSheet(5, 5, 3);
  frames[2] = test::waveSheet(6, 5, 3)[2];
  // Intra coding takes frames of any size.
  checkRoundTrip(frames, encodeAndDecode(frames, paramsFor(10, 3, PMeshMode::kIntra)));
  // P meshes need the first frame's vertices.
  try {
    encodeSequence(paramsFor(10, 3, PMeshMode::kD3dmc), gridForSequence(frames, 10), frames,
                   {"a.obj", "b.obj", "c.obj"}, [](int, const IntMesh&) {});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("c.obj: 30 vertices, but the GOM's first frame (a.obj) "
                                          "has 25",
                                          0),
              0u)
        << e.what();
  }
  // ... unless the odd frame starts its own GOM.
  checkRoundTrip(frames, encodeAndDecode(frames, paramsFor(10, 2, PMeshMode::kD3dmc)));
}

}  // namespace
}  // namespace tdvo
