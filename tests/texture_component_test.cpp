// The geometry decoder without the texture component (issue 19 point 1): tdvo_decoder decodes
// a textured stream's geometry without any picture decoder (its texture units are read and
// checked, not decoded), refuses a texture callback it cannot serve, and with the texture
// component's makeH264Decoder decodes the textures bit-exactly.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "common/core/error.h"
#include "common/core/md5.h"
#include "decoder/stream_decoder.h"
#include "decoder/texture/h264_decoder.h"

namespace tdvo {
namespace {

const std::string kStream =
    std::string(TDVO_SOURCE_DIR) + "/conformance/streams/texture_bbox_mb128_g3";

std::vector<uint8_t> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>((std::istreambuf_iterator<char>(in)),
                              std::istreambuf_iterator<char>());
}

// The expected log's lines that contain `kind` (" geometry=" or " texture ").
std::vector<std::string> expectedLines(const std::string& kind) {
  std::ifstream in(kStream + ".md5");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    if (line.find(kind) != std::string::npos) lines.push_back(line);
  return lines;
}

TEST(TextureComponent, GeometryDecodesWithoutAPictureDecoder) {
  const std::vector<uint8_t> stream = readBytes(kStream + ".3dvo");
  ASSERT_FALSE(stream.empty());
  StreamDecoder decoder(stream.data(), stream.size(), "t.3dvo");
  std::vector<std::string> lines;
  decoder.decode([&](int frame, const IntMesh& mesh) {
    lines.push_back(geometryHashLine(decoder.sequenceHeader().sh_first_frame + frame, mesh));
  });
  EXPECT_EQ(lines, expectedLines(" geometry="));
  EXPECT_FALSE(decoder.sequenceHeader().cameras.empty());
  EXPECT_GT(decoder.textureBytes(), 0u);  // the texture units were read
}

TEST(TextureComponent, TextureCallbackWithoutAPictureDecoderIsAnError) {
  const std::vector<uint8_t> stream = readBytes(kStream + ".3dvo");
  StreamDecoder decoder(stream.data(), stream.size(), "t.3dvo");
  try {
    decoder.decode([](int, const IntMesh&) {}, [](int, int, const YuvPicture&, const Image&) {});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no picture decoder"), std::string::npos) << e.what();
  }
}

TEST(TextureComponent, H264DecoderGivesTheExpectedPictures) {
  const std::vector<uint8_t> stream = readBytes(kStream + ".3dvo");
  StreamDecoder decoder(stream.data(), stream.size(), "t.3dvo");
  decoder.setPictureDecoder(makeH264Decoder);
  std::vector<std::string> lines;
  decoder.decode([](int, const IntMesh&) {},
                 [&](int frame, int camera, const YuvPicture& picture, const Image&) {
                   lines.push_back(textureHashLine(decoder.sequenceHeader().sh_first_frame + frame,
                                                   camera, picture));
                 });
  EXPECT_EQ(lines, expectedLines(" texture "));
  EXPECT_FALSE(lines.empty());
}

}  // namespace
}  // namespace tdvo
