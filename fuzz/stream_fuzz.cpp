// Fuzz target: the whole-stream decoder (StreamDecoder), from the sequence header to the last
// frame, through I meshes (Draco), P meshes (both modes) and keyframe interpolation.
//
// The input is a .3dvo stream; unit CRCs are repaired first (fuzz_support.h), so that mutated
// payloads reach the parsers instead of the CRC check. Seeds: the conformance streams.
//
// Decoded output per stream byte is not bounded by the syntax (an interpolated frame costs no
// bytes; docs/robustness.md, "Decoding work"), so the target stops a stream, as a rejected
// input, once it has produced more than kVertexFrameBudget vertices over all its frames: a
// decoder that reaches the budget has done work linear in its output, which is what is tested.
#include <cstdint>

#include "common/core/error.h"
#include "common/core/md5.h"
#include "decoder/stream_decoder.h"
#include "decoder/texture/h264_decoder.h"
#include "fuzz/fuzz_support.h"

namespace {
constexpr uint64_t kVertexFrameBudget = uint64_t{1} << 21;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> stream = tdvo::fuzz::withValidCrcs(data, size);
  uint64_t vertexFrames = 0;
  try {
    tdvo::StreamDecoder decoder(stream.data(), stream.size(), "fuzz.3dvo");
    decoder.setPictureDecoder(tdvo::makeH264Decoder);
    decoder.decode([&](int frame, const tdvo::IntMesh& mesh) {
      vertexFrames += mesh.positions.size() + 1;
      if (vertexFrames > kVertexFrameBudget) throw tdvo::Error("fuzz: output budget reached");
      tdvo::geometryHashLine(frame, mesh);
    });
  } catch (const tdvo::Error&) {
  }
  return 0;
}
