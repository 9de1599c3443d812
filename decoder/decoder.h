// The public decoding API: a .3dvo stream opened from a file or from memory, its header, and
// its frames one at a time, in order, from the start or from a seek (docs/api.md).
//
//   tdvo::Decoder decoder = tdvo::Decoder::openFile("object.3dvo");
//   decoder.setPictureDecoder(tdvo::makeH264Decoder);  // textures too (texture component)
//   tdvo::DecodedFrame frame;
//   while (decoder.next(frame)) use(frame.number, frame.mesh, frame.positions, frame.textures);
//
// Errors: every function throws tdvo::Error (common/core/error.h) with a message naming the
// stream, the unit and its byte offset, exactly the message 3dvo-dec prints; nothing else is
// thrown for a bad stream. After an error of next(), every next() throws that error again until
// seek() (which starts decoding afresh); the decoder may also be destroyed.
//
// Memory: one frame (its mesh, and with textures one picture and one shape per camera) plus
// one unit of the stream (a file is read unit by unit), whatever the GOM's length: frames are
// made one at a time as next() asks for them. The limits of StreamDecoder (decoding work,
// mesh memory, texture work per stream byte; docs/robustness.md) hold here too.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bitstream/camera_parameters.h"
#include "common/core/grid.h"
#include "common/core/mesh.h"
#include "common/views/image.h"
#include "common/views/texture_shape.h"
#include "common/views/yuv_picture.h"
#include "decoder/picture_decoder.h"
#include "decoder/stream_decoder.h"

namespace tdvo {

// What the sequence header says (docs/bitstream.md, section 2).
struct StreamInfo {
  int syntaxVersion = 0;
  int64_t firstFrame = 0;  // the input's frame number of the stream's first frame
  uint32_t frameCount = 0;
  double frameRate = 0;
  Grid grid;                              // grid integers -> positions: grid.dequantise(q)
  std::vector<CameraParameters> cameras;  // empty: geometry only
  std::string description;                // the input dataset's description (with cameras)
  bool upPresent = false;
  std::array<double, 3> up{0, 1, 0};  // the world's up direction, when upPresent

  // The input's frame number of stream frame `index` (0-based).
  int64_t frameNumber(uint32_t index) const { return firstFrame + index; }
};

struct DecodedFrame {
  int64_t number = 0;  // the input's frame number
  uint32_t index = 0;  // the stream frame (0-based)
  // Grid integers, in the input's vertex order and triangle list (docs/bitstream.md 4.1).
  IntMesh mesh;
  // The same positions in the input's units (grid.dequantise: origin + q * step, in double),
  // vertex for vertex: the values 3dvo-dec writes. Double, not float: a float has 24 bits of
  // mantissa, too few for a 20-bit grid away from the origin, and cannot hold coordinates
  // beyond 3.4e38 or below 1.2e-38 (the codec takes up to 1e300).
  std::vector<Vec3d> positions;
  // With a picture decoder and a textured stream: one per camera, in camera order.
  std::vector<DecodedTexture> textures;

  // "MD5 frame=<n> geometry=<hex>" (docs/bitstream.md, section 8), as 3dvo-dec prints it.
  std::string geometryHashLine() const;
};

class Decoder {
 public:
  // Opens a stream file (read unit by unit: the file is never held whole in memory) or a stream
  // in memory (`copy`: the decoder keeps its own copy; otherwise `data` must outlive the
  // decoder). Reads and checks the sequence header. `name` prefixes error messages (default: the
  // path, or "stream"). Throws Error.
  static Decoder openFile(const std::string& path, const std::string& name = "");
  static Decoder openMemory(const uint8_t* data, size_t size, const std::string& name = "stream",
                            bool copy = true);
  // A stream that arrives in pieces (a download; docs/api.md, "Progressive decoding"): give
  // its bytes to append() as they come and call finish() after the last. The decoder keeps the
  // bytes (the stream's size). Before finish(), call next() and seek() only when
  // canDecodeNext() is true, info() only when headerArrived() is.
  static Decoder openArriving(const std::string& name = "stream");
  // Arriving streams only. append() copies the bytes; it throws Error when the stream does not
  // start with "3DVO", and after finish().
  void append(const uint8_t* data, size_t size);
  void finish();
  uint64_t bytesArrived() const;
  // Whether the sequence header has arrived (or the stream is finished); the first true reads
  // it, and throws Error when it is malformed. Always true for files and memory.
  bool headerArrived();
  // Whether next() needs no byte that has not arrived: the whole GOM of the next frame has (the
  // next GOM's header, before which the GOM's units lie, is there), or the stream is finished.
  // Always true for files and memory.
  bool canDecodeNext();

  Decoder(Decoder&&) noexcept;
  Decoder& operator=(Decoder&&) noexcept;
  ~Decoder();

  const StreamInfo& info() const;
  bool hasTextures() const { return !info().cameras.empty(); }

  // Decodes texture pictures with decoders `factory` makes, one per camera (the texture
  // component's tdvo::makeH264Decoder, decoder/texture/h264_decoder.h); an empty factory (the
  // default) reads and checks texture units without decoding them, and frames then have no
  // textures. Takes effect at the next GOM decoded from its start: set it before the first
  // next(), or seek() after it.
  void setPictureDecoder(PictureDecoderFactory factory);
  // Decoder limits (StreamDecoder's; 0 lifts one). Set before the first next().
  void setMaxVertexFramesPerByte(uint64_t limit);
  void setMaxMeshMemoryPerByte(uint64_t limit);
  void setMaxTexturePixelsPerByte(uint64_t limit);
  // Hands each frame's texture access units out (DecodedTexture::accessUnits: H.264, Annex B),
  // for a program that decodes the pictures itself, e.g. the browser player with WebCodecs;
  // without a picture decoder, the frames' pictures and shapes are then empty. Set it before
  // the first next(), or seek() after it.
  void setTextureAccessUnits(bool keep);

  // The next frame into `frame` (its buffers are reused); false after the last frame (the
  // stream has then been read to its end and checked for units after the last frame).
  bool next(DecodedFrame& frame);

  // The random access points (GOM starts where decoding can begin), as the input's frame
  // numbers, in order. The first call reads every unit's header and CRC once (no decoding);
  // it does not move the decoding position.
  // For an arriving stream, before finish(): the random access points among the GOMs whose
  // headers have arrived so far.
  const std::vector<int64_t>& gomStarts();
  // "MD5 header=<hex>" (docs/bitstream.md, section 8), as 3dvo-dec prints it after the frames.
  std::string headerHashLine() const;

  // Makes next() return frame `frameNumber` (an input frame number) next: decoding restarts at
  // the random access point at or before it (decoding, without output, what lies between).
  // Throws Error when the frame is not in the stream.
  void seek(int64_t frameNumber);

 private:
  struct State;
  explicit Decoder(std::unique_ptr<State> state);
  std::unique_ptr<State> s_;
};

}  // namespace tdvo
