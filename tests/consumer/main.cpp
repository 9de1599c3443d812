// A consumer of the installed 3DVO library: decodes a stream's geometry with the public
// pull-style API (decoder/decoder.h) and prints its per-frame MD5 lines (the lines 3dvo-dec
// prints), so that tests/consumer/run.sh can compare them with the stream's expected log. It
// also seeks to every random access point and checks that the frames from there are the same.
// Usage: tdvo_consumer STREAM.3dvo
#include <cstdio>
#include <string>
#include <vector>

#include "common/core/error.h"
#include "decoder/decoder.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: tdvo_consumer STREAM.3dvo\n");
    return 2;
  }
  try {
    tdvo::Decoder decoder = tdvo::Decoder::openFile(argv[1]);
    std::vector<std::string> lines;
    tdvo::DecodedFrame frame;
    while (decoder.next(frame))
      lines.push_back(frame.geometryHashLine());
    for (const std::string& line : lines)
      std::printf("%s\n", line.c_str());
    const int64_t first = decoder.info().firstFrame;
    for (int64_t start : decoder.gomStarts()) {
      decoder.seek(start);
      for (size_t k = static_cast<size_t>(start - first); decoder.next(frame); ++k)
        if (k >= lines.size() || frame.geometryHashLine() != lines[k]) {
          std::fprintf(stderr, "tdvo_consumer: frame %lld differs after a seek to %lld\n",
                       static_cast<long long>(frame.number), static_cast<long long>(start));
          return 1;
        }
    }
  } catch (const tdvo::Error& e) {
    std::fprintf(stderr, "tdvo_consumer: %s\n", e.what());
    return 1;
  }
  return 0;
}
