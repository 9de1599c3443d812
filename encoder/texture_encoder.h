// Texture coding: each camera's video, cut to its texture box, padded outside the object's
// shape and coded as H.264 (docs/textures.md).
//
// The box of each camera is fixed for the sequence (so each camera is one H.264 stream of one
// size): in bbox mode the macroblock-aligned bounding box of the input geometry's shape over
// all frames, grown by TextureBoxMargin; in full mode the whole frame. The shape used for
// padding is the *decoded* geometry's, as the decoder will see it. Each GOM starts with an IDR
// picture. The encoder decodes its own access units (the decoder's H.264 path) so that what
// it reports is exactly what a decoder outputs.
#pragma once

#include <memory>
#include <mutex>
#include <vector>

#include "bitstream/syntax.h"
#include "bitstream/units.h"
#include "common/core/grid.h"
#include "common/media/dataset.h"
#include "common/media/yuv.h"
#include "common/views/rasteriser.h"
#include "decoder/stream_decoder.h"
#include "encoder/encoder_params.h"

namespace tdvo {

class H264Encoder;
class H264Decoder;

// The cameras' texture boxes for a sequence. Made for a dataset and a frame count (it checks
// that the dataset can be coded: cameras, their number and sizes, enough frames; an Error
// names the dataset otherwise; every coded frame number must be a dataset frame,
// checkTextureFrames), it is shown every input mesh (frame k = frame number
// params.firstFrame + k) with add(), from any thread and in any order, e.g. during the pass
// that takes the bounding box (gridForSequence's `inspect`); boxes() is then each camera's box:
// in bbox mode the union of the meshes' macroblock boxes, in full mode the whole frame (add()
// does nothing). The boxes do not depend on the order of the add() calls.
class TextureBoxFinder {
 public:
  TextureBoxFinder(const EncoderParams& params, const Dataset& dataset, size_t frameCount);
  ~TextureBoxFinder();
  void add(const Mesh& mesh);
  std::vector<TextureBox> boxes() const;

 private:
  const EncoderParams& params_;
  const Dataset& dataset_;
  std::vector<MaskRenderer> renderers_;
  mutable std::mutex mutex_;
  std::vector<TextureBox> boxes_;  // the union so far (bbox mode)
};

class TextureEncoder {
 public:
  // `boxes` (TextureBoxFinder::boxes()) are the cameras' texture boxes, one per camera of
  // `dataset`.
  TextureEncoder(const EncoderParams& params, const Dataset& dataset,
                 const std::vector<TextureBox>& boxes);
  // With the boxes found from the input meshes in memory (frame k = frame number
  // params.firstFrame + k, i.e. dataset frame index params.firstFrame + k - frames.first),
  // params.threadCount() frames at a time; the boxes do not depend on the thread count.
  TextureEncoder(const EncoderParams& params, const Dataset& dataset,
                 const std::vector<Mesh>& frames);
  ~TextureEncoder();

  // The cameras and boxes, for the sequence header.
  const std::vector<CameraParameters>& cameras() const { return cameras_; }
  // The input dataset (its description and up direction go into the sequence header).
  const Dataset& dataset() const { return dataset_; }

  // Codes the textures of frames first .. first + decoded.size() - 1 (one GOM) from their
  // decoded meshes; writes one TEXTURE unit per frame and camera (frame-major). The cameras
  // are coded in parallel on params.threadCount() threads (each camera's pictures in order,
  // x264 single-threaded), and units and onTexture calls come in frame-major order on the
  // calling thread, so the stream and the callbacks do not depend on the thread count.
  void encodeGom(size_t first, const std::vector<IntMesh>& decoded, const Grid& grid,
                 UnitWriter& units, const TextureCallback& onTexture);

 private:
  const EncoderParams& params_;
  const Dataset& dataset_;
  std::vector<CameraParameters> cameras_;
  std::vector<MaskRenderer> shapes_;  // per camera, as the decoder sees it
  std::vector<CameraFrames> frames_;
  std::vector<std::unique_ptr<H264Encoder>> encoders_;
  std::vector<std::unique_ptr<H264Decoder>> decoders_;
};

// Checks that a dataset has meshes for frames firstFrame .. firstFrame + frameCount - 1
// (an Error names its dataset.json otherwise).
void checkDatasetMeshes(const Dataset& dataset, int firstFrame, int frameCount);
// Reads the geometry from a dataset's meshes: frames firstFrame .. + frameCount - 1, checked
// as above.
std::vector<Mesh> readDatasetFrames(const Dataset& dataset, int firstFrame, int frameCount);

}  // namespace tdvo
