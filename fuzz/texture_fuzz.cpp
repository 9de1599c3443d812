// Fuzz target: the texture path of the stream decoder (StreamDecoder with cameras in the
// sequence header): camera parameters and texture boxes, the texture-work limit, the texture
// units' order and syntax, H.264 access units (FFmpeg), the frames made again for the texture
// pass, and the shapes rasterised from them.
//
// The input is a .3dvo stream; unit CRCs are repaired first (fuzz_support.h). Seeds: the
// conformance streams with cameras and fuzz/seeds/texture/ (crafted streams: a long textured
// GOM, a 16384 x 16384 camera). As in the stream target, a stream is stopped, as a rejected
// input, once its decoded output exceeds a budget (vertex-frames, and shape pixels), so that a
// run stays fast; within the budget the decoder does work linear in its output.
#include <cstdint>

#include "common/core/error.h"
#include "common/core/md5.h"
#include "decoder/stream_decoder.h"
#include "decoder/texture/h264_decoder.h"
#include "fuzz/fuzz_support.h"

namespace {
constexpr uint64_t kVertexFrameBudget = uint64_t{1} << 21;
constexpr uint64_t kPixelBudget = uint64_t{1} << 24;
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> stream = tdvo::fuzz::withValidCrcs(data, size);
  uint64_t vertexFrames = 0, pixels = 0;
  try {
    tdvo::StreamDecoder decoder(stream.data(), stream.size(), "fuzz.3dvo");
    decoder.setPictureDecoder(tdvo::makeH264Decoder);
    decoder.decode(
        [&](int frame, const tdvo::IntMesh& mesh) {
          vertexFrames += mesh.positions.size() + 1;
          if (vertexFrames > kVertexFrameBudget) throw tdvo::Error("fuzz: output budget reached");
          tdvo::geometryHashLine(frame, mesh);
        },
        [&](int frame, int camera, const tdvo::YuvPicture& picture, const tdvo::Image& shape) {
          pixels += shape.pixels.size() + picture.y.size() + 1;
          if (pixels > kPixelBudget) throw tdvo::Error("fuzz: texture budget reached");
          tdvo::textureHashLine(frame, camera, picture);
        });
  } catch (const tdvo::Error&) {
  }
  return 0;
}
