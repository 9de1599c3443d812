// Decoding of a whole 3DVO stream: units in order, GOM by GOM, frame by frame.
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>

#include "bitstream/syntax.h"
#include "common/grid.h"
#include "common/mesh.h"

namespace tdvo {

// Called once per decoded frame, in frame order; `frame` counts from 0.
using FrameCallback = std::function<void(int frame, const IntMesh& mesh)>;

class StreamDecoder {
 public:
  // `name` (the file name) prefixes error messages; `trace`, when given, receives every syntax
  // element read.
  StreamDecoder(const uint8_t* data, size_t size, std::string name, std::FILE* trace = nullptr);

  // Decodes everything, calling `onFrame` as each frame is finished. Throws Error, naming the
  // unit and byte offset, on any malformed, truncated or inconsistent stream.
  void decode(const FrameCallback& onFrame);

  // Valid once decode() has read the sequence header.
  const SequenceHeader& sequenceHeader() const { return sh_; }
  Grid grid() const;

 private:
  const uint8_t* data_;
  size_t size_;
  std::string name_;
  std::FILE* trace_;
  SequenceHeader sh_;
};

// Grid defined by a sequence header.
Grid gridFromHeader(const SequenceHeader& sh);

}  // namespace tdvo
