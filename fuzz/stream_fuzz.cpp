// Fuzz target: the whole-stream decoder (StreamDecoder), from the sequence header to the last
// frame, through I meshes (Draco), P meshes (both modes) and keyframe interpolation; and,
// differentially, the pull-style public decoder (tdvo::Decoder, decoder/decoder.h) on the same
// stream, geometry only, given whole and arriving in pieces (openArriving): both must give the
// same frames and, where the push-style decoder refuses the stream, the same error message
// (anything else aborts: a finding).
//
// The input is a .3dvo stream; unit CRCs are repaired first (fuzz_support.h), so that mutated
// payloads reach the parsers instead of the CRC check. Seeds: the conformance streams.
//
// Decoded output per stream byte is not bounded by the syntax (an interpolated frame costs no
// bytes; docs/robustness.md, "Decoding work"), so the target stops a stream, as a rejected
// input, once it has produced more than kVertexFrameBudget vertices over all its frames: a
// decoder that reaches the budget has done work linear in its output, which is what is tested.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "common/core/error.h"
#include "common/core/md5.h"
#include "decoder/decoder.h"
#include "decoder/stream_decoder.h"
#include "decoder/texture/h264_decoder.h"
#include "fuzz/fuzz_support.h"

namespace {
constexpr uint64_t kVertexFrameBudget = uint64_t{1} << 21;
const std::string kBudget = "fuzz: output budget reached";

// The frames' MD5 lines, then "error: <message>" when the stream was refused.
struct Outcome {
  std::vector<std::string> lines;
  std::string error;
};

void mismatch(const char* what, const std::string& push, const std::string& pull) {
  std::fprintf(stderr, "push and pull decoders differ (%s):\n  push: %s\n  pull: %s\n", what,
               push.c_str(), pull.c_str());
  std::abort();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> stream = tdvo::fuzz::withValidCrcs(data, size);
  uint64_t vertexFrames = 0;
  try {
    tdvo::StreamDecoder decoder(stream.data(), stream.size(), "fuzz.3dvo");
    decoder.setPictureDecoder(tdvo::makeH264Decoder);
    decoder.decode([&](int frame, const tdvo::IntMesh& mesh) {
      vertexFrames += mesh.positions.size() + 1;
      if (vertexFrames > kVertexFrameBudget) throw tdvo::Error(kBudget);
      tdvo::geometryHashLine(frame, mesh);
    });
  } catch (const tdvo::Error&) {
  }

  // Geometry only, both ways.
  Outcome push, pull;
  vertexFrames = 0;
  try {
    tdvo::StreamDecoder decoder(stream.data(), stream.size(), "fuzz.3dvo");
    decoder.decode([&](int frame, const tdvo::IntMesh& mesh) {
      vertexFrames += mesh.positions.size() + 1;
      if (vertexFrames > kVertexFrameBudget) throw tdvo::Error(kBudget);
      push.lines.push_back(tdvo::geometryHashLine(frame, mesh));
    });
  } catch (const tdvo::Error& e) {
    push.error = e.what();
  }
  // Pull-style: the stream in memory, and arriving in pieces of 1 to 61 bytes (frames decoded
  // as soon as canDecodeNext() allows).
  const auto pullFrames = [&](tdvo::Decoder& decoder, Outcome& out) {
    vertexFrames = 0;
    tdvo::DecodedFrame frame;
    while (decoder.canDecodeNext() && decoder.next(frame)) {
      vertexFrames += frame.mesh.positions.size() + 1;
      if (vertexFrames > kVertexFrameBudget) throw tdvo::Error(kBudget);
      out.lines.push_back(tdvo::geometryHashLine(static_cast<int>(frame.index), frame.mesh));
    }
  };
  try {
    tdvo::Decoder decoder =
        tdvo::Decoder::openMemory(stream.data(), stream.size(), "fuzz.3dvo", false);
    pullFrames(decoder, pull);
  } catch (const tdvo::Error& e) {
    pull.error = e.what();
  }
  Outcome arriving;
  try {
    tdvo::Decoder decoder = tdvo::Decoder::openArriving("fuzz.3dvo");
    for (size_t at = 0, piece = 1 + size % 61; at < stream.size(); at += piece) {
      decoder.append(stream.data() + at, std::min(piece, stream.size() - at));
      pullFrames(decoder, arriving);
    }
    decoder.finish();
    pullFrames(decoder, arriving);
  } catch (const tdvo::Error& e) {
    arriving.error = e.what();
  }
  for (const Outcome* other : {&pull, &arriving}) {
    const size_t common = std::min(push.lines.size(), other->lines.size());
    for (size_t k = 0; k < common; ++k)
      if (push.lines[k] != other->lines[k]) mismatch("a frame", push.lines[k], other->lines[k]);
    if (push.error != kBudget && other->error != kBudget) {
      if (push.lines.size() != other->lines.size())
        mismatch("the frame count", std::to_string(push.lines.size()),
                 std::to_string(other->lines.size()));
      if (push.error != other->error) mismatch("the error", push.error, other->error);
    }
  }
  return 0;
}
