// Decoding of a whole 3DVO stream: units in order, GOM by GOM, frame by frame.
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>

#include "bitstream/syntax.h"
#include "bitstream/units.h"
#include "common/grid.h"
#include "common/image.h"
#include "common/mesh.h"
#include "common/yuv.h"

namespace tdvo {

// Called once per decoded frame, in frame order; `frame` counts from 0.
using FrameCallback = std::function<void(int frame, const IntMesh& mesh)>;

// Called once per camera and frame with a decoded texture picture (the camera's texture box)
// and the object's shape in that camera (a mask of the full camera frame, from the decoded
// mesh). Texture calls of a GOM follow the frame calls of that GOM, frames in order, cameras in
// order within a frame.
using TextureCallback =
    std::function<void(int frame, int camera, const YuvPicture& picture, const Image& shape)>;

class StreamDecoder {
 public:
  // `name` (the file name) prefixes error messages; `trace`, when given, receives every syntax
  // element read.
  StreamDecoder(const uint8_t* data, size_t size, std::string name, std::FILE* trace = nullptr);
  // Decodes the units `units` gives (e.g. a UnitFileReader: the stream is then never held in
  // memory as a whole, and memory does not grow with the sequence's length).
  StreamDecoder(UnitSource& units, std::string name, std::FILE* trace = nullptr);

  // Decodes everything, calling `onFrame` as each frame is finished. Throws Error, naming the
  // unit and byte offset, on any malformed, truncated or inconsistent stream.
  void decode(const FrameCallback& onFrame, const TextureCallback& onTexture = {});

  // Valid once decode() has read the sequence header.
  const SequenceHeader& sequenceHeader() const { return sh_; }
  Grid grid() const;
  // Bytes of the TEXTURE units decoded so far (unit headers and CRCs included).
  uint64_t textureBytes() const { return textureBytes_; }

 private:
  const uint8_t* data_ = nullptr;
  size_t size_ = 0;
  UnitSource* source_ = nullptr;  // when not decoding from data_
  std::string name_;
  std::FILE* trace_;
  SequenceHeader sh_;
  uint64_t textureBytes_ = 0;
};

// Grid defined by a sequence header.
Grid gridFromHeader(const SequenceHeader& sh);

}  // namespace tdvo
