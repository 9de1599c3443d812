// 3dvo-dec: decodes a .3dvo stream to mesh frames (OBJ, PLY or glTF) and prints per-frame MD5
// lines.
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bitstream/camera_parameters.h"
#include "bitstream/header_hash.h"
#include "bitstream/units.h"
#include "common/core/app.h"
#include "common/core/config.h"
#include "common/core/file_io.h"
#include "common/core/gltf_io.h"
#include "common/core/gom_list.h"
#include "common/core/md5.h"
#include "common/core/mesh_io.h"
#include "common/core/obj_io.h"
#include "common/core/progress.h"
#include "common/core/sequence.h"
#include "common/media/dataset.h"
#include "common/media/media_version.h"
#include "common/media/png_io.h"
#include "common/media/yuv.h"
#include "common/views/image.h"
#include "decoder/decoder_version.h"
#include "decoder/stream_decoder.h"
#include "decoder/texture/h264_decoder.h"

using namespace tdvo;

namespace {

// The frame number of an "MD5 frame=<n> ..." line (-1 when it has none).
int64_t md5LineFrame(const std::string& line) {
  const std::string prefix = "MD5 frame=";
  if (line.rfind(prefix, 0) != 0) return -1;
  int64_t n = 0;
  size_t i = prefix.size();
  if (i >= line.size() || line[i] < '0' || line[i] > '9') return -1;
  for (; i < line.size() && line[i] >= '0' && line[i] <= '9' && n < (int64_t{1} << 40); ++i)
    n = n * 10 + (line[i] - '0');
  return n;
}

// The "MD5 ..." lines of a log (other lines, e.g. summaries, are ignored), read one at a time
// as the decoded lines are compared with them: memory does not grow with the log. A line longer
// than kMaxMd5LogLine bytes (no MD5 line is) is an error, so a file that never ends a line
// (/dev/zero) is refused at once.
constexpr size_t kMaxMd5LogLine = size_t{1} << 16;

class Md5Log {
 public:
  explicit Md5Log(const std::string& path) : path_(path), file_(std::fopen(path.c_str(), "rb")) {
    if (!file_) throw Error(path + ": cannot open: " + std::strerror(errno));
    noteFileRead(file_);
  }
  ~Md5Log() { std::fclose(file_); }
  Md5Log(const Md5Log&) = delete;
  Md5Log& operator=(const Md5Log&) = delete;

  // From now on, next() skips the frame lines of frames outside [first, end) (a decoder frame
  // range is compared with the log's lines of its frames only).
  void keepFrames(int64_t first, int64_t end) {
    first_ = first;
    end_ = end;
  }

  // The next MD5 line into `line`; false at the end of the file.
  bool next(std::string& line) {
    while (readLine(line)) {
      if (line.rfind("MD5 ", 0) != 0) continue;
      const int64_t frame = md5LineFrame(line);
      if (frame >= 0 && (frame < first_ || frame >= end_)) continue;
      return true;
    }
    return false;
  }

 private:
  bool readLine(std::string& line) {
    line.clear();
    int c;
    while ((c = std::getc(file_)) != EOF && c != '\n') {
      if (line.size() == kMaxMd5LogLine)
        throw Error(path_ + ":" + std::to_string(lineNumber_ + 1) + ": line longer than " +
                    std::to_string(kMaxMd5LogLine) + " bytes (not an MD5 log)");
      line += static_cast<char>(c);
    }
    if (std::ferror(file_)) throw Error(path_ + ": read error: " + std::strerror(errno));
    if (c == EOF && line.empty()) return false;
    ++lineNumber_;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  }

  std::string path_;
  std::FILE* file_;
  size_t lineNumber_ = 0;
  int64_t first_ = 0, end_ = INT64_MAX;
};

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

// The decoded output as a dataset (docs/dataset.md): meshes and per-camera RGBA frames, with
// everything of the input dataset the stream carries (cameras with their names, description,
// up, frame numbers from `firstNumber`) and each camera's texture box.
Dataset decodedDataset(const StreamDecoder& decoder, const std::string& folder,
                       const std::string& meshPattern, bool meshes, int firstNumber, int frames) {
  const SequenceHeader& sh = decoder.sequenceHeader();
  Dataset d;
  d.folder = folder;
  d.description = sh.sh_description;
  d.firstFrame = firstNumber;
  d.frameCount = frames;
  d.frameRate = sh.sh_frame_rate;
  if (sh.sh_up_present) d.up = Vec3d{sh.sh_up[0], sh.sh_up[1], sh.sh_up[2]};
  if (meshes) d.meshes = meshPattern;  // MeshFormat none: a dataset without meshes
  const auto& cameras = sh.cameras;
  for (size_t c = 0; c < cameras.size(); ++c) {
    DatasetCamera dc;
    dc.camera = toCamera(cameras[c], static_cast<int>(c));
    dc.images = cameraFolder(static_cast<int>(c)) + "/" + imagePattern(meshPattern);
    dc.alphaMask = true;
    const TextureBox box = textureBox(cameras[c]);
    dc.textureBox = std::array<int, 4>{box.x, box.y, box.width, box.height};
    d.cameras.push_back(dc);
  }
  return d;
}

// True when folder `a` is folder `b` or inside it (by name).
bool insideFolder(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  const fs::path relative =
      fs::path(a + "/").lexically_normal().lexically_relative(fs::path(b + "/").lexically_normal());
  return !relative.empty() && *relative.begin() != "..";
}

// Writes each camera's H.264 access units, in order, as one Annex B file DIR/cam<c>.264.
void extractTextures(const std::string& streamPath, const std::string& name, const std::string& dir,
                     OutputFolder& outputs) {
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
    std::string meshFormatName, animationFile;
    bool trace = false, renumber = false, overwrite = false;
    int threads = 1, firstFrame = 0, frameCount = 0;
    int maxVertexFramesPerByte = static_cast<int>(kDefaultMaxVertexFramesPerByte);
    int maxTexturePixelsPerByte = static_cast<int>(kDefaultMaxTexturePixelsPerByte);
    int maxMeshMemoryPerByte = static_cast<int>(kDefaultMaxMeshMemoryPerByte);
    PngEffort pngEffort = PngEffort::kFast;
    OptionTable table("3dvo-dec", "3dvo-dec -i STREAM.3dvo [-o OUTDIR] [--verify MD5LOG]");
    table.section("Decoder");
    table.add("BitstreamFile", streamPath, "the .3dvo stream to decode", "-i");
    table.add("OutputDir", outputDir, "folder for the decoded frames (none: hashes only)", "-o");
    table.add("OutputMeshPattern", meshPattern,
              "file name of decoded frame n inside OutputDir (printf pattern; n is the input's "
              "frame number, or from 0 with RenumberFrames)");
    table.add("MeshFormat", meshFormatName,
              "the decoded frames' files: obj | ply (binary little-endian) | ply-ascii | gltf "
              "(buffer as a data URI) | glb | none (no per-frame files); not set: from "
              "OutputMeshPattern's extension (obj unless .ply, .gltf or .glb); set, the default "
              "OutputMeshPattern gets its extension");
    table.add("AnimationFile", animationFile,
              "also write the decoded frames as one animated glTF binary (.glb) of this name "
              "inside OutputDir (morph targets per run of constant connectivity; "
              "docs/user-guide.md)");
    table.add("RenumberFrames", renumber,
              "number the output frames from 0 (files, gom_starts.txt, dataset.json) instead "
              "of with the input's frame numbers; the MD5 lines keep the input's numbers");
    table.add("FirstFrame", firstFrame, 0, static_cast<int>(kMaxFirstFrame + kMaxFrames - 1),
              "decode from this input frame number on (not set: the stream's first frame); "
              "decoding starts at the GOM holding it, output starts at it");
    table.derivedWhenUnset("FirstFrame", "the stream's first frame", false);
    table.add("FrameCount", frameCount, 0, static_cast<int>(kMaxFrames),
              "output this many frames from FirstFrame (0 = to the end of the stream)");
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
    table.add("Overwrite", overwrite,
              "replace the contents of a non-empty OutputDir (and ExtractTextures folder); "
              "without it such a folder is refused",
              "--Overwrite");
    table.add("MaxVertexFramesPerByte", maxVertexFramesPerByte, 0, 1 << 30,
              "refuse a stream declaring more decoded vertices x frames than this per stream "
              "byte read (a GOM's frames x its I mesh's vertices, summed; docs/robustness.md); "
              "0 = no limit");
    table.add("MaxTexturePixelsPerByte", maxTexturePixelsPerByte, 0, 1 << 30,
              "refuse a stream whose texture units add up to more camera pixels than this per "
              "stream byte read, or whose camera frames need more memory than the stream read "
              "so far allows (2^21 pixels + 2 per byte read; docs/robustness.md); 0 = no limit");
    table.add("MaxMeshMemoryPerByte", maxMeshMemoryPerByte, 0, 1 << 30,
              "refuse an I mesh whose vertex and face counts need more decoding memory than "
              "40 MiB + this many bytes per stream byte read (Draco allocates from them; "
              "docs/robustness.md, \"Memory\"); 0 = no limit");
    table.add("Trace", trace, "print every syntax element read to stderr", "--trace");
    table.add("Threads", threads, 0, 256,
              "cameras whose textures are decoded in parallel (0 = hardware concurrency); the "
              "output, the MD5 lines and any error are the same for any value");
    table.addVersionLines(decoderVersionLines());
    table.addVersionLines(mediaLibraryVersions());
    if (!table.parseCommandLine(argc, argv)) return 0;
    check(!streamPath.empty(), "no stream given (-i STREAM.3dvo; see --help)");
    // The per-frame mesh format: MeshFormat, else OutputMeshPattern's extension.
    bool writeMeshes = true;
    MeshOutputFormat meshFormat = MeshOutputFormat::kObj;
    if (meshFormatName.empty()) {
      meshFormat = meshOutputFormat(meshPattern);
    } else {
      const std::pair<const char*, MeshOutputFormat> kFormats[] = {
          {"obj", MeshOutputFormat::kObj},
          {"ply", MeshOutputFormat::kPly},
          {"ply-ascii", MeshOutputFormat::kPlyAscii},
          {"gltf", MeshOutputFormat::kGltf},
          {"glb", MeshOutputFormat::kGlb},
          {"none", MeshOutputFormat::kObj}};
      bool known = false;
      for (const auto& [name, format] : kFormats)
        if (meshFormatName == name) {
          known = true;
          meshFormat = format;
        }
      check(known, "MeshFormat: '" + meshFormatName +
                       "' is not one of obj, ply, ply-ascii, gltf, glb, none");
      writeMeshes = meshFormatName != "none";
      if (!table.wasSet("OutputMeshPattern"))
        meshPattern = std::string("%04d") + meshOutputExtension(meshFormat);
      // Files named as one format and holding another could be read by no reader (each takes
      // the format from the name).
      const auto asNamed = [](MeshOutputFormat f) {
        return f == MeshOutputFormat::kPlyAscii ? MeshOutputFormat::kPly : f;
      };
      check(!writeMeshes || asNamed(meshOutputFormat(meshPattern)) == asNamed(meshFormat),
            "OutputMeshPattern '" + meshPattern + "' names " +
                meshOutputExtension(meshOutputFormat(meshPattern)) + " files, but MeshFormat " +
                meshFormatName + " writes " + meshOutputExtension(meshFormat) +
                " files: give matching ones (or either alone)");
    }
    checkOutputFramePattern(meshPattern, "OutputMeshPattern");
    if (!animationFile.empty()) {
      check(!outputDir.empty(), "AnimationFile needs an OutputDir (-o) to write it into");
      check(animationFile.size() > 4 && animationFile.substr(animationFile.size() - 4) == ".glb" &&
                animationFile.find('/') == std::string::npos,
            "AnimationFile: '" + animationFile +
                "' must be a file name ending in .glb (it is written inside OutputDir)");
    }
    std::optional<GltfAnimationWriter> animation;
    const auto start = std::chrono::steady_clock::now();

    std::unique_ptr<Md5Log> expected;
    if (!verifyPath.empty()) expected = std::make_unique<Md5Log>(verifyPath);
    std::string expectedLine;
    const bool range = table.wasSet("FirstFrame") || frameCount > 0;
    // Output folders (docs/user-guide.md): a non-empty one is refused unless --Overwrite is
    // given; the output is staged inside and put in place when the run has succeeded, so that
    // the folder then holds exactly this run's output, and a failed run leaves it as it was.
    std::vector<std::string> inputs = table.filesRead();  // the cfg files
    inputs.push_back(streamPath);
    inputs.push_back(verifyPath);
    std::optional<OutputFolder> outputs, extracted;
    if (!outputDir.empty()) outputs.emplace(outputDir, overwrite, inputs);
    const bool extractIntoOutput = outputs && insideFolder(extractDir, outputDir);
    if (!extractDir.empty() && !extractIntoOutput) {
      check(outputDir.empty() || !insideFolder(outputDir, extractDir),
            "OutputDir " + outputDir + " must not be inside ExtractTextures " + extractDir);
      extracted.emplace(extractDir, overwrite, inputs);
    }

    // Units are read from the file one at a time and every frame is written (and released) as
    // soon as it is decoded: memory does not grow with the length of the sequence.
    UnitFileReader units(streamPath, streamPath);
    const uint64_t streamBytes = units.fileSize();
    StreamDecoder decoder(units, streamPath, trace ? stderr : nullptr);
    decoder.setPictureDecoder(makeH264Decoder);
    decoder.setMaxVertexFramesPerByte(static_cast<uint64_t>(maxVertexFramesPerByte));
    decoder.setMaxTexturePixelsPerByte(static_cast<uint64_t>(maxTexturePixelsPerByte));
    decoder.setMaxMeshMemoryPerByte(static_cast<uint64_t>(maxMeshMemoryPerByte));
    if (range) decoder.setFrameRange(table.wasSet("FirstFrame") ? firstFrame : -1, frameCount);
    decoder.setThreads(
        threads > 0 ? threads : std::max(1, static_cast<int>(std::thread::hardware_concurrency())));
    uint64_t vertexFrames = 0;
    int frames = 0;         // frames output so far
    int64_t outFirst = -1;  // the stream frame of the first one
    // The input's frame number of stream frame k, and the number its files get.
    auto inputNumber = [&](int k) {
      return static_cast<int>(decoder.sequenceHeader().sh_first_frame + static_cast<uint32_t>(k));
    };
    auto outputNumber = [&](int k) {
      return renumber ? k - static_cast<int>(outFirst) : inputNumber(k);
    };
    size_t lines = 0;            // MD5 lines printed so far, compared in order with the log's
    bool rangeFiltered = false;  // the log's lines cut to the decoded range
    auto report = [&](const std::string& line) {
      std::printf("%s\n", line.c_str());
      if (verifyPath.empty()) return;
      if (range && !rangeFiltered) {
        // Compared with the log's lines of the decoded frames only.
        const SequenceHeader& sh = decoder.sequenceHeader();
        const int64_t first = table.wasSet("FirstFrame") ? firstFrame : sh.sh_first_frame;
        const int64_t end =
            frameCount > 0 ? first + frameCount : int64_t{sh.sh_first_frame} + sh.sh_frame_count;
        expected->keepFrames(first, end);
        rangeFiltered = true;
      }
      check(expected->next(expectedLine), verifyPath + ": has no line for '" + line + "'");
      check(expectedLine == line, verifyPath + ": line " + std::to_string(lines + 1) +
                                      " of its MD5 lines differs: "
                                      "expected '" +
                                      expectedLine + "', decoded '" + line + "'");
      ++lines;
    };
    // Frames decoded, on stderr when it is a terminal (the count is known once the sequence
    // header is read).
    std::optional<Progress> progress;
    std::mutex pngMutex;
    std::map<std::pair<int, int>, std::vector<uint8_t>> pngs;  // (frame, camera): to be written
    decoder.decode(
        [&](int frame, const IntMesh& mesh) {
          if (outFirst < 0) outFirst = frame;
          report(geometryHashLine(inputNumber(frame), mesh));
          if (!outputDir.empty() && (writeMeshes || !animationFile.empty())) {
            const Mesh decoded = decoder.grid().dequantise(mesh);
            // A format's limit (e.g. glTF's float positions) is named with the frame and file.
            std::string file;
            try {
              if (writeMeshes) {
                file = framePath(meshPattern, outputNumber(frame));
                outputs->write(outputDir + "/" + file, formatMeshFile(decoded, meshFormat));
              }
              if (!animationFile.empty()) {
                file = animationFile;
                if (!animation) {
                  // Too many frames for one animation file: said before any is decoded.
                  const SequenceHeader& sh = decoder.sequenceHeader();
                  const int64_t count =
                      frameCount > 0 ? frameCount
                                     : int64_t{sh.sh_first_frame} + sh.sh_frame_count - inputNumber(frame);
                  try {
                    checkGltfAnimationFrames(static_cast<uint64_t>(std::max<int64_t>(count, 0)));
                  } catch (const Error& e) {
                    throw Error(std::string("the output range has ") + e.what());
                  }
                  animation.emplace(sh.sh_frame_rate);
                }
                animation->add(decoded);
              }
            } catch (const Error& e) {
              throw Error("frame " + std::to_string(inputNumber(frame)) + " (" + file +
                          "): " + e.what());
            }
          }
          vertexFrames += mesh.positions.size();
          ++frames;
          if (!progress) {
            const uint32_t all = decoder.sequenceHeader().sh_frame_count;
            progress.emplace("3dvo-dec: frame",
                             frameCount > 0 ? static_cast<size_t>(frameCount)
                                            : static_cast<size_t>(all - outFirst));
          }
          progress->tick(static_cast<size_t>(frames));
        },
        [&](int frame, int camera, const YuvPicture& picture, const Image&) {
          report(textureHashLine(inputNumber(frame), camera, picture));
          if (outputDir.empty()) return;
          std::vector<uint8_t> png;
          {
            std::lock_guard<std::mutex> lock(pngMutex);
            const auto made = pngs.find({frame, camera});
            png = std::move(made->second);
            pngs.erase(made);
          }
          const std::string folder = outputDir + "/" + cameraFolder(camera);
          outputs->write(folder + "/" + framePath(imagePattern(meshPattern), outputNumber(frame)),
                         png.data(), png.size());
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
    if (!verifyPath.empty()) {
      size_t more = 0;
      while (expected->next(expectedLine))
        ++more;
      check(more == 0, verifyPath + ": has " + std::to_string(lines + more) +
                           " MD5 lines, the stream gives " + std::to_string(lines));
    }
    if (!outputDir.empty() && !decoder.sequenceHeader().cameras.empty())
      outputs->write(outputDir + "/" + kDatasetFileName,
                     formatDataset(decodedDataset(decoder, outputDir, meshPattern, writeMeshes,
                                                  outputNumber(static_cast<int>(outFirst)), frames),
                                   outputDir));
    // Where each GOM starts (the output's frame numbers; the starts within the output):
    // 3dvo-metrics matches vertices there (GroupStarts).
    if (!outputDir.empty()) {
      std::vector<uint32_t> starts;
      for (uint32_t start : decoder.gomStarts())
        if (start >= outFirst && start < outFirst + frames)
          starts.push_back(static_cast<uint32_t>(outputNumber(static_cast<int>(start))));
      outputs->write(outputDir + "/" + kGomStartsFileName, formatGomStarts(starts));
    }
    if (animation) outputs->write(outputDir + "/" + animationFile, animation->finish());
    if (!extractDir.empty())
      extractTextures(streamPath, streamPath, extractDir, extracted ? *extracted : *outputs);
    progress.reset();  // clears its line before the summary
    // Both folders in place, or (an Error) each as it was.
    std::vector<CommittableOutput*> folders;
    if (extracted) folders.push_back(&*extracted);
    if (outputs) folders.push_back(&*outputs);
    commitAll(folders);

    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double bits = 8.0 * streamBytes;
    const double fps = decoder.sequenceHeader().sh_frame_rate;
    std::printf("# summary\n");
    std::printf("frames              : %d\n", frames);
    if (!outputDir.empty()) std::printf("output              : %s\n", outputDir.c_str());
    std::printf("bytes               : %zu\n", static_cast<size_t>(streamBytes));
    const uint64_t textureBytes = decoder.textureBytes();
    if (range) {  // rates need the whole stream
      std::printf("range               : frames %d .. %d of the input\n",
                  inputNumber(static_cast<int>(outFirst)),
                  inputNumber(static_cast<int>(outFirst) + frames - 1));
    } else {
      std::printf("bits/vertex/frame   : %.4f (geometry and headers only)\n",
                  8.0 * (streamBytes - textureBytes) / static_cast<double>(vertexFrames));
      if (textureBytes > 0)
        std::printf("texture kbit/s      : %.3f (all cameras)\n",
                    8.0 * textureBytes / 1000.0 / (frames / fps));
      std::printf("kbit/s at %g fps    : %.3f\n", fps, bits / 1000.0 / (frames / fps));
    }
    std::printf("time                : %.3f s\n", seconds);
    if (!verifyPath.empty()) std::printf("verify              : all %d frames match\n", frames);
    return 0;
  });
}
