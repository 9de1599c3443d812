// The 3DVO dataset layout: one folder with a calibration file, dataset.json, that lists the
// cameras and, per camera, where its frames are (an image sequence or a video file), optional
// silhouette masks and background, plus optional ground-truth meshes. The encoder, the
// reconstruction, the renderer, the importers and the synthetic rig all use this one layout;
// docs/dataset.md describes every field with an example.
//
// Frames: the dataset has frameCount frames, indexed 0 … frameCount−1. Frame index i has the
// frame number n = firstFrame + i: image, mask and mesh patterns ("cam0/%04d.png") are filled
// with n, and videos are read at their n-th frame (counting from 0). A path without a %d
// conversion names one still file used for every frame (a still multi-view set has one frame).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/core/file_io.h"
#include "common/core/mesh.h"
#include "common/views/camera.h"
#include "common/views/image.h"

namespace tdvo {

class VideoReader;

constexpr const char* kDatasetFileName = "dataset.json";

struct DatasetCamera {
  Camera camera;                // name, image size, intrinsics, distortion, R, t
  std::string images;           // PNG image sequence pattern or still image; or
  std::string video;            // a video file (anything FFmpeg reads): exactly one of the two
  std::string masks;            // optional silhouette masks (PNG pattern or still)
  bool alphaMask = false;       // the images' alpha channel is the silhouette
  std::string background;       // optional background without the object (PNG pattern or still)
  std::string backgroundVideo;  // optional background video
  // The texture box a 3DVO stream codes of this camera, [x, y, width, height] in pixels
  // (written by 3dvo-dec; 3dvo-metrics measures inside it).
  std::optional<std::array<int, 4>> textureBox;
};

struct Dataset {
  // The folder that relative paths are relative to (where dataset.json lives).
  std::string folder = ".";
  std::string description;  // free text: where the data came from
  int firstFrame = 0;
  int frameCount = 1;
  double frameRate = 25;
  std::optional<Vec3d> up;  // the world's up direction, when known
  std::string meshes;       // optional ground-truth meshes (OBJ pattern or still)
  std::vector<DatasetCamera> cameras;

  // A path of the dataset as a usable file name: `folder`/`path` unless `path` is absolute.
  std::string resolve(const std::string& path) const;
  // The file of frame index `frame` for a pattern or still path (resolved). Image, mask,
  // background and mesh paths are pattern text: "%%" is a '%', in a still path too.
  std::string framePath(const std::string& pattern, int frame) const;
  // Index of the camera with this name; throws Error when there is none.
  size_t cameraIndex(const std::string& name) const;
};

// True when `path` holds a frame-number conversion (%d, %Nd, %0Nd).
bool hasFrameConversion(const std::string& path);

// Every file a dataset names (dataset.json, each camera's images, video, masks, background and
// background video, the meshes; sequences over all the dataset's frames), for protecting them
// from a run's outputs: as InputFiles (an output file that is one of them is refused), and as
// the paths that an output folder replaced with --Overwrite may not hold (dataset.json, each
// still file, and the folder of each sequence: its pattern's path up to the last '/' before
// the conversion).
void addDatasetFiles(InputFiles& inputs, const Dataset& dataset);
std::vector<std::string> datasetPaths(const Dataset& dataset);

// Reads `folderOrFile`/dataset.json (or the named JSON file) and checks its structure: required
// fields present with valid values, no unknown keys, rotations orthonormal, camera names unique,
// exactly one image source per camera. Throws Error naming the file and the field.
Dataset readDataset(const std::string& folderOrFile);
// Parses dataset JSON text; `name` is used in messages, `folder` becomes Dataset::folder.
Dataset parseDataset(const std::string& json, const std::string& name, const std::string& folder);

// Checks a dataset's structure (what parseDataset checks), naming `name` in messages.
void checkDataset(const Dataset& dataset, const std::string& name);

// Camera names name files and folders inside an app's output folder (3dvo-recon's
// silhouettes/NAME/, 3dvo-render's NAME/ of a leave-one-out run, 3dvo-synth's NAME/): a name
// must be one file name, so that it can never choose a place outside that folder. Throws Error
// "<where>: camera name '<name>' cannot name a folder (...)" for an empty name, "." or "..", a
// name with '/', '\\' or a control character, or one longer than 255 bytes (docs/dataset.md).
void checkCameraName(const std::string& name, const std::string& where);

// The dataset.json text for a dataset placed in `outputFolder`: absolute paths stay as they are,
// relative ones (relative to dataset.folder) are rewritten relative to `outputFolder` when both
// lie under the same top-level folder (e.g. /work), else written absolute.
// Deterministic: same dataset, same bytes.
std::string formatDataset(const Dataset& dataset, const std::string& outputFolder);
// Writes `outputFolder`/dataset.json atomically (creating the folder when missing).
void writeDataset(const Dataset& dataset, const std::string& outputFolder);

// Checks that every file the dataset names exists and fits: each frame's image and mask is a PNG
// of the camera's size, videos open with the camera's size and (when the container says) have
// enough frames, mesh files exist. Throws Error naming the file and what is wrong.
void validateDatasetFiles(const Dataset& dataset);

// Reads the frames of one camera; sequential reads of a video decode each frame once.
class CameraFrames {
 public:
  CameraFrames(const Dataset& dataset, size_t camera);
  ~CameraFrames();
  CameraFrames(CameraFrames&&) noexcept;
  // The RGB (or RGBA, or grey, as stored) image of frame index `frame`.
  Image frame(int frame);
  // The silhouette of frame index `frame` as a grey image, 255 inside and 0 outside: from the
  // mask files (first sample ≥ 128 is inside) or from the images' alpha (alpha ≥ 128).
  Image mask(int frame);
  bool hasMasks() const;

 private:
  const Dataset* dataset_;
  size_t camera_;
  std::unique_ptr<VideoReader> video_;
};

// The ground-truth mesh of frame index `frame`; throws Error when the dataset has none.
Mesh readDatasetMesh(const Dataset& dataset, int frame);

}  // namespace tdvo
