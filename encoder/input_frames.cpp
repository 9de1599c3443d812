#include "encoder/input_frames.h"

#include <filesystem>
#include <optional>

#include "bitstream/syntax.h"
#include "common/core/error.h"
#include "common/core/mesh_io.h"
#include "common/core/sequence.h"
#include "common/core/warnings.h"

namespace tdvo {

namespace {

std::string datasetName(const Dataset& dataset) {
  return dataset.resolve(kDatasetFileName);
}

std::string datasetRange(const Dataset& dataset) {
  return "its frames are " + std::to_string(dataset.firstFrame) + " .. " +
         std::to_string(dataset.firstFrame + dataset.frameCount - 1);
}

bool inDataset(const Dataset& dataset, int64_t frame) {
  return frame >= dataset.firstFrame && frame < int64_t{dataset.firstFrame} + dataset.frameCount;
}

}  // namespace

std::string inputMeshPath(const EncoderParams& params, const Dataset* dataset, int frame) {
  if (!params.inputMeshPattern.empty())
    return isMeshAnimationFile(params.inputMeshPattern) ? params.inputMeshPattern
                                                        : framePath(params.inputMeshPattern, frame);
  check(dataset != nullptr, "InputMeshPattern is not set, nor a Dataset with meshes");
  check(!dataset->meshes.empty(),
        datasetName(*dataset) + ": the dataset has no meshes; set InputMeshPattern");
  check(inDataset(*dataset, frame), datasetName(*dataset) + ": frame " + std::to_string(frame) +
                                        " is not in the dataset (" + datasetRange(*dataset) + ")");
  return dataset->framePath(dataset->meshes, frame - dataset->firstFrame);
}

namespace {

// FrameCount unset codes every frame up to the first missing file: when files of later frames
// exist (a gap in the numbering), that is a partial result, and it is said.
void warnAboutLaterFrames(const EncoderParams& params, int missing, const std::string& path) {
  const std::string& pattern = params.inputMeshPattern;
  if (pattern.empty() || isMeshAnimationFile(pattern)) return;
  if (const std::optional<std::string> later = firstFileAfter(pattern, missing))
    warn(*later + " exists, after " + path +
         ", which does not exist: the frames after that gap are not coded (FrameCount not set: "
         "every frame from FirstFrame until the first missing file); number the files without "
         "a gap");
}

}  // namespace

int resolveFrameCount(const EncoderParams& params, const Dataset* dataset, std::string* found) {
  if (params.frameCount > 0) return params.frameCount;
  if (dataset) {
    check(inDataset(*dataset, params.firstFrame),
          datasetName(*dataset) + ": FirstFrame " + std::to_string(params.firstFrame) +
              " is not a frame of the dataset (" + datasetRange(*dataset) + ")");
  }
  const int first = params.firstFrame;
  int count = 0;
  std::string why;
  for (;; ++count) {
    const int64_t frame = int64_t{first} + count;
    if (count == static_cast<int>(kMaxFrames)) {
      why = "the most a stream can hold";
      break;
    }
    if (dataset && !inDataset(*dataset, frame)) {
      why = "the last frame of " + datasetName(*dataset);
      break;
    }
    const std::string path = inputMeshPath(params, dataset, static_cast<int>(frame));
    std::error_code ec;
    // A dataset's meshes are as many as its frames.count says: a missing one is an error, not
    // the end of the sequence.
    if (dataset && params.inputMeshPattern.empty() && !std::filesystem::is_regular_file(path, ec))
      throw Error(path + ": cannot open: frame " + std::to_string(frame) + " of " +
                  datasetName(*dataset) + " (" + datasetRange(*dataset) +
                  ") has no mesh file; set FrameCount to code the frames before it");
    if (!std::filesystem::is_regular_file(path, ec)) {
      check(count > 0, path +
                           ": cannot open: no input frames (FrameCount not set: every frame "
                           "from FirstFrame " +
                           std::to_string(first) + " until the first missing file)");
      why = path + ", which does not exist";
      warnAboutLaterFrames(params, static_cast<int>(frame), path);
      break;
    }
  }
  if (found)
    *found = std::to_string(count) + " frames, " + std::to_string(first) + " .. " +
             std::to_string(first + count - 1) + " (" + inputMeshPath(params, dataset, first) +
             " .. " + inputMeshPath(params, dataset, first + count - 1) + "; stopped at " + why +
             ")";
  return count;
}

void checkTextureFrames(const EncoderParams& params, const Dataset& dataset, int count) {
  for (const int64_t frame : {int64_t{params.firstFrame}, int64_t{params.firstFrame} + count - 1}) {
    if (inDataset(dataset, frame)) continue;
    const std::string geometry = params.inputMeshPattern.empty()
                                     ? "frame " + std::to_string(frame)
                                     : inputMeshPath(params, nullptr, static_cast<int>(frame));
    throw Error(geometry + ": geometry frame " + std::to_string(frame) +
                " has no texture frame in " + datasetName(dataset) + " (" + datasetRange(dataset) +
                "; geometry and texture frames are tied by frame number)");
  }
}

}  // namespace tdvo
