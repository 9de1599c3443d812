#include "encoder/texture_encoder.h"

#include "bitstream/camera_parameters.h"
#include "common/error.h"
#include "common/rasteriser.h"
#include "common/texture_shape.h"
#include "decoder/h264_decoder.h"
#include "encoder/h264_encoder.h"
#include "encoder/texture_padding.h"

namespace tdvo {

std::vector<Mesh> readDatasetFrames(const Dataset& dataset, int firstFrame, int frameCount) {
  check(!dataset.meshes.empty(),
        dataset.resolve(kDatasetFileName) + ": the dataset has no meshes; set InputMeshPattern");
  check(firstFrame + frameCount <= dataset.frameCount,
        dataset.resolve(kDatasetFileName) +
            ": FirstFrame + FrameCount = " + std::to_string(firstFrame + frameCount) +
            " but the dataset has " + std::to_string(dataset.frameCount) + " frames");
  std::vector<Mesh> frames;
  for (int k = 0; k < frameCount; ++k)
    frames.push_back(readDatasetMesh(dataset, firstFrame + k));
  return frames;
}

TextureEncoder::TextureEncoder(const EncoderParams& params, const Dataset& dataset,
                               const std::vector<Mesh>& frames)
    : params_(params), dataset_(dataset) {
  const std::string name = dataset.resolve(kDatasetFileName);
  check(!dataset.cameras.empty(), name + ": no cameras");
  check(dataset.cameras.size() <= kMaxCameras,
        name + ": more than " + std::to_string(kMaxCameras) + " cameras");
  check(params.firstFrame + static_cast<int>(frames.size()) <= dataset.frameCount,
        name + ": FirstFrame + FrameCount = " + std::to_string(params.firstFrame + frames.size()) +
            " but the dataset has " + std::to_string(dataset.frameCount) + " frames");
  for (size_t c = 0; c < dataset.cameras.size(); ++c) {
    const Camera& camera = dataset.cameras[c].camera;
    check(camera.width <= kMaxImageSize && camera.height <= kMaxImageSize,
          name + ": camera " + camera.name + " is larger than 16384 pixels");
    TextureBox box;
    if (params.textureMode == TextureBoxMode::kFull) {
      box = fullFrameBox(camera.width, camera.height);
    } else {
      for (const Mesh& mesh : frames)
        box = unite(box, macroblockBox(renderMask(mesh, camera), params.textureBoxMargin));
      if (box.empty()) box = {0, 0, kMacroblockSize, kMacroblockSize};  // never sees the object
    }
    cameras_.push_back(toParameters(camera, box));
    frames_.emplace_back(dataset, c);
    H264Settings settings;
    settings.width = box.width;
    settings.height = box.height;
    settings.frameRate = params.frameRate;
    settings.qp = params.textureQp;
    settings.bitrateKbps = params.textureBitrate;
    settings.preset = params.texturePreset;
    encoders_.push_back(std::make_unique<H264Encoder>(settings));
    decoders_.push_back(std::make_unique<H264Decoder>("encoder's own texture of " + camera.name));
  }
}

TextureEncoder::~TextureEncoder() = default;

void TextureEncoder::encodeGom(size_t first, const std::vector<IntMesh>& decoded, const Grid& grid,
                               UnitWriter& units, const TextureCallback& onTexture) {
  for (size_t k = 0; k < decoded.size(); ++k) {
    const size_t frame = first + k;
    for (size_t c = 0; c < cameras_.size(); ++c) {
      const Camera camera = toCamera(cameras_[c], static_cast<int>(c));
      const TextureBox box = textureBox(cameras_[c]);
      const int datasetFrame = params_.firstFrame + static_cast<int>(frame);
      Image rgb = frames_[c].frame(datasetFrame);
      check(rgb.width == camera.width && rgb.height == camera.height,
            dataset_.resolve(kDatasetFileName) + ": camera " + dataset_.cameras[c].camera.name +
                " frame " + std::to_string(datasetFrame) + " is " + std::to_string(rgb.width) +
                "x" + std::to_string(rgb.height) + ", the calibration says " +
                std::to_string(camera.width) + "x" + std::to_string(camera.height));
      if (rgb.channels != 3) rgb = convertChannels(rgb, 3);
      const Image shape = textureShape(decoded[k], grid, camera);
      const YuvPicture picture = prepareTexture(rgb, shape, box, params_.texturePadding);
      TextureUnit tx;
      tx.tx_frame = static_cast<uint32_t>(frame);
      tx.tx_camera = static_cast<uint16_t>(c);
      tx.tx_access_unit = encoders_[c]->encode(picture, k == 0);
      const YuvPicture reconstruction =
          decoders_[c]->decode(tx.tx_access_unit, box.width, box.height);
      units.write(UnitType::kTexture, serialise(std::move(tx)));
      onTexture(static_cast<int>(frame), static_cast<int>(c), reconstruction, shape);
    }
  }
}

}  // namespace tdvo
