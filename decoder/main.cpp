// 3dvo-dec: decodes a .3dvo stream to OBJ frames and prints per-frame MD5 lines.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "common/app.h"
#include "common/config.h"
#include "common/file_io.h"
#include "common/md5.h"
#include "common/obj_io.h"
#include "common/sequence.h"
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

}  // namespace

int main(int argc, char** argv) {
  return runApp("3dvo-dec", [&]() {
    std::string streamPath, outputDir, meshPattern = "%04d.obj", verifyPath;
    bool trace = false;
    OptionTable table("3dvo-dec", "3dvo-dec -i STREAM.3dvo [-o OUTDIR] [--verify MD5LOG]");
    table.section("Decoder");
    table.add("BitstreamFile", streamPath, "the .3dvo stream to decode", "-i");
    table.add("OutputDir", outputDir, "folder for the decoded frames (none: hashes only)", "-o");
    table.add("OutputMeshPattern", meshPattern,
              "file name of decoded frame n inside OutputDir (printf pattern, n from 0)");
    table.add("VerifyMd5", verifyPath,
              "compare the decoded MD5 lines with this log's; exit 1 on any difference",
              "--verify");
    table.add("Trace", trace, "print every syntax element read to stderr", "--trace");
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

    const std::vector<uint8_t> stream = readFileBytes(streamPath);
    StreamDecoder decoder(stream.data(), stream.size(), streamPath, trace ? stderr : nullptr);
    StagedFiles outputs;
    uint64_t vertexFrames = 0;
    int frames = 0;
    decoder.decode([&](int frame, const IntMesh& mesh) {
      const std::string line = geometryHashLine(frame, mesh);
      std::printf("%s\n", line.c_str());
      if (!verifyPath.empty()) {
        check(static_cast<size_t>(frame) < expected.size(),
              verifyPath + ": has no line for frame " + std::to_string(frame));
        check(expected[frame] == line, verifyPath + ": frame " + std::to_string(frame) +
                                           " differs: expected '" + expected[frame] + "'");
      }
      if (!outputDir.empty())
        outputs.write(outputDir + "/" + framePath(meshPattern, frame),
                      formatObj(decoder.grid().dequantise(mesh)));
      vertexFrames += mesh.positions.size();
      frames = frame + 1;
    });
    if (!verifyPath.empty())
      check(expected.size() == static_cast<size_t>(frames),
            verifyPath + ": has " + std::to_string(expected.size()) + " MD5 lines, decoded " +
                std::to_string(frames) + " frames");
    outputs.commit();
    createdFolder.keep = true;

    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double bits = 8.0 * stream.size();
    const double fps = decoder.sequenceHeader().sh_frame_rate;
    std::printf("# summary\n");
    std::printf("frames              : %d\n", frames);
    if (!outputDir.empty()) std::printf("output              : %s\n", outputDir.c_str());
    std::printf("bytes               : %zu\n", stream.size());
    std::printf("bits/vertex/frame   : %.4f\n", bits / static_cast<double>(vertexFrames));
    std::printf("kbit/s at %g fps    : %.3f\n", fps, bits / 1000.0 / (frames / fps));
    std::printf("time                : %.3f s\n", seconds);
    if (!verifyPath.empty()) std::printf("verify              : all %d frames match\n", frames);
    return 0;
  });
}
