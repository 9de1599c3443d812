// P-mesh acceptance on the real sequences in ../shared/data/meshseq (skipped, saying so, when
// the data is absent): lossless coding of horse-gallop against intra-only coding, and the
// closed loop and rate behaviour of samba and pcow at several MotionQuantStep values.
#include <gtest/gtest.h>

#include <filesystem>

#include "common/core/md5.h"
#include "common/core/obj_io.h"
#include "common/core/sequence.h"
#include "encoder/sequence_encoder.h"

namespace tdvo {
namespace {

std::string dataPath(const std::string& relative) {
  return std::string(TDVO_SHARED_DATA_DIR) + "/meshseq/" + relative;
}

// Reads a sequence, or returns empty when the data set is not there.
std::vector<Mesh> readSequence(const std::string& pattern, int first, int count) {
  std::vector<Mesh> frames;
  if (!std::filesystem::exists(framePath(pattern, first))) return frames;
  for (int k = 0; k < count; ++k)
    frames.push_back(readObj(framePath(pattern, first + k)));
  return frames;
}

struct Coded {
  EncodedSequence sequence;
  std::vector<std::string> encoderLines, decoderLines;
  std::vector<IntMesh> decoded;
};

Coded encodeAndDecode(const EncoderParams& params, const Grid& grid,
                      const std::vector<Mesh>& frames) {
  Coded c;
  c.sequence = encodeSequence(params, grid, frames, {}, [&](int f, const IntMesh& m) {
    c.encoderLines.push_back(geometryHashLine(f, m));
  });
  StreamDecoder decoder(c.sequence.stream.data(), c.sequence.stream.size(), "test stream");
  decoder.decode([&](int f, const IntMesh& m) {
    c.decoderLines.push_back(geometryHashLine(f, m));
    c.decoded.push_back(m);
  });
  return c;
}

double bitsPerVertexFrame(const Coded& c) {
  return 8.0 * c.sequence.stream.size() / static_cast<double>(c.sequence.vertexFrames);
}

TEST(HorseGallop, LosslessAndAtMostSixTenthsOfIntra) {
  const std::vector<Mesh> frames = readSequence(dataPath("horse-gallop/%04d.obj.gz"), 1, 48);
  if (frames.empty()) GTEST_SKIP() << "../shared/data/meshseq/horse-gallop is absent";
  EncoderParams params;
  params.gridBits = 12;
  params.gomSize = 48;
  params.motionQuantStep = 1;
  const Grid grid = gridForSequence(frames, params.gridBits);

  params.pmeshMode = PMeshMode::kD3dmc;
  const Coded d3dmc = encodeAndDecode(params, grid, frames);
  params.pmeshMode = PMeshMode::kIntra;
  const Coded intra = encodeAndDecode(params, grid, frames);

  ASSERT_EQ(d3dmc.encoderLines.size(), 48u);
  EXPECT_EQ(d3dmc.encoderLines, d3dmc.decoderLines);
  EXPECT_EQ(intra.encoderLines, intra.decoderLines);
  // Lossless: every decoded vertex is exactly the input vertex quantised to the grid.
  for (size_t f = 0; f < frames.size(); ++f) {
    const IntMesh input = grid.quantise(frames[f]);
    const std::vector<uint32_t>& map = d3dmc.sequence.frameInputIndex[f];
    ASSERT_EQ(d3dmc.decoded[f].positions.size(), map.size());
    for (size_t j = 0; j < map.size(); ++j)
      ASSERT_EQ(d3dmc.decoded[f].positions[j], input.positions[map[j]]) << "frame " << f;
  }
  const double ratio =
      static_cast<double>(d3dmc.sequence.stream.size()) / intra.sequence.stream.size();
  std::printf(
      "horse-gallop: d3dmc %zu bytes (%.3f bits/vertex/frame), intra %zu bytes "
      "(%.3f), ratio %.3f\n",
      d3dmc.sequence.stream.size(), bitsPerVertexFrame(d3dmc), intra.sequence.stream.size(),
      bitsPerVertexFrame(intra), ratio);
  EXPECT_LE(ratio, 0.6);
}

void checkStepSweep(const std::string& name, const std::vector<Mesh>& frames) {
  EncoderParams params;
  params.gridBits = 12;
  params.gomSize = 48;
  params.pmeshMode = PMeshMode::kD3dmc;
  const Grid grid = gridForSequence(frames, params.gridBits);
  double previousRate = 1e9;
  for (int step : {1, 4, 16}) {
    params.motionQuantStep = step;
    const Coded c = encodeAndDecode(params, grid, frames);
    ASSERT_EQ(c.encoderLines.size(), frames.size());
    EXPECT_EQ(c.encoderLines, c.decoderLines) << name << " MotionQuantStep " << step;
    const double rate = bitsPerVertexFrame(c);
    std::printf("%s: MotionQuantStep %2d -> %.4f bits/vertex/frame\n", name.c_str(), step, rate);
    EXPECT_LT(rate, previousRate) << name << ": rate must fall as MotionQuantStep grows";
    previousRate = rate;
  }
}

TEST(Samba, ClosedLoopAndRateFallsWithStep) {
  const std::vector<Mesh> frames = readSequence(dataPath("samba/mesh_%04d.obj.gz"), 0, 175);
  if (frames.empty()) GTEST_SKIP() << "../shared/data/meshseq/samba is absent";
  checkStepSweep("samba", frames);
}

TEST(Pcow, ClosedLoopAndRateFallsWithStep) {
  const std::vector<Mesh> frames = readSequence(dataPath("pcow/%d.obj.gz"), 1, 204);
  if (frames.empty()) GTEST_SKIP() << "../shared/data/meshseq/pcow is absent";
  checkStepSweep("pcow", frames);
}

}  // namespace
}  // namespace tdvo
