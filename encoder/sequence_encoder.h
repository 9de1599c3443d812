// Encoding of a whole mesh sequence into a 3DVO stream.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "common/grid.h"
#include "common/mesh.h"
#include "decoder/stream_decoder.h"
#include "encoder/encoder_params.h"

namespace tdvo {

struct EncodedSequence {
  std::vector<uint8_t> stream;
  // Per frame: decoded vertex index -> input vertex index (the GOM's vertex order, see
  // imesh_encoder.h). Lets tests and metrics compare decoded frames with the input.
  std::vector<std::vector<uint32_t>> frameInputIndex;
  uint64_t headerBytes = 0, iMeshBytes = 0, pMeshBytes = 0;
  uint64_t vertexFrames = 0;  // sum over frames of the decoded vertex count
  // Reconstruction error against the input quantised to the grid, in grid units, over all
  // vertex coordinates of all frames (0 and 0 when coding is lossless on the grid).
  double sumSquaredError = 0;
  int64_t maxAbsError = 0;
};

// The grid for a sequence: its bounding box over all frames at `bits`.
Grid gridForSequence(const std::vector<Mesh>& frames, int bits);

// Encodes `frames` on `grid` (normally gridForSequence(frames, params.gridBits); already read;
// frame k of the stream is frames[k]; `frameNames`, if not empty, names each frame's source in
// error messages). Calls `onFrame` with the encoder's reconstruction of each frame, which equals
// the decoder's output. Throws Error on input the codec cannot represent (e.g. connectivity
// changing inside a GOM of P meshes).
EncodedSequence encodeSequence(const EncoderParams& params, const Grid& grid,
                               const std::vector<Mesh>& frames,
                               const std::vector<std::string>& frameNames,
                               const FrameCallback& onFrame);

}  // namespace tdvo
