// 3dvo-dec: decodes a .3dvo stream to OBJ frames and prints per-frame MD5 lines.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bitstream/camera_parameters.h"
#include "bitstream/header_hash.h"
#include "bitstream/units.h"
#include "common/app.h"
#include "common/config.h"
#include "common/dataset.h"
#include "common/file_io.h"
#include "common/gom_list.h"
#include "common/image.h"
#include "common/md5.h"
#include "common/obj_io.h"
#include "common/progress.h"
#include "common/sequence.h"
#include "common/yuv.h"
#include "decoder/decoder_version.h"
#include "decoder/stream_decoder.h"

using namespace tdvo;

namespace {

// The "MD5 ..." lines of a log (other lines, e.g. summaries, are ignored).
std::vector<std::string> readMd5Lines(const std::string& path) {
  const std::vector<uint8_t> bytes = readFileBytes(path);
  std::vector<std::string> lines;
  std::string line;
  for (size_t i = 0; i <= bytes.size(); ++i) {
    if (i == bytes.size() || bytes[i] == '\n') {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.rfind("MD5 ", 0) == 0) lines.push_back(line);
      line.clear();
    } else {
      line += static_cast<char>(bytes[i]);
    }
  }
  return lines;
}

std::string cameraFolder(int camera) {
  return "cam" + std::to_string(camera);
}

// Texture frames are named like the mesh frames, with .png: "%04d.obj" -> "%04d.png".
std::string imagePattern(const std::string& meshPattern) {
  const size_t dot = meshPattern.rfind('.');
  return (dot == std::string::npos ? meshPattern : meshPattern.substr(0, dot)) + ".png";
}

// The full camera frame as RGBA: the decoded box in place (the rest black), alpha from the
// object's shape inside the box.
Image cameraFrame(const YuvPicture& picture, const TextureBox& box, const Image& shape) {
  const Image rgb = yuv420ToRgb(picture);
  Image out(shape.width, shape.height, 4, 0);
  for (int y = 0; y < box.height && box.y + y < shape.height; ++y)
    for (int x = 0; x < box.width && box.x + x < shape.width; ++x) {
      for (int c = 0; c < 3; ++c)
        out.at(box.x + x, box.y + y, c) = rgb.at(x, y, c);
      out.at(box.x + x, box.y + y, 3) = shape.at(box.x + x, box.y + y) ? 255 : 0;
    }
  return out;
}

// The decoded output as a dataset (docs/dataset.md): meshes and per-camera RGBA frames.
Dataset decodedDataset(const StreamDecoder& decoder, const std::string& folder,
                       const std::string& meshPattern, int frames) {
  Dataset d;
  d.folder = folder;
  d.description = "decoded by 3dvo-dec";
  d.frameCount = frames;
  d.frameRate = decoder.sequenceHeader().sh_frame_rate;
  d.meshes = meshPattern;
  const auto& cameras = decoder.sequenceHeader().cameras;
  for (size_t c = 0; c < cameras.size(); ++c) {
    DatasetCamera dc;
    dc.camera = toCamera(cameras[c], static_cast<int>(c));
    dc.images = cameraFolder(static_cast<int>(c)) + "/" + imagePattern(meshPattern);
    dc.alphaMask = true;
    d.cameras.push_back(dc);
  }
  return d;
}

// Writes each camera's H.264 access units, in order, as one Annex B file DIR/cam<c>.264.
void extractTextures(const std::string& streamPath, const std::string& name, const std::string& dir,
                     StagedFiles& outputs) {
  makeDirectories(dir);
  std::vector<std::vector<uint8_t>> perCamera;
  UnitFileReader units(streamPath, name);
  UnitView unit;
  while (units.next(unit)) {
    if (unit.type != static_cast<uint8_t>(UnitType::kTexture)) continue;
    ByteReader reader(unit.payload, unit.size, name + ": " + unit.describe(), unit.payloadOffset);
    TextureUnit tx;
    transfer(reader, tx);
    if (tx.tx_camera >= perCamera.size()) perCamera.resize(tx.tx_camera + 1);
    perCamera[tx.tx_camera].insert(perCamera[tx.tx_camera].end(), tx.tx_access_unit.begin(),
                                   tx.tx_access_unit.end());
  }
  for (size_t c = 0; c < perCamera.size(); ++c)
    outputs.write(dir + "/" + cameraFolder(static_cast<int>(c)) + ".264", perCamera[c].data(),
                  perCamera[c].size());
}

}  // namespace

int main(int argc, char** argv) {
  return runApp("3dvo-dec", [&]() {
    std::string extractDir, streamPath, outputDir, meshPattern = "%04d.obj", verifyPath;
    bool trace = false;
    int threads = 1;
    int maxVertexFramesPerByte = static_cast<int>(kDefaultMaxVertexFramesPerByte);
    PngEffort pngEffort = PngEffort::kFast;
    OptionTable table("3dvo-dec", "3dvo-dec -i STREAM.3dvo [-o OUTDIR] [--verify MD5LOG]");
    table.section("Decoder");
    table.add("BitstreamFile", streamPath, "the .3dvo stream to decode", "-i");
    table.add("OutputDir", outputDir, "folder for the decoded frames (none: hashes only)", "-o");
    table.add("OutputMeshPattern", meshPattern,
              "file name of decoded frame n inside OutputDir (printf pattern, n from 0)");
    table.addEnum("PngCompression", pngEffort,
                  {{"fast", PngEffort::kFast}, {"small", PngEffort::kSmall}},
                  "the camera frames' PNG files: fast = zlib level 1, Up filter; small = zlib "
                  "level 6, adaptive filters (about 3.7x slower, files about 30 % smaller); the "
                  "pixels are the same");
    table.add("VerifyMd5", verifyPath,
              "compare the decoded MD5 lines with this log's; exit 1 on any difference",
              "--verify");
    table.add("ExtractTextures", extractDir,
              "write each camera's H.264 texture stream to this folder as cam<c>.264 (Annex B)",
              "--extract-textures");
    table.add("MaxVertexFramesPerByte", maxVertexFramesPerByte, 0, 1 << 30,
              "refuse a stream declaring more decoded vertices x frames than this per stream "
              "byte read (a GOM's frames x its I mesh's vertices, summed; docs/robustness.md); "
              "0 = no limit");
    table.add("Trace", trace, "print every syntax element read to stderr", "--trace");
    table.add("Threads", threads, 0, 256,
              "cameras whose textures are decoded in parallel (0 = hardware concurrency); the "
              "output, the MD5 lines and any error are the same for any value");
    table.addVersionLines(decoderVersionLines());
    if (!table.parseCommandLine(argc, argv)) return 0;
    check(!streamPath.empty(), "no stream given (-i STREAM.3dvo; see --help)");
    checkFramePattern(meshPattern, "OutputMeshPattern");
    const auto start = std::chrono::steady_clock::now();

    std::vector<std::string> expected;
    if (!verifyPath.empty()) expected = readMd5Lines(verifyPath);
    // A folder this run creates is removed again if the run fails (it is empty then: the
    // frames are staged and removed on failure).
    struct CreatedFolder {
      std::string path;
      bool keep = false;
      ~CreatedFolder() {
        std::error_code ec;
        if (!keep && !path.empty()) std::filesystem::remove(path, ec);
      }
    } createdFolder;
    if (!outputDir.empty()) {
      if (!std::filesystem::exists(outputDir)) createdFolder.path = outputDir;
      makeDirectories(outputDir);
    }

    // Units are read from the file one at a time and every frame is written (and released) as
    // soon as it is decoded: memory does not grow with the length of the sequence.
    UnitFileReader units(streamPath, streamPath);
    const uint64_t streamBytes = units.fileSize();
    StreamDecoder decoder(units, streamPath, trace ? stderr : nullptr);
    decoder.setMaxVertexFramesPerByte(static_cast<uint64_t>(maxVertexFramesPerByte));
    decoder.setThreads(
        threads > 0 ? threads : std::max(1, static_cast<int>(std::thread::hardware_concurrency())));
    StagedFiles outputs;
    uint64_t vertexFrames = 0;
    int frames = 0;
    size_t lines = 0;  // MD5 lines printed so far, compared in order with the log's
    auto report = [&](const std::string& line) {
      std::printf("%s\n", line.c_str());
      if (verifyPath.empty()) return;
      check(lines < expected.size(), verifyPath + ": has no line for '" + line + "'");
      check(expected[lines] == line, verifyPath + ": line " + std::to_string(lines + 1) +
                                         " of its MD5 lines differs: "
                                         "expected '" +
                                         expected[lines] + "', decoded '" + line + "'");
      ++lines;
    };
    // Frames decoded, on stderr when it is a terminal (the count is known once the sequence
    // header is read).
    std::optional<Progress> progress;
    std::mutex pngMutex;
    std::map<std::pair<int, int>, std::vector<uint8_t>> pngs;  // (frame, camera): to be written
    decoder.decode(
        [&](int frame, const IntMesh& mesh) {
          report(geometryHashLine(frame, mesh));
          if (!outputDir.empty())
            outputs.write(outputDir + "/" + framePath(meshPattern, frame),
                          formatObj(decoder.grid().dequantise(mesh)));
          vertexFrames += mesh.positions.size();
          frames = frame + 1;
          if (!progress) progress.emplace("3dvo-dec: frame", decoder.sequenceHeader().sh_frame_count);
          progress->tick(static_cast<size_t>(frames));
        },
        [&](int frame, int camera, const YuvPicture& picture, const Image&) {
          report(textureHashLine(frame, camera, picture));
          if (outputDir.empty()) return;
          std::vector<uint8_t> png;
          {
            std::lock_guard<std::mutex> lock(pngMutex);
            const auto made = pngs.find({frame, camera});
            png = std::move(made->second);
            pngs.erase(made);
          }
          const std::string folder = outputDir + "/" + cameraFolder(camera);
          makeDirectories(folder);
          outputs.write(folder + "/" + framePath(imagePattern(meshPattern), frame), png.data(),
                        png.size());
        },
        // The PNGs are made where the pictures are decoded (on Threads threads), then written
        // above in order.
        outputDir.empty() ? TextureCallback() : [&](int frame, int camera,
                                                    const YuvPicture& picture, const Image& shape) {
          const CameraParameters& c = decoder.sequenceHeader().cameras[camera];
          std::vector<uint8_t> png =
              encodePng(cameraFrame(picture, textureBox(c), shape), pngEffort);
          std::lock_guard<std::mutex> lock(pngMutex);
          pngs[{frame, camera}] = std::move(png);
        });
    // What the frame lines do not cover: the grid, the cameras, every header field.
    report(sequenceHeaderHashLine(decoder.sequenceHeader()));
    if (!verifyPath.empty())
      check(expected.size() == lines, verifyPath + ": has " + std::to_string(expected.size()) +
                                          " MD5 lines, the stream gives " + std::to_string(lines));
    if (!outputDir.empty() && !decoder.sequenceHeader().cameras.empty())
      outputs.write(
          outputDir + "/" + kDatasetFileName,
          formatDataset(decodedDataset(decoder, outputDir, meshPattern, frames), outputDir));
    // Where each GOM starts: 3dvo-metrics matches vertices there (GroupStarts), the player
    // of 3dvo-render --Mode=export seeks to these frames.
    if (!outputDir.empty())
      outputs.write(outputDir + "/" + kGomStartsFileName, formatGomStarts(decoder.gomStarts()));
    if (!extractDir.empty()) extractTextures(streamPath, streamPath, extractDir, outputs);
    progress.reset();  // clears its line before the summary
    outputs.commit();
    createdFolder.keep = true;

    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double bits = 8.0 * streamBytes;
    const double fps = decoder.sequenceHeader().sh_frame_rate;
    std::printf("# summary\n");
    std::printf("frames              : %d\n", frames);
    if (!outputDir.empty()) std::printf("output              : %s\n", outputDir.c_str());
    std::printf("bytes               : %zu\n", static_cast<size_t>(streamBytes));
    const uint64_t textureBytes = decoder.textureBytes();
    std::printf("bits/vertex/frame   : %.4f (geometry and headers only)\n",
                8.0 * (streamBytes - textureBytes) / static_cast<double>(vertexFrames));
    if (textureBytes > 0)
      std::printf("texture kbit/s      : %.3f (all cameras)\n",
                  8.0 * textureBytes / 1000.0 / (frames / fps));
    std::printf("kbit/s at %g fps    : %.3f\n", fps, bits / 1000.0 / (frames / fps));
    std::printf("time                : %.3f s\n", seconds);
    if (!verifyPath.empty()) std::printf("verify              : all %d frames match\n", frames);
    return 0;
  });
}
