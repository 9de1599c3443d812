#include "tools/metrics/texture_metrics.h"

#include <chrono>
#include <cstdio>
#include <optional>
#include <vector>

#include "bitstream/byte_io.h"
#include "bitstream/camera_parameters.h"
#include "bitstream/syntax.h"
#include "bitstream/units.h"
#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/progress.h"
#include "common/media/dataset.h"
#include "tools/eval/metrics.h"

namespace tdvo {

namespace {

// The texture boxes of a stream's sequence header (its first unit), one per camera.
std::vector<TextureBox> streamBoxes(const std::string& path) {
  const std::vector<uint8_t> bytes = readFileBytes(path);
  UnitReader units(bytes.data(), bytes.size(), path);
  UnitView unit;
  check(units.next(unit) && unit.type == static_cast<uint8_t>(UnitType::kSequenceHeader),
        path + ": does not start with a sequence header unit");
  ByteReader reader(unit.payload, unit.size, path + ": " + unit.describe(), unit.payloadOffset);
  SequenceHeader sh;
  transfer(reader, sh);
  std::vector<TextureBox> boxes;
  for (const CameraParameters& c : sh.cameras)
    boxes.push_back(textureBox(c));
  return boxes;
}

// The test frame's shape: 255 where alpha is 255 (3dvo-dec writes alpha 255 exactly on the
// decoded shape inside the texture box, 0 elsewhere).
Image shapeFromAlpha(const Image& rgba) {
  Image mask(rgba.width, rgba.height, 1, 0);
  for (int y = 0; y < rgba.height; ++y)
    for (int x = 0; x < rgba.width; ++x)
      if (rgba.at(x, y, 3) == 255) mask.at(x, y) = 255;
  return mask;
}

std::string format(const std::optional<double>& value, int digits) {
  if (!value) return std::string();
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, *value);
  return buffer;
}

std::string text(const std::optional<double>& value) {
  return value ? format(value, 6) : std::string("n/a");
}

// One row of figures: the object's and the frame region's errors.
struct Row {
  PictureError object, region;
};

const char* const kCsvHeader =
    "frame,reference_frame,test_frame,camera,object_pixels,object_y_psnr,object_cb_psnr,"
    "object_cr_psnr,object_yuv_psnr,frame_pixels,frame_y_psnr,frame_cb_psnr,frame_cr_psnr,"
    "frame_yuv_psnr,frame_region\n";

std::string csvFigures(const Row& r, const std::string& region) {
  std::string s = std::to_string(r.object.pixels);
  for (int c = 0; c < 3; ++c)
    s += "," + format(r.object.psnr(c), 10);
  s += "," + format(r.object.yuvPsnr(), 10) + "," + std::to_string(r.region.pixels);
  for (int c = 0; c < 3; ++c)
    s += "," + format(r.region.psnr(c), 10);
  return s + "," + format(r.region.yuvPsnr(), 10) + "," + region + "\n";
}

void printFigures(const Row& r) {
  std::printf(" %8llu %8s %8s %8s %8s %8llu %8s %8s\n",
              static_cast<unsigned long long>(r.object.pixels), text(r.object.psnr(0)).c_str(),
              text(r.object.psnr(1)).c_str(), text(r.object.psnr(2)).c_str(),
              text(r.object.yuvPsnr()).c_str(), static_cast<unsigned long long>(r.region.pixels),
              text(r.region.psnr(0)).c_str(), text(r.region.yuvPsnr()).c_str());
}

}  // namespace

int runTextureMetrics(const TextureMetricsParams& p) {
  check(!p.referenceDataset.empty() && !p.testDataset.empty(),
        "texture metrics need both ReferenceDataset and TestDataset");
  const auto start = std::chrono::steady_clock::now();
  const Dataset reference = readDataset(p.referenceDataset);
  const Dataset test = readDataset(p.testDataset);
  const std::string referenceName = reference.resolve(kDatasetFileName);
  const std::string testName = test.resolve(kDatasetFileName);
  const size_t cameras = reference.cameras.size();
  check(test.cameras.size() == cameras, testName + ": has " + std::to_string(test.cameras.size()) +
                                            " cameras, " + referenceName + " " +
                                            std::to_string(cameras));
  for (size_t c = 0; c < cameras; ++c) {
    const Camera& a = reference.cameras[c].camera;
    const Camera& b = test.cameras[c].camera;
    check(a.width == b.width && a.height == b.height,
          testName + ": camera " + b.name + " is " + std::to_string(b.width) + "x" +
              std::to_string(b.height) + ", camera " + a.name + " of " + referenceName + " " +
              std::to_string(a.width) + "x" + std::to_string(a.height));
    check(test.cameras[c].alphaMask,
          testName + ": camera " + b.name +
              " has no alpha shape (alphaMask); expected a folder written by 3dvo-dec");
  }

  // Frames: test frame index TestFirstFrame + k against reference index ReferenceFirstFrame + k.
  check(p.referenceFirstFrame < reference.frameCount,
        referenceName + ": ReferenceFirstFrame " + std::to_string(p.referenceFirstFrame) +
            " but the dataset has " + std::to_string(reference.frameCount) + " frames");
  check(p.testFirstFrame < test.frameCount,
        testName + ": TestFirstFrame " + std::to_string(p.testFirstFrame) +
            " but the dataset has " + std::to_string(test.frameCount) + " frames");
  const int available =
      std::min(reference.frameCount - p.referenceFirstFrame, test.frameCount - p.testFirstFrame);
  const int frames = p.frameCount > 0 ? p.frameCount : available;
  check(frames <= available, "FrameCount " + std::to_string(frames) + " but " + referenceName +
                                 " from frame " + std::to_string(p.referenceFirstFrame) + " and " +
                                 testName + " from frame " + std::to_string(p.testFirstFrame) +
                                 " have only " + std::to_string(available));
  // The CSV file may not replace an input (docs/user-guide.md, "Output files"): any file of the
  // datasets (addDatasetFiles: every frame, camera and mask, the meshes) and the stream, by
  // file identity or sequence path, before any is read.
  if (!p.csvFile.empty()) {
    InputFiles inputs;
    inputs.add(p.bitstream);
    addDatasetFiles(inputs, reference);
    addDatasetFiles(inputs, test);
    inputs.checkOutput(p.csvFile);
  }

  // The frame region: each camera's texture box (clipped to the frame) or the whole frame.
  // The boxes come from the stream (Bitstream), else from the test dataset's textureBox fields
  // (3dvo-dec writes them), else the region is the whole frame.
  std::vector<TextureBox> boxes;
  std::string boxSource;
  bool datasetBoxes = true;
  for (const DatasetCamera& c : test.cameras)
    datasetBoxes = datasetBoxes && c.textureBox.has_value();
  if (!p.bitstream.empty()) {
    boxes = streamBoxes(p.bitstream);
    check(boxes.size() == cameras, p.bitstream + ": has " + std::to_string(boxes.size()) +
                                       " cameras, " + testName + " " + std::to_string(cameras));
    boxSource = p.bitstream;
  } else if (datasetBoxes) {
    for (const DatasetCamera& c : test.cameras) {
      const std::array<int, 4>& b = *c.textureBox;
      boxes.push_back({b[0], b[1], b[2], b[3]});
    }
    boxSource = testName;
  } else {
    for (const DatasetCamera& c : test.cameras)
      boxes.push_back({0, 0, c.camera.width, c.camera.height});
  }
  const std::string region = boxSource.empty() ? "frame" : "box";

  std::vector<CameraFrames> referenceFrames, testFrames;
  for (size_t c = 0; c < cameras; ++c) {
    referenceFrames.emplace_back(reference, c);
    testFrames.emplace_back(test, c);
  }

  std::printf("# 3dvo-metrics: texture\n");
  std::printf("reference           : %s, frames %d..%d\n", referenceName.c_str(),
              p.referenceFirstFrame, p.referenceFirstFrame + frames - 1);
  std::printf("test                : %s, frames %d..%d\n", testName.c_str(), p.testFirstFrame,
              p.testFirstFrame + frames - 1);
  std::printf("cameras             : %zu\n", cameras);
  std::printf("colour              : BT.601 Y'CbCr, limited range, per pixel from RGB\n");
  std::printf("object              : test pixels with alpha 255 (the decoded shape)\n");
  if (boxSource.empty())
    std::printf("frame region        : the whole camera frame\n");
  else
    std::printf("frame region        : the texture box of each camera, from %s\n",
                boxSource.c_str());
  std::printf("# per frame and camera: PSNR in dB; obj = inside the shape, frm = frame region\n");
  std::printf("%6s %6s %6s %4s %8s %8s %8s %8s %8s %8s %8s %8s\n", "frame", "ref", "test", "cam",
              "obj_px", "obj_Y", "obj_Cb", "obj_Cr", "obj_YUV", "frm_px", "frm_Y", "frm_YUV");

  std::string csv = kCsvHeader;
  std::vector<Row> perCamera(cameras);
  Row total;
  {
    Progress progress("comparing frames", static_cast<size_t>(frames));
    for (int k = 0; k < frames; ++k) {
      const int referenceFrame = p.referenceFirstFrame + k, testFrame = p.testFirstFrame + k;
      for (size_t c = 0; c < cameras; ++c) {
        const Image original = referenceFrames[c].frame(referenceFrame);
        const Image decoded = testFrames[c].frame(testFrame);
        const std::string where =
            "camera " + test.cameras[c].camera.name + " frame " + std::to_string(testFrame);
        check(decoded.channels == 4,
              testName + ": " + where + ": the image has no alpha channel (the shape)");
        check(original.channels >= 3, referenceName + ": camera " +
                                          reference.cameras[c].camera.name + " frame " +
                                          std::to_string(referenceFrame) + ": not an RGB image");
        check(original.width == decoded.width && original.height == decoded.height,
              testName + ": " + where + " is " + std::to_string(decoded.width) + "x" +
                  std::to_string(decoded.height) + ", the reference frame " +
                  std::to_string(original.width) + "x" + std::to_string(original.height));
        Row row;
        row.object = maskedPictureError(original, decoded, shapeFromAlpha(decoded));
        const TextureBox& b = boxes[c];
        row.region = regionPictureError(original, decoded, b.x, b.y, b.x + b.width, b.y + b.height);
        perCamera[c].object.add(row.object);
        perCamera[c].region.add(row.region);
        total.object.add(row.object);
        total.region.add(row.region);
        std::printf("%6d %6d %6d %4zu", k, referenceFrame, testFrame, c);
        printFigures(row);
        csv += std::to_string(k) + "," + std::to_string(referenceFrame) + "," +
               std::to_string(testFrame) + "," + std::to_string(c) + "," + csvFigures(row, region);
      }
      progress.tick(static_cast<size_t>(k) + 1);
    }
  }

  std::printf("# per camera, all frames (PSNR of the pooled squared error)\n");
  for (size_t c = 0; c < cameras; ++c) {
    std::printf("%6s %6s %6s %4zu", "all", "", "", c);
    printFigures(perCamera[c]);
    csv += "all,,," + std::to_string(c) + "," + csvFigures(perCamera[c], region);
  }
  csv += "all,,,all," + csvFigures(total, region);
  if (!p.csvFile.empty()) writeFileAtomic(p.csvFile, csv);

  auto line = [](const char* name, const std::optional<double>& value) {
    std::printf("%-22s: %s%s\n", name, text(value).c_str(), value ? " dB" : "");
  };
  std::printf("# summary (all cameras and frames, PSNR of the pooled squared error)\n");
  std::printf("%-22s: %d\n", "frames", frames);
  std::printf("%-22s: %zu\n", "cameras", cameras);
  std::printf("%-22s: %llu\n", "object pixels",
              static_cast<unsigned long long>(total.object.pixels));
  line("object Y-PSNR", total.object.psnr(0));
  line("object Cb-PSNR", total.object.psnr(1));
  line("object Cr-PSNR", total.object.psnr(2));
  line("object YUV-PSNR", total.object.yuvPsnr());
  std::printf("%-22s: %llu (%s)\n", "frame pixels",
              static_cast<unsigned long long>(total.region.pixels),
              boxSource.empty() ? "whole frames" : "texture boxes");
  line("frame Y-PSNR", total.region.psnr(0));
  line("frame YUV-PSNR", total.region.yuvPsnr());
  if (!p.csvFile.empty()) std::printf("%-22s: %s\n", "csv", p.csvFile.c_str());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%-22s: %.3f s\n", "time", seconds);
  return 0;
}

}  // namespace tdvo
