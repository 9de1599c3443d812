// UnitFileReader (issue 10: the decoder reads a stream file unit by unit, so its memory does not
// grow with the sequence): it gives the units UnitReader gives for the same bytes in memory,
// fails with the same message on every truncation and on corrupted bytes, and StreamDecoder
// decodes the same frames from it.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "bitstream/units.h"
#include "common/core/error.h"
#include "common/core/md5.h"
#include "decoder/stream_decoder.h"
#include "decoder/texture/h264_decoder.h"
#include "encoder/sequence_encoder.h"
#include "tests/test_support.h"

namespace tdvo {
namespace {

std::vector<uint8_t> smallStream() {
  const std::vector<Mesh> frames = test::wobblingSphere(1, 7);
  EncoderParams params;
  params.gridBits = 10;
  params.gomSize = 3;
  return encodeSequence(params, gridForSequence(frames, 10), frames, {}, [](int, const IntMesh&) {})
      .stream;
}

// Every unit (type, offsets, payload) or the error message that ends the walk.
std::vector<std::string> walk(UnitSource& units) {
  std::vector<std::string> out;
  try {
    UnitView u;
    while (units.next(u))
      out.push_back(u.describe() + " " + std::to_string(u.payloadOffset) + " " +
                    std::string(u.payload, u.payload + u.size));
  } catch (const Error& e) {
    out.push_back(std::string("error: ") + e.what());
  }
  return out;
}

std::vector<std::string> walkFile(const std::string& path, const std::string& name) {
  try {
    UnitFileReader units(path, name);
    return walk(units);
  } catch (const Error& e) {
    return {std::string("error: ") + e.what()};
  }
}

std::vector<std::string> walkMemory(const std::vector<uint8_t>& bytes, const std::string& name) {
  try {
    UnitReader units(bytes.data(), bytes.size(), name);
    return walk(units);
  } catch (const Error& e) {
    return {std::string("error: ") + e.what()};
  }
}

TEST(UnitFileReader, GivesTheUnitsOfUnitReader) {
  test::TempDir dir("unitfile");
  const std::vector<uint8_t> stream = smallStream();
  test::writeBytes(dir.file("s.3dvo"), stream);
  const std::vector<std::string> units = walkMemory(stream, "s.3dvo");
  ASSERT_GT(units.size(), 5u);
  EXPECT_EQ(units.back().rfind("error", 0), std::string::npos);
  EXPECT_EQ(walkFile(dir.file("s.3dvo"), "s.3dvo"), units);
}

TEST(UnitFileReader, FailsLikeUnitReaderOnEveryTruncation) {
  test::TempDir dir("unitfile");
  const std::vector<uint8_t> stream = smallStream();
  size_t errors = 0;
  for (size_t size = 0; size < stream.size(); size += 1 + size / 8) {
    const std::vector<uint8_t> cut(stream.begin(), stream.begin() + size);
    test::writeBytes(dir.file("t.3dvo"), cut);
    // A cut between two units is a shorter sequence of whole units; any other cut is an error.
    const std::vector<std::string> expected = walkMemory(cut, "t.3dvo");
    if (!expected.empty() && expected.back().rfind("error", 0) == 0) ++errors;
    EXPECT_EQ(walkFile(dir.file("t.3dvo"), "t.3dvo"), expected) << size;
  }
  EXPECT_GT(errors, 20u);
}

TEST(UnitFileReader, FailsLikeUnitReaderOnCorruptedBytes) {
  test::TempDir dir("unitfile");
  const std::vector<uint8_t> stream = smallStream();
  for (size_t at : {size_t{0}, size_t{4}, size_t{5}, size_t{8}, size_t{20}, stream.size() / 2,
                    stream.size() - 1}) {
    std::vector<uint8_t> bad = stream;
    bad[at] ^= 0x5A;
    test::writeBytes(dir.file("c.3dvo"), bad);
    const std::vector<std::string> expected = walkMemory(bad, "c.3dvo");
    ASSERT_FALSE(expected.empty());
    ASSERT_EQ(expected.back().rfind("error", 0), 0u) << at;
    EXPECT_EQ(walkFile(dir.file("c.3dvo"), "c.3dvo"), expected) << at;
  }
  EXPECT_EQ(walkFile(dir.file("missing.3dvo"), "missing.3dvo").back(),
            "error: missing.3dvo: cannot open: No such file or directory");
}

TEST(UnitFileReader, StreamDecoderDecodesTheSameFrames) {
  test::TempDir dir("unitfile");
  const std::vector<uint8_t> stream = smallStream();
  test::writeBytes(dir.file("s.3dvo"), stream);
  std::vector<std::string> fromMemory, fromFile;
  StreamDecoder memory(stream.data(), stream.size(), "s.3dvo");
  memory.setPictureDecoder(makeH264Decoder);
  memory.decode([&](int f, const IntMesh& m) { fromMemory.push_back(geometryHashLine(f, m)); });
  UnitFileReader units(dir.file("s.3dvo"), "s.3dvo");
  StreamDecoder file(units, "s.3dvo");
  file.setPictureDecoder(makeH264Decoder);
  file.decode([&](int f, const IntMesh& m) { fromFile.push_back(geometryHashLine(f, m)); });
  ASSERT_EQ(fromMemory.size(), 7u);
  EXPECT_EQ(fromFile, fromMemory);
  EXPECT_EQ(units.fileSize(), stream.size());
}

}  // namespace
}  // namespace tdvo
