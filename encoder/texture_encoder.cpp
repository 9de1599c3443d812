#include "encoder/texture_encoder.h"

#include "bitstream/camera_parameters.h"
#include "common/core/error.h"
#include "common/core/ordered_parallel.h"
#include "common/views/rasteriser.h"
#include "common/views/texture_shape.h"
#include "decoder/texture/h264_decoder.h"
#include "encoder/h264_encoder.h"
#include "encoder/input_frames.h"
#include "encoder/texture_padding.h"

namespace tdvo {

void checkDatasetMeshes(const Dataset& dataset, int firstFrame, int frameCount) {
  check(!dataset.meshes.empty(),
        dataset.resolve(kDatasetFileName) + ": the dataset has no meshes; set InputMeshPattern");
  check(firstFrame + frameCount <= dataset.frameCount,
        dataset.resolve(kDatasetFileName) +
            ": FirstFrame + FrameCount = " + std::to_string(firstFrame + frameCount) +
            " but the dataset has " + std::to_string(dataset.frameCount) + " frames");
}

std::vector<Mesh> readDatasetFrames(const Dataset& dataset, int firstFrame, int frameCount) {
  checkDatasetMeshes(dataset, firstFrame, frameCount);
  std::vector<Mesh> frames;
  for (int k = 0; k < frameCount; ++k)
    frames.push_back(readDatasetMesh(dataset, firstFrame + k));
  return frames;
}

TextureBoxFinder::TextureBoxFinder(const EncoderParams& params, const Dataset& dataset,
                                   size_t frameCount)
    : params_(params), dataset_(dataset) {
  const std::string name = dataset.resolve(kDatasetFileName);
  check(!dataset.cameras.empty(), name + ": no cameras");
  check(dataset.cameras.size() <= kMaxCameras,
        name + ": more than " + std::to_string(kMaxCameras) + " cameras");
  check(frameCount > 0 && frameCount <= kMaxFrames, name + ": no frames to code");
  checkTextureFrames(params, dataset, static_cast<int>(frameCount));
  for (const DatasetCamera& c : dataset.cameras) {
    // The bounds of cam_width and cam_height (bitstream/syntax.h).
    const std::string maxSize = std::to_string(kMaxImageSize);
    check(c.camera.width <= kMaxImageSize && c.camera.height <= kMaxImageSize,
          name + ": camera " + c.camera.name + " is larger than " + maxSize + " pixels");
    check(c.camera.width >= kMinImageSize && c.camera.height >= kMinImageSize,
          name + ": camera " + c.camera.name + " is " + std::to_string(c.camera.width) + "x" +
              std::to_string(c.camera.height) + " pixels; the stream's cameras are " +
              std::to_string(kMinImageSize) + " .. " + maxSize + " pixels wide and high");
  }
  // The texts the stream carries (the rest of the dataset's fields are numbers or paths).
  check(dataset.description.size() <= kMaxDescriptionBytes,
        name + ": description: longer than " + std::to_string(kMaxDescriptionBytes) +
            " bytes, more than the stream carries");
  check(dataset.description.find('\0') == std::string::npos,
        name + ": description: holds a NUL character (\\u0000), which the stream does not carry");
  for (const DatasetCamera& c : dataset.cameras)
    check(c.camera.name.size() <= kMaxCameraNameBytes,
          name + ": camera name '" + c.camera.name.substr(0, 32) + "...' is longer than " +
              std::to_string(kMaxCameraNameBytes) + " bytes, more than the stream carries");
  boxes_.resize(dataset.cameras.size());
  if (params.textureMode == TextureBoxMode::kBox)
    for (const DatasetCamera& c : dataset.cameras)
      renderers_.emplace_back(c.camera);
}

TextureBoxFinder::~TextureBoxFinder() = default;

void TextureBoxFinder::add(const Mesh& mesh) {
  if (params_.textureMode != TextureBoxMode::kBox) return;
  // The shapes outside the lock (MaskRenderer::render may run on several threads at once).
  std::vector<TextureBox> frameBoxes(renderers_.size());
  for (size_t c = 0; c < renderers_.size(); ++c)
    frameBoxes[c] = macroblockBox(renderers_[c].render(mesh), params_.textureBoxMargin);
  std::lock_guard<std::mutex> lock(mutex_);
  for (size_t c = 0; c < renderers_.size(); ++c)
    boxes_[c] = unite(boxes_[c], frameBoxes[c]);
}

std::vector<TextureBox> TextureBoxFinder::boxes() const {
  std::vector<TextureBox> boxes;
  if (params_.textureMode == TextureBoxMode::kFull) {
    for (const DatasetCamera& c : dataset_.cameras)
      boxes.push_back(fullFrameBox(c.camera.width, c.camera.height));
    return boxes;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  boxes = boxes_;
  for (TextureBox& box : boxes)
    if (box.empty()) box = {0, 0, kMacroblockSize, kMacroblockSize};  // never sees the object
  return boxes;
}

namespace {

// The boxes from meshes in memory, params.threadCount() frames at a time.
std::vector<TextureBox> findBoxes(const EncoderParams& params, const Dataset& dataset,
                                  const std::vector<Mesh>& frames) {
  TextureBoxFinder finder(params, dataset, frames.size());
  if (params.textureMode == TextureBoxMode::kBox) {
    const int threads = params.threadCount();
    orderedParallelFor<int>(
        frames.size(), threads, 2 * static_cast<size_t>(threads),
        [&](size_t k) {
          finder.add(frames[k]);
          return 0;
        },
        [](size_t, int&) {});
  }
  return finder.boxes();
}

}  // namespace

TextureEncoder::TextureEncoder(const EncoderParams& params, const Dataset& dataset,
                               const std::vector<Mesh>& frames)
    : TextureEncoder(params, dataset, findBoxes(params, dataset, frames)) {}

TextureEncoder::TextureEncoder(const EncoderParams& params, const Dataset& dataset,
                               const std::vector<TextureBox>& boxes)
    : params_(params), dataset_(dataset) {
  check(boxes.size() == dataset.cameras.size() && !boxes.empty(),
        "TextureEncoder: one texture box per camera expected");
  for (size_t c = 0; c < dataset.cameras.size(); ++c) {
    const Camera& camera = dataset.cameras[c].camera;
    const TextureBox& box = boxes[c];
    cameras_.push_back(toParameters(camera, box));
    shapes_.emplace_back(toCamera(cameras_.back(), static_cast<int>(c)));  // as decoded
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
  // Item i = k * cameras + c is camera c's picture of the GOM's frame k. The items run on
  // Threads threads, at most `cameras` of them started and not yet consumed: item i starts only
  // once item i - cameras (the same camera's previous picture) has been consumed, so each
  // camera's H.264 encoder and decoder see its pictures in order, one at a time, and the
  // cameras of a frame are coded in parallel. Units and callbacks follow in item order
  // (frame-major), as a sequential run gives them.
  const size_t cameras = cameras_.size();
  std::vector<Mesh> meshes;  // the GOM's decoded meshes, dequantised once for all cameras
  meshes.reserve(decoded.size());
  for (const IntMesh& mesh : decoded)
    meshes.push_back(grid.dequantise(mesh));
  struct Coded {
    TextureUnit unit;
    YuvPicture reconstruction;
    Image shape;
  };
  orderedParallelFor<Coded>(
      decoded.size() * cameras, params_.threadCount(), cameras,
      [&](size_t i) {
        const size_t k = i / cameras, c = i % cameras;
        const size_t frame = first + k;
        const Camera& camera = shapes_[c].camera();
        const TextureBox box = textureBox(cameras_[c]);
        // Tied by frame number: the input's frame FirstFrame + frame is dataset frame index
        // FirstFrame + frame - frames.first (checkTextureFrames made sure it is one).
        const int frameNumber = params_.firstFrame + static_cast<int>(frame);
        const int datasetFrame = frameNumber - dataset_.firstFrame;
        Image rgb = frames_[c].frame(datasetFrame);
        check(rgb.width == camera.width && rgb.height == camera.height,
              dataset_.resolve(kDatasetFileName) + ": camera " + dataset_.cameras[c].camera.name +
                  " frame " + std::to_string(frameNumber) + " is " + std::to_string(rgb.width) +
                  "x" + std::to_string(rgb.height) + ", the calibration says " +
                  std::to_string(camera.width) + "x" + std::to_string(camera.height));
        if (rgb.channels != 3) rgb = convertChannels(rgb, 3);
        Coded coded;
        coded.shape = textureShape(meshes[k], shapes_[c]);
        const YuvPicture picture = prepareTexture(rgb, coded.shape, box, params_.texturePadding);
        coded.unit.tx_frame = static_cast<uint32_t>(frame);
        coded.unit.tx_camera = static_cast<uint16_t>(c);
        coded.unit.tx_access_unit = encoders_[c]->encode(picture, k == 0);
        coded.reconstruction =
            decoders_[c]->decode(coded.unit.tx_access_unit, box.width, box.height);
        return coded;
      },
      [&](size_t i, Coded& coded) {
        const int frame = static_cast<int>(coded.unit.tx_frame);
        units.write(UnitType::kTexture, serialise(std::move(coded.unit)));
        onTexture(frame, static_cast<int>(i % cameras), coded.reconstruction, coded.shape);
      });
}

}  // namespace tdvo
