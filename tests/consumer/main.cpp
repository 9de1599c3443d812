// A consumer of the installed 3DVO library: decodes a stream and prints its per-frame MD5 lines
// (the lines 3dvo-dec prints), so that tests/consumer/run.sh can compare them with the stream's
// expected log. Usage: tdvo_consumer STREAM.3dvo
#include <cstdio>
#include <fstream>
#include <iterator>
#include <vector>

#include "common/core/error.h"
#include "common/core/md5.h"
#include "decoder/stream_decoder.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: tdvo_consumer STREAM.3dvo\n");
    return 2;
  }
  std::ifstream in(argv[1], std::ios::binary);
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
  try {
    tdvo::StreamDecoder decoder(bytes.data(), bytes.size(), argv[1]);
    decoder.decode([&](int frame, const tdvo::IntMesh& mesh) {
      const int number = static_cast<int>(decoder.sequenceHeader().sh_first_frame) + frame;
      std::printf("%s\n", tdvo::geometryHashLine(number, mesh).c_str());
    });
  } catch (const tdvo::Error& e) {
    std::fprintf(stderr, "tdvo_consumer: %s\n", e.what());
    return 1;
  }
  return 0;
}
