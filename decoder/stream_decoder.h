// Decoding of a whole 3DVO stream: units in order, GOM by GOM, frame by frame.
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bitstream/syntax.h"
#include "bitstream/units.h"
#include "common/core/grid.h"
#include "common/core/mesh.h"
#include "common/views/image.h"
#include "common/views/texture_shape.h"
#include "common/views/yuv_picture.h"
#include "decoder/draco_limits.h"
#include "decoder/picture_decoder.h"

namespace tdvo {

// Decoding-work limit (docs/robustness.md, "Limits and decoding work"): the decoded output
// declared so far, summed over the GOMs (a GOM's frames times its I mesh's vertices; in intra
// GOMs each I mesh's vertices), may be at most this many vertex-frames per byte of the stream
// read so far, through the I mesh that declares it. Checked before any frame of the GOM is
// decoded from that I mesh, so decoding time is linear in the stream size. 2^16 passes any GOM
// length whose I mesh costs at least one byte per vertex.
constexpr uint64_t kDefaultMaxVertexFramesPerByte = uint64_t{1} << 16;

// Texture-work limit (docs/robustness.md, "Limits and decoding work"): every TEXTURE unit
// costs work and memory in proportion to its camera's pixels (the shape is a mask of the whole
// camera frame; the picture is the texture box), not to its bytes. Checked for each texture
// unit as it is read, before its picture is decoded, with B the stream bytes read through it:
// - the camera pixels of the texture units so far (a camera's pixels: the larger of its frame
//   and its texture box) may be at most this many per byte: B x 2^16;
// - one camera's pixels at most kTexturePixelsFree + kTexturePixelsPerByte x B, so that a
//   picture's memory is bounded by the stream read so far (a 1920 x 1080 camera always passes).
// setMaxTexturePixelsPerByte(0) lifts both.
constexpr uint64_t kDefaultMaxTexturePixelsPerByte = uint64_t{1} << 16;
constexpr uint64_t kTexturePixelsFree = uint64_t{1} << 21;
constexpr uint64_t kTexturePixelsPerByte = 2;

// Called once per decoded frame, in frame order; `frame` counts from 0.
using FrameCallback = std::function<void(int frame, const IntMesh& mesh)>;

// Called once per camera and frame with a decoded texture picture (the camera's texture box)
// and the object's shape in that camera (a mask of the full camera frame, from the decoded
// mesh). Texture calls of a GOM follow the frame calls of that GOM, frames in order, cameras in
// order within a frame. The texture pass makes the GOM's frames again from the GOM's geometry
// payloads (kept as read), a few at a time, so a GOM's frames are never all in memory at once
// (docs/robustness.md, "Memory").
using TextureCallback =
    std::function<void(int frame, int camera, const YuvPicture& picture, const Image& shape)>;

// One camera's decoded texture picture of a frame (pull-style decoding, decoder/decoder.h).
struct DecodedTexture {
  int camera = 0;
  TextureBox box;      // where the picture lies in the camera frame (pixels, top-left)
  YuvPicture picture;  // 4:2:0, box.width x box.height (with a picture decoder)
  Image shape;         // the object's mask in the whole camera frame (255 inside), from the mesh
  // With setKeepAccessUnits: the H.264 access units (tx_access_unit, Annex B) to give the
  // camera's picture decoder before this frame is shown: the frame's own, last, after those of
  // the frames of its GOM that were decoded without output (after a seek into a GOM, the GOM's
  // earlier pictures, from its IDR on, which this one is predicted from).
  std::vector<std::vector<uint8_t>> accessUnits;
};

class StreamDecoder {
 public:
  // `name` (the file name) prefixes error messages; `trace`, when given, receives every syntax
  // element read.
  StreamDecoder(const uint8_t* data, size_t size, std::string name, std::FILE* trace = nullptr);
  // Decodes the units `units` gives (e.g. a UnitFileReader: the stream is then never held in
  // memory as a whole, and memory does not grow with the sequence's length).
  StreamDecoder(UnitSource& units, std::string name, std::FILE* trace = nullptr);
  ~StreamDecoder();
  StreamDecoder(const StreamDecoder&) = delete;  // a run refers to its decoder
  StreamDecoder& operator=(const StreamDecoder&) = delete;

  // Decodes everything, calling `onFrame` as each frame is finished. Throws Error, naming the
  // unit and byte offset, on any malformed, truncated or inconsistent stream.
  // `prepareTexture`, when given, is called for every texture picture before its onTexture
  // call, on the thread that decoded it: with setThreads(n > 1) on worker threads, several at
  // once and in no particular order, so it must be safe to call concurrently. It is for work on
  // a picture that may run in parallel (e.g. compressing it for output); what it leaves for
  // onTexture is visible there. An exception it throws comes out in picture order.
  void decode(const FrameCallback& onFrame, const TextureCallback& onTexture = {},
              const TextureCallback& prepareTexture = {});

  // Decodes only what frames `first` .. `first + count - 1` need (count 0: to the end), in the
  // input's frame numbers (sh_first_frame + stream frame): GOMs before the GOM holding `first`
  // are skipped (their units are read and checked for type, not decoded), decoding starts at
  // that GOM's I mesh and IDR pictures, and stops after the GOM holding the last frame (later
  // units are not read). onFrame, onTexture and prepareTexture are called for the range's
  // frames only (`frame` still counts from the stream's frame 0). decode() throws an Error
  // naming the stream when the range is not within its frames.
  void setFrameRange(int64_t first, int64_t count) {
    rangeFirst_ = first;
    rangeCount_ = count;
  }

  // Pull-style decoding, what tdvo::Decoder (decoder/decoder.h) is built on: makes the next
  // frame of the range (setFrameRange) and returns its stream frame in `frame` and its mesh, in
  // the output order, in `mesh` (valid until the next call); false after the last frame (the
  // stream has then been checked for units after it). The first call reads the sequence
  // header. Frames are made one at a time as they are asked for (memory: one frame, whatever
  // the GOM's length). With `textureUnits` (a second source over the same stream: a
  // UnitReader or UnitFileReader of the same bytes, moved with UnitSource::seek) and a picture
  // decoder (or setKeepAccessUnits), `textures` receives each frame's pictures (or access
  // units), one per camera: the second source reads
  // a GOM's texture units while the first reads its geometry. Without them a stream's texture
  // units are read and checked, not decoded. Not to be mixed with decode() on one object.
  bool pullFrame(uint32_t& frame, const IntMesh*& mesh, UnitSource* textureUnits = nullptr,
                 std::vector<DecodedTexture>* textures = nullptr);
  // Pull-style: reads and checks the sequence header (sequenceHeader()) without decoding a
  // frame; pullFrame() goes on from there. Throws Error.
  void readHeader();

  // Sets how texture pictures are decoded: one decoder per camera, made by `factory` at the
  // camera's first texture unit (the texture component's makeH264Decoder,
  // decoder/texture/h264_decoder.h). Without one (a geometry-only program), a stream's texture
  // units are read and not decoded, and decode() throws an Error if it was given a texture
  // callback for a stream with textures.
  void setPictureDecoder(PictureDecoderFactory factory) { pictureDecoders_ = std::move(factory); }
  // Pull-style: hands each frame's texture access units out (DecodedTexture::accessUnits), for
  // a caller that decodes the pictures itself (the browser's H.264 decoder); with no picture
  // decoder set, pictures and shapes are then left empty.
  void setKeepAccessUnits(bool keep) { keepAccessUnits_ = keep; }
  // Sets the decoding-work limit (kDefaultMaxVertexFramesPerByte above); 0 lifts it.
  void setMaxVertexFramesPerByte(uint64_t limit) { maxVertexFramesPerByte_ = limit; }
  // Sets the texture-work limit (kDefaultMaxTexturePixelsPerByte above); 0 lifts it.
  void setMaxTexturePixelsPerByte(uint64_t limit) { maxTexturePixelsPerByte_ = limit; }
  // Sets the mesh-memory limit (kDefaultMaxMeshMemoryPerByte, decoder/draco_limits.h); 0 lifts
  // it.
  void setMaxMeshMemoryPerByte(uint64_t limit) { maxMeshMemoryPerByte_ = limit; }
  // Decodes the cameras' textures on this many threads (default 1: on the calling thread).
  // Each camera's pictures are decoded in order; onFrame and onTexture, their order and thread
  // (the calling one), the output and any error are the same for every thread count.
  void setThreads(int threads) { threads_ = threads; }

  // Valid once decode() has read the sequence header.
  const SequenceHeader& sequenceHeader() const { return sh_; }
  Grid grid() const;
  // Bytes of the TEXTURE units decoded so far (unit headers and CRCs included).
  uint64_t textureBytes() const { return textureBytes_; }
  // The first frame of every random access point read so far (intra GOMs and GOMs with
  // gh_random_access 1), in order: where decoding can start.
  const std::vector<uint32_t>& gomStarts() const { return gomStarts_; }

 private:
  class Decoding;                   // one run of decode() (stream_decoder.cpp)
  std::unique_ptr<Decoding> pull_;  // the run of pullFrame()
  Decoding& pullRun();

  const uint8_t* data_ = nullptr;
  size_t size_ = 0;
  UnitSource* source_ = nullptr;  // when not decoding from data_
  std::string name_;
  std::FILE* trace_;
  SequenceHeader sh_;
  uint64_t textureBytes_ = 0;
  std::vector<uint32_t> gomStarts_;
  uint64_t maxVertexFramesPerByte_ = kDefaultMaxVertexFramesPerByte;
  uint64_t maxTexturePixelsPerByte_ = kDefaultMaxTexturePixelsPerByte;
  uint64_t maxMeshMemoryPerByte_ = kDefaultMaxMeshMemoryPerByte;
  int64_t rangeFirst_ = -1, rangeCount_ = 0;  // setFrameRange; -1: from the stream's first
  int threads_ = 1;
  PictureDecoderFactory pictureDecoders_;
  bool keepAccessUnits_ = false;
};

// Grid defined by a sequence header.
Grid gridFromHeader(const SequenceHeader& sh);

}  // namespace tdvo
