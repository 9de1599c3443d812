// Encoding of a whole mesh sequence into a 3DVO stream.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "common/core/grid.h"
#include "common/core/mesh.h"
#include "decoder/stream_decoder.h"
#include "encoder/encoder_params.h"
#include "encoder/texture_encoder.h"

namespace tdvo {

struct EncodedSequence {
  std::vector<uint8_t> stream;
  // Per frame: output vertex index -> input vertex index (the identity unless Draco dropped
  // unused vertices or split non-manifold ones). Lets tests and metrics compare decoded frames
  // with the input.
  std::vector<std::vector<uint32_t>> frameInputIndex;
  uint64_t headerBytes = 0, iMeshBytes = 0, pMeshBytes = 0, textureBytes = 0;
  uint64_t orderBytes = 0;           // VERTEX_ORDER units
  uint64_t attributeBytes = 0;       // ATTRIBUTES units
  uint64_t vertexFrames = 0;         // sum over frames of the decoded vertex count
  std::vector<size_t> gomKeyframes;  // per GOM: its frames coded as I or P meshes
  // Reconstruction error against the input quantised to the grid, in grid units, over all
  // vertex coordinates of all frames (0 and 0 when coding is lossless on the grid).
  double sumSquaredError = 0;
  int64_t maxAbsError = 0;
  // The MD5 lines of the stream (docs/bitstream.md, section 8), as 3dvo-enc prints them and
  // 3dvo-dec --verify checks them; filled by Encoder::encode (encoder/encoder.h).
  std::vector<std::string> md5Lines;
};

// The input frames of a sequence, read on demand, so that the encoder never holds more than a
// few GOMs of them. read(k) returns frame k (0-based); with Threads > 1 it is called from
// several threads at once (for different frames), so it must be thread-safe, and it must
// return the same frame each time (the encoder reads each frame twice: a first pass for the
// grid, then the coding; what read(k) warns the second time is not said). name(k) names
// frame k's source in error messages (may be empty: "frame k").
struct FrameSource {
  size_t count = 0;
  std::function<Mesh(size_t frame)> read;
  std::function<std::string(size_t frame)> name;
};

// The grid for a sequence at `bits` (GridBits): its bounding box over all frames spans the grid
// (GridFit sequence), or the object's size, the largest extent of any one frame, spans
// 2^bits - 1 steps and the grid has the further bits the sequence's box needs (GridFit object;
// Grid::fitObject).
Grid gridForSequence(const std::vector<Mesh>& frames, int bits, GridFit fit = GridFit::kSequence);
// The same grid from frames read one by one (`threads` at a time) and released as soon as
// their bounds are taken; `onFrameRead(k)` (optional) is called in frame order on the calling
// thread. `inspect(k, mesh)` (optional) sees every frame on the thread that read it, several
// at once and in no particular order, before it is released (e.g. TextureBoxFinder::add, so
// that one pass over the input serves both). Errors of read() and inspect() come out in
// frame order, as if run sequentially.
Grid gridForSequence(const FrameSource& source, int bits, GridFit fit, int threads = 1,
                     const std::function<void(size_t frame)>& onFrameRead = {},
                     const std::function<void(size_t frame, const Mesh& mesh)>& inspect = {});

// What the grid is made from: the bounding box of all frames, the object's size (the largest
// extent of any one frame), and the names of the first and last frame for messages.
struct SequenceBounds {
  Vec3d lo{0, 0, 0}, hi{0, 0, 0};
  double objectExtent = 0;
  size_t frames = 0;
  std::string firstName, lastName;
  // What 2^bits - 1 steps of gridFor(*this, bits, fit) span (Grid::spannedSize).
  double spannedSize(GridFit fit) const { return Grid::spannedSize(lo, hi, objectExtent, fit); }
};
// The bounds of frames already read (named "frame k" in messages), each folded where it is.
SequenceBounds boundsOfSequence(const std::vector<Mesh>& frames);
// The bounds of frames read as gridForSequence() above reads them.
SequenceBounds boundsOfSequence(
    const FrameSource& source, int threads = 1,
    const std::function<void(size_t frame)>& onFrameRead = {},
    const std::function<void(size_t frame, const Mesh& mesh)>& inspect = {});
// The grid of `bits` and `fit` for those bounds (an Error names the frames).
Grid gridFor(const SequenceBounds& bounds, int bits, GridFit fit);

// Encodes `frames` on `grid` (normally gridForSequence(frames, params.gridBits); already read;
// frame k of the stream is frames[k]; `frameNames`, if not empty, names each frame's source in
// error messages). Calls `onFrame` with the encoder's reconstruction of each frame, which equals
// the decoder's output. Throws Error on input the codec cannot represent (e.g. connectivity
// changing inside a GOM of P meshes).
EncodedSequence encodeSequence(const EncoderParams& params, const Grid& grid,
                               const std::vector<Mesh>& frames,
                               const std::vector<std::string>& frameNames,
                               const FrameCallback& onFrame, TextureEncoder* textures = nullptr,
                               const TextureCallback& onTexture = {});

// The same for frames read on demand: GOM by GOM (params.goms(source.count): GOMSize frames
// each, or the GOMs of GOMListFile), params.threadCount() GOMs coded in parallel,
// the stream and every callback in the order of a sequential run (byte-identical for any
// thread count). At most 2 * threads GOMs of frames and results are held at once. The frames'
// vertex order is kept in frameInputIndex only when `keepInputIndex` (it grows with the
// sequence; the overload above keeps it). What the frames' readers warn here is not said: the
// frames were read, and their warnings said in frame order, by boundsOfSequence before.
EncodedSequence encodeSequence(const EncoderParams& params, const Grid& grid,
                               const FrameSource& source, const FrameCallback& onFrame,
                               TextureEncoder* textures = nullptr,
                               const TextureCallback& onTexture = {}, bool keepInputIndex = false);

// Says (warn(), common/core/warnings.h) when decoders with their default limits
// (MaxMeshMemoryPerByte, MaxVertexFramesPerByte, MaxTexturePixelsPerByte; docs/robustness.md)
// refuse `stream`, as for a fan of 160,000 triangles whose Draco vertices need more decoding
// memory than the stream's bytes allow. tdvo::Encoder::encode calls it on the stream it returns
// (not encodeSequence: the Quality search's trial codings are not checked).
void warnIfDecodersRefuse(const std::vector<uint8_t>& stream);

}  // namespace tdvo
