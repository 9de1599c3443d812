// The GOM decoding process, written once (decoder/gom_decoder.h): the encoder's closed loop
// (encodeGomGeometry) makes its frames with a GomDecoder, so the frames it reports must be what
// a GomDecoder makes of the GOM's units alone, asking for them exactly in the order the encoder
// wrote them; and the texture pass's second GomDecoder, started from the first one's first
// reference and the kept P-mesh payloads, must make the same frames again.
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "bitstream/syntax.h"
#include "common/core/error.h"
#include "common/geometry/keyframes.h"
#include "decoder/gom_decoder.h"
#include "decoder/imesh_decoder.h"
#include "encoder/gom_coder.h"
#include "encoder/sequence_encoder.h"
#include "tests/test_support.h"

namespace tdvo {
namespace {

template <class T>
T parse(const std::vector<uint8_t>& payload) {
  T value;
  ByteReader reader(payload.data(), payload.size(), "test unit", 0);
  transfer(reader, value);
  reader.expectEnd("the unit");
  return value;
}

// A GOM's units as the encoder wrote them, handed out strictly in that order: every request
// must be for the next unit (its type and frame), or the test fails.
class CodedUnits : public GomUnits {
 public:
  CodedUnits(const GomGeometry& gom, int gridBits) : gom_(gom), gridBits_(gridBits) {
    header_ = parse<GomHeader>(next(UnitType::kGomHeader).payload);
  }
  const GomHeader& header() const { return header_; }
  bool allTaken() const { return taken_ == gom_.units.size(); }
  const std::vector<std::vector<uint8_t>>& pMeshPayloads() const { return pMeshes_; }

  void iMesh(uint32_t k, IntMesh& mesh, std::string& where) override {
    const IMeshUnit im = parse<IMeshUnit>(next(UnitType::kIMesh).payload);
    EXPECT_EQ(im.im_frame, header_.gh_first_frame + k);
    const VertexOrderUnit vo = parse<VertexOrderUnit>(next(UnitType::kVertexOrder).payload);
    EXPECT_EQ(vo.vo_frame, header_.gh_first_frame + k);
    mesh = decodeIMesh(im.im_draco_payload, gridBits_, "test I mesh");
    where = "test I mesh";
  }
  const std::vector<uint32_t>& askedPMeshes() const { return asked_; }

  PMeshPayload pMesh(uint32_t k) override {
    const PMeshUnit pm = parse<PMeshUnit>(next(UnitType::kPMesh).payload);
    EXPECT_EQ(pm.pm_frame, header_.gh_first_frame + k);
    asked_.push_back(k);
    pMeshes_.push_back(pm.pm_cabac_payload);
    return {pMeshes_.back().data(), pMeshes_.back().size(), "test P mesh", nullptr};
  }

 private:
  const GomGeometry::Unit& next(UnitType type) {
    if (taken_ >= gom_.units.size()) throw std::logic_error("a unit past the GOM's units");
    const GomGeometry::Unit& unit = gom_.units[taken_++];
    if (unit.type != type)
      throw std::logic_error("unit " + std::to_string(taken_ - 1) + " is not the one asked for");
    return unit;
  }

  const GomGeometry& gom_;
  int gridBits_;
  size_t taken_ = 0;
  GomHeader header_;
  std::vector<std::vector<uint8_t>> pMeshes_;
  std::vector<uint32_t> asked_;
};

// Replays kept P-mesh payloads (the texture pass's KeptUnits, for P-mesh GOMs).
class KeptPMeshes : public GomUnits {
 public:
  explicit KeptPMeshes(const std::vector<std::vector<uint8_t>>& payloads) : payloads_(payloads) {}
  void iMesh(uint32_t, IntMesh&, std::string&) override {
    throw std::logic_error("the replay of a P-mesh GOM asked for an I mesh");
  }
  PMeshPayload pMesh(uint32_t) override {
    const std::vector<uint8_t>& p = payloads_.at(next_++);
    return {p.data(), p.size(), "kept P mesh", nullptr};
  }

 private:
  const std::vector<std::vector<uint8_t>>& payloads_;
  size_t next_ = 0;
};

struct Case {
  const char* name;
  PMeshMode mode;
  int gomSize;
  int quantStep;
  int keyframeCount;
  int keyframeMaxError;
  bool continueGoms;  // every GOM after the first continues the previous one
  int bMeshGap = 0;
};

// Codes `frames` GOM by GOM with encodeGomGeometry (continuing GOMs as asked), then decodes
// each GOM's units with one GomDecoder (which continues GOMs by itself, as in the stream
// decoder) and replays each P-mesh GOM with a second one from the first reference.
void checkCase(const Case& c, const std::vector<Mesh>& frames) {
  SCOPED_TRACE(c.name);
  EncoderParams params;
  params.gridBits = 11;
  params.pmeshMode = c.mode;
  params.motionQuantStep = c.quantStep;
  params.keyframeCount = c.keyframeCount;
  params.keyframeMaxError = c.keyframeMaxError;
  params.bMeshGap = c.bMeshGap;
  const Grid grid = gridForSequence(frames, params.gridBits);
  const std::function<std::string(size_t)> name = [](size_t k) {
    return "frame " + std::to_string(k);
  };

  GomDecoder decoder, replay;
  decoder.keepFirstReference(true);
  GomContinuation continuation;
  size_t gomsContinued = 0, keyframesInterpolated = 0, bMeshGoms = 0;
  for (size_t first = 0; first < frames.size(); first += static_cast<size_t>(c.gomSize)) {
    const size_t count = std::min(frames.size() - first, static_cast<size_t>(c.gomSize));
    const std::vector<Mesh> gomFrames(frames.begin() + static_cast<std::ptrdiff_t>(first),
                                      frames.begin() + static_cast<std::ptrdiff_t>(first + count));
    const bool continuing = c.continueGoms && first > 0;
    const GomGeometry coded = encodeGomGeometry(
        params, grid, first, gomFrames, name, continuing ? &continuation : nullptr, &continuation);
    ASSERT_EQ(coded.frames.size(), count);

    CodedUnits units(coded, params.gridBits);
    const GomHeader& gh = units.header();
    gomsContinued += gh.gh_random_access == 0 && c.mode != PMeshMode::kIntra;
    keyframesInterpolated += count - gh.keyframes.size();
    bMeshGoms += hasBMeshes(gh);
    decoder.start(gh, params.gridBits, "test GOM");
    for (size_t k = 0; k < count; ++k) {
      ASSERT_FALSE(decoder.done());
      const std::vector<Vec3i>& positions = decoder.next(units);
      const GomGeometry::Frame& expected = coded.frames[k];
      ASSERT_EQ(positions, expected.positions) << "frame " << first + k;
      ASSERT_EQ(decoder.triangles(), coded.iMeshes[expected.iMesh].decoded.triangles);
    }
    EXPECT_TRUE(decoder.done());
    EXPECT_TRUE(units.allTaken()) << "the decoder left units of GOM " << first << " unread";

    if (c.mode == PMeshMode::kIntra) continue;
    // The texture pass: the same frames from the first reference and the kept payloads.
    KeptPMeshes kept(units.pMeshPayloads());
    replay.start(gh, params.gridBits, "test GOM", &decoder.firstReference());
    for (size_t k = 0; k < count; ++k)
      ASSERT_EQ(replay.next(kept), coded.frames[k].positions) << "replayed frame " << first + k;
  }
  if (c.continueGoms && c.mode != PMeshMode::kIntra) {
    EXPECT_GT(gomsContinued, 0u);
  }
  if (c.keyframeCount > 0 || c.keyframeMaxError > 0) {
    EXPECT_GT(keyframesInterpolated, 0u);
  }
  if (c.bMeshGap > 0) {
    EXPECT_GT(bMeshGoms, 0u);
  }
}

const Case kCases[] = {
    {"intra", PMeshMode::kIntra, 3, 1, 0, 0, false},
    {"d3dmc lossless", PMeshMode::kD3dmc, 4, 1, 0, 0, false},
    {"d3dmc q4 keyframes", PMeshMode::kD3dmc, 6, 4, 3, 0, false},
    {"d3dmc continued", PMeshMode::kD3dmc, 3, 2, 0, 0, true},
    {"d3dmc continued keyframes", PMeshMode::kD3dmc, 5, 1, 3, 0, true},
    {"afxic", PMeshMode::kAfxic, 4, 1, 0, 0, false},
    {"afxic max error continued", PMeshMode::kAfxic, 6, 4, 0, 200, true},
    {"d3dmc B meshes", PMeshMode::kD3dmc, 12, 2, 0, 0, false, 4},
    {"d3dmc B meshes continued", PMeshMode::kD3dmc, 5, 1, 0, 0, true, 3},
    {"d3dmc B meshes, one gap", PMeshMode::kD3dmc, 12, 4, 0, 0, false, 11},
};

// The B meshes between decoded frames l < r in the order of docs/bitstream.md ("B meshes").
void bMeshOrder(int l, int r, std::vector<uint32_t>& out) {
  if (r - l < 2) return;
  const int m = l + (r - l) / 2;
  out.push_back(static_cast<uint32_t>(m));
  bMeshOrder(l, m, out);
  bMeshOrder(m, r, out);
}

EncoderParams bMeshParams(int gridBits, int motionQuantStep, int bMeshGap) {
  EncoderParams params;
  params.gridBits = gridBits;
  params.motionQuantStep = motionQuantStep;
  params.bMeshGap = bMeshGap;
  return params;
}

// `frames` coded as one GOM on the grid over them.
GomGeometry codeOneGom(const EncoderParams& params, const std::vector<Mesh>& frames) {
  return encodeGomGeometry(
      params, gridForSequence(frames, params.gridBits), 0, frames,
      [](size_t k) { return std::to_string(k); }, nullptr, nullptr);
}

// A GOM of 41 frames with BMeshGap 32: keyframes 0, 32 and 40. The decoder asks for the B meshes
// in the documented order, holds no more than log2(32) + 1 frames waiting, and makes the
// encoder's frames.
TEST(GomDecoder, BMeshesComeInHalvingOrderWithFewFramesWaiting) {
  const std::vector<Mesh> frames = test::wobblingSphere(1, 41);
  const EncoderParams params = bMeshParams(11, 2, 32);
  const GomGeometry coded = codeOneGom(params, frames);
  CodedUnits units(coded, params.gridBits);
  ASSERT_TRUE(hasBMeshes(units.header()));
  EXPECT_EQ(units.header().gh_bmesh_quant_step, 4);
  EXPECT_EQ(units.header().keyframes, (std::vector<uint16_t>{0, 32, 40}));
  GomDecoder decoder;
  decoder.start(units.header(), params.gridBits, "test GOM");
  size_t mostWaiting = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    ASSERT_EQ(decoder.next(units), coded.frames[k].positions) << k;
    mostWaiting = std::max(mostWaiting, decoder.waitingFrames());
  }
  EXPECT_TRUE(units.allTaken());
  std::vector<uint32_t> expected = {32};
  bMeshOrder(0, 32, expected);
  expected.push_back(40);
  bMeshOrder(32, 40, expected);
  EXPECT_EQ(units.askedPMeshes(), expected);
  EXPECT_LE(mostWaiting, 6u);
  EXPECT_GE(mostWaiting, 4u);  // the halving path really is held
}

// bMeshLevel is the depth of the halving recursion bMeshOrder walks (1 at the middle frame).
void bMeshLevels(int l, int r, int level, std::vector<int>& out) {
  if (r - l < 2) return;
  const int m = l + (r - l) / 2;
  out[static_cast<size_t>(m)] = level;
  bMeshLevels(l, m, level + 1, out);
  bMeshLevels(m, r, level + 1, out);
}

TEST(BMeshLevel, IsTheDepthOfTheHalving) {
  for (int a : {0, 5})
    for (int gap = 2; gap <= 70; ++gap) {
      std::vector<int> levels(static_cast<size_t>(a + gap + 1), 0);
      bMeshLevels(a, a + gap, 1, levels);
      for (int f = a + 1; f < a + gap; ++f)
        ASSERT_EQ(bMeshLevel(a, a + gap, f), levels[static_cast<size_t>(f)]) << a << " " << gap;
    }
  EXPECT_EQ(bMeshLevel(0, 8, 4), 1);
  EXPECT_EQ(bMeshLevel(0, 8, 6), 2);
  EXPECT_EQ(bMeshLevel(0, 8, 7), 3);
}

// BMeshLambdaGrowth scales the Lambda of the B meshes below the first level only: the keyframes'
// P meshes and the middle frame's B mesh are the same bytes with any growth, deeper B meshes
// take fewer bytes with a larger one.
TEST(GomCoder, BMeshLambdaGrowsPerLevelBelowTheFirst) {
  const std::vector<Mesh> frames = test::wobblingSphere(2, 17);
  EncoderParams params = bMeshParams(12, 2, 8);
  std::map<uint32_t, std::vector<uint8_t>> units[2];
  for (int i = 0; i < 2; ++i) {
    params.bMeshLambdaGrowth = i == 0 ? 1 : 8;
    const GomGeometry coded = codeOneGom(params, frames);
    for (const GomGeometry::Unit& u : coded.units)
      if (u.type == UnitType::kPMesh) {
        const PMeshUnit pm = parse<PMeshUnit>(u.payload);
        units[i][pm.pm_frame] = pm.pm_cabac_payload;
      }
  }
  ASSERT_EQ(units[0].size(), 16u);
  ASSERT_EQ(units[1].size(), 16u);
  for (uint32_t k : {8u, 16u, 4u, 12u})
    EXPECT_EQ(units[0][k], units[1][k]) << "frame " << k;
  size_t deep[2] = {0, 0};
  for (int i = 0; i < 2; ++i)
    for (uint32_t k : {1u, 3u, 5u, 7u, 9u, 11u, 13u, 15u})
      deep[i] += units[i][k].size();
  EXPECT_LT(deep[1], deep[0]);
}

TEST(GomDecoder, MakesTheEncodersFramesFromItsUnitsInTheirOrder) {
  const std::vector<Mesh> sphere = test::wobblingSphere(2, 12);
  for (const Case& c : kCases)
    checkCase(c, sphere);
}

TEST(GomDecoder, MakesTheEncodersFramesOnASheetWithBorders) {
  const std::vector<Mesh> sheet = test::waveSheet(9, 7, 10);
  for (const Case& c : kCases)
    checkCase(c, sheet);
}

GomHeader header(PMeshMode mode, uint8_t randomAccess, uint8_t depth) {
  GomHeader gh;
  gh.gh_frame_count = 2;
  gh.gh_pmesh_mode = static_cast<uint8_t>(mode);
  gh.gh_random_access = randomAccess;
  gh.gh_max_octree_depth = depth;
  gh.keyframes = {0, 1};
  return gh;
}

void expectError(const std::function<void()>& f, const std::string& part) {
  try {
    f();
    ADD_FAILURE() << "no error; expected one containing: " << part;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(GomDecoder, RefusesToContinueNothingAndTooDeepOctrees) {
  GomDecoder d;
  expectError([&] { d.start(header(PMeshMode::kD3dmc, 0, 8), 10, "GOM at 0"); },
              "GOM at 0: gh_random_access 0, but no previous GOM of P meshes to continue");
  expectError([&] { d.start(header(PMeshMode::kD3dmc, 1, 11), 10, "GOM at 0"); },
              "GOM at 0: gh_max_octree_depth 11 exceeds sh_grid_bits 10");
  // After a GOM of P meshes a GOM may continue; after an intra GOM (or clearContinuation) not.
  d.start(header(PMeshMode::kAfxic, 1, 8), 10, "GOM at 0");
  EXPECT_TRUE(d.canContinue());
  d.start(header(PMeshMode::kIntra, 1, 8), 10, "GOM at 2");
  expectError([&] { d.start(header(PMeshMode::kAfxic, 0, 8), 10, "GOM at 4"); },
              "GOM at 4: gh_random_access 0");
  d.start(header(PMeshMode::kAfxic, 1, 8), 10, "GOM at 4");
  d.clearContinuation();
  expectError([&] { d.start(header(PMeshMode::kAfxic, 0, 8), 10, "GOM at 6"); },
              "GOM at 6: gh_random_access 0");
}

}  // namespace
}  // namespace tdvo
