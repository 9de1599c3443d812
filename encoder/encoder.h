// The public encoding API: mesh frames from memory (or read on demand) into a .3dvo stream,
// configured with the cfg keys of 3dvo-enc (docs/options.md), so that a program encodes without
// writing OBJ files and gets the stream 3dvo-enc would write for the same frames and keys.
//
//   tdvo::Encoder encoder;
//   encoder.readConfig("cfg/d3dmc-lossy.cfg");
//   encoder.set("GOMSize", "12");
//   tdvo::EncodedSequence coded = encoder.encode(frames);  // std::vector<tdvo::Mesh>
//   // coded.stream: the .3dvo bytes; coded.md5Lines: what 3dvo-dec prints for it
//
// Errors: every function throws tdvo::Error (common/core/error.h) with the message 3dvo-enc
// prints (naming the key, the cfg file and line, or the frame).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/core/grid.h"
#include "common/core/mesh.h"
#include "encoder/encoder_params.h"
#include "encoder/sequence_encoder.h"

namespace tdvo {

class OptionTable;
struct Dataset;

class Encoder {
 public:
  Encoder();
  Encoder(Encoder&&) noexcept;
  Encoder& operator=(Encoder&&) noexcept;
  ~Encoder();

  // Sets one cfg key, like 3dvo-enc's --Key=value (later settings win). Keys that name input
  // or output files (InputMeshPattern, BitstreamFile, ReconMeshPattern) are the app's business
  // and are accepted but not used by encode(); Dataset is used (textures).
  void set(const std::string& key, const std::string& value);
  // Reads a cfg file, like 3dvo-enc -c FILE.
  void readConfig(const std::string& path);
  // Every key with its effective value (a valid cfg file), as 3dvo-enc prints it.
  std::string effectiveConfig() const;
  // The parameters the keys set, checked (Error when they are inconsistent), with a Dataset's
  // first frame number and frame rate where FirstFrame and FrameRate are not set: what
  // encode() uses.
  const EncoderParams& params();
  // The dataset Dataset names (read by params()), or null.
  const Dataset* dataset();
  // True when `key` was set by set() or readConfig() (not left at its default).
  bool wasSet(const std::string& key) const;
  // The grid of the last encode() (normally its frames' bounding box at GridBits), valid from
  // that encode()'s first onFrame call on: grid().dequantise(recon) gives float positions.
  const Grid& grid() const;
  // What Quality chose in the last encode() (one line; empty when Quality is off).
  const std::string& qualityReport() const;
  // The parameters the last encode() coded with: params() with Quality's choices (GridFit,
  // GridBits, MotionQuantStep, BMeshGap or KeyframeLambda).
  const EncoderParams& codedParams() const;
  // The option table (3dvo-enc parses its command line with it; --help lists it).
  OptionTable& options();

  // Encodes `frames` (frame k of the stream is frames[k]: the input's frame number FirstFrame
  // + k; FrameCount, when set, must equal frames.size(); each frame is checked like a mesh
  // file: finite positions, triangle indices within its vertices). `onFrame` receives the encoder's
  // reconstruction of each frame (the decoder's output), `onTexture` each coded camera
  // picture when Dataset is set. The result's md5Lines are the lines 3dvo-enc prints (and
  // 3dvo-dec --verify checks). Throws Error on input the codec cannot represent.
  EncodedSequence encode(const std::vector<Mesh>& frames, const FrameCallback& onFrame = {},
                         const TextureCallback& onTexture = {});
  // The same for frames read on demand (FrameSource, encoder/sequence_encoder.h): never more
  // than a few GOMs of them in memory. `onFramesRead(k)`, when given, is called as the first
  // pass (bounding box, texture boxes) has read frame k (progress).
  EncodedSequence encode(const FrameSource& frames, const FrameCallback& onFrame = {},
                         const TextureCallback& onTexture = {},
                         const std::function<void(size_t frame)>& onFramesRead = {});

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace tdvo
