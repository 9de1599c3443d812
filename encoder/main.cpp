// 3dvo-enc: encodes an OBJ mesh sequence into a .3dvo stream.
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>

#include "bitstream/header_hash.h"
#include "common/core/app.h"
#include "common/core/file_io.h"
#include "common/core/gltf_io.h"
#include "common/core/md5.h"
#include "common/core/mesh_io.h"
#include "common/core/number_text.h"
#include "common/core/obj_io.h"
#include "common/core/progress.h"
#include "common/core/sequence.h"
#include "common/media/dataset.h"
#include "common/media/media_version.h"
#include "common/media/yuv.h"
#include "decoder/decoder_version.h"
#include "encoder/encoder.h"
#include "encoder/input_frames.h"

extern "C" {
#include <x264.h>
}

using namespace tdvo;

int main(int argc, char** argv) {
  return runApp("3dvo-enc", [&]() {
    Encoder encoder;
    OptionTable& table = encoder.options();
    table.addVersionLines(decoderVersionLines());
    table.addVersionLines(
        {std::string("x264 ") + X264_POINTVER + " (build " + std::to_string(X264_BUILD) + ")"});
    table.addVersionLines(mediaLibraryVersions());
    if (!table.parseCommandLine(argc, argv)) return 0;
    // The keys checked, with a dataset's first frame number and frame rate where FirstFrame and
    // FrameRate are not set (Encoder::params).
    EncoderParams params = encoder.params();
    params.validate();  // and the file keys
    const auto start = std::chrono::steady_clock::now();
    // One glTF file holding the whole sequence (InputMeshPattern without %d naming a .gltf or
    // .glb): its animation's keyframes are the frames 0 .. N-1, read from the file held once.
    std::optional<GltfFile> animation;
    if (!params.inputMeshPattern.empty() && isMeshAnimationFile(params.inputMeshPattern)) {
      animation.emplace(params.inputMeshPattern);
      // The frames coded: FirstFrame .. FirstFrame + FrameCount - 1 of its keyframes
      // (FrameCount not set: to the last, at most kMaxFrames).
      const int64_t frames = static_cast<int64_t>(animation->frameCount());
      check(params.firstFrame < frames,
            params.inputMeshPattern + ": FirstFrame " + std::to_string(params.firstFrame) +
                " is not a frame of the animation (its frames are 0 .. " +
                std::to_string(frames - 1) + ")");
      if (params.frameCount == 0)
        params.frameCount = static_cast<int>(
            std::min<int64_t>(frames - params.firstFrame, static_cast<int64_t>(kMaxFrames)));
      check(int64_t{params.firstFrame} + params.frameCount <= frames,
            params.inputMeshPattern + ": FirstFrame + FrameCount - 1 = " +
                std::to_string(int64_t{params.firstFrame} + params.frameCount - 1) +
                " is past the animation's last frame " + std::to_string(frames - 1));
      // FrameRate not set (and no Dataset, whose frames.rate the camera images follow): the
      // key times' rate when they are evenly spaced, which the stream then carries (and a
      // decoded animation file's key times); else the default, said. Before the effective
      // configuration, which then shows it.
      const size_t first = static_cast<size_t>(params.firstFrame);
      const size_t count = static_cast<size_t>(params.frameCount);
      if (!encoder.dataset() && !encoder.wasSet("FrameRate") && count > 1) {
        const std::optional<double> rate = animation->keyRate(first, count);
        const std::string keys = params.inputMeshPattern + ": the key times of keyframes " +
                                 std::to_string(first) + " .. " + std::to_string(first + count - 1);
        const std::string coded = ": the frames are coded one every 1/FrameRate s, FrameRate " +
                                  formatDouble(params.frameRate) + " (not set); set FrameRate";
        if (rate && *rate >= 0.001 && *rate <= 1000) {
          encoder.options().set("FrameRate", formatDouble(*rate),
                                params.inputMeshPattern + " key times");
          params.frameRate = encoder.params().frameRate;
          std::printf("# FrameRate: %s (the key times of %s)\n",
                      formatDouble(params.frameRate).c_str(), params.inputMeshPattern.c_str());
        } else if (rate) {
          warn(keys + " are evenly spaced at " + formatDouble(*rate) +
               " frames/s, outside FrameRate's range 0.001 .. 1000" + coded);
        } else {
          warn(keys + " are not evenly spaced (" + formatDouble(animation->frameTime(first)) +
               " s to " + formatDouble(animation->frameTime(first + count - 1)) + " s)" + coded);
        }
      }
    }
    std::printf("# 3dvo-enc effective configuration\n%s\n", table.effectiveConfig().c_str());

    // Input. OBJ frames, named by InputMeshPattern or by the dataset's meshes, are read frame
    // by frame, never all at once: a first pass takes the sequence's bounding box (the grid
    // needs it) and, with a dataset, the texture boxes, then the encoder reads each GOM's
    // frames when it codes that GOM, so memory is bounded by a few GOMs, not by the sequence.
    FrameSource source;
    const Dataset* input = encoder.dataset();  // the dataset, when given
    if (animation) {
      std::printf("# input frames: %d of the %zu keyframes of %s\n", params.frameCount,
                  animation->frameCount(), params.inputMeshPattern.c_str());
    }
    // FrameCount not set: every frame from FirstFrame until the first missing file.
    std::string found;
    params.frameCount = resolveFrameCount(params, input, &found);
    if (!found.empty()) std::printf("# input frames: %s\n", found.c_str());
    if (input) checkTextureFrames(params, *input, params.frameCount);
    if (input) {
      // What of the dataset the stream does not carry, said rather than dropped silently
      // (docs/bitstream.md, section 2): the decoded dataset has the decoded files instead.
      int masks = 0, backgrounds = 0;
      for (const DatasetCamera& c : input->cameras) {
        masks += !c.masks.empty() || c.alphaMask;
        backgrounds += !c.background.empty() || !c.backgroundVideo.empty();
      }
      if (masks + backgrounds > 0)
        std::printf(
            "# dataset fields not coded: masks of %d and backgrounds of %d cameras (the "
            "decoded images carry the decoded shape as alpha)\n",
            masks, backgrounds);
    }
    if (!params.gomListFile.empty()) params.goms(static_cast<size_t>(params.frameCount));
    source.count = static_cast<size_t>(params.frameCount);
    auto framePathOf = [&params, input](size_t k) {
      return inputMeshPath(params, input, params.firstFrame + static_cast<int>(k));
    };
    // A frame's name in messages: its file, or the sequence file and the keyframe.
    source.name = [&framePathOf, &animation, &params](size_t k) {
      if (!animation) return framePathOf(k);
      return framePathOf(k) + " keyframe " + std::to_string(params.firstFrame + k);
    };
    source.read = [&framePathOf, &animation, &params](size_t k) {
      if (animation) return animation->frame(static_cast<size_t>(params.firstFrame) + k);
      return readMesh(framePathOf(k));
    };
    // The input's frame number (FirstFrame + k) names the reconstruction of coded frame k.
    auto reconName = [&params](int k) {
      return framePath(params.reconMeshPattern, params.firstFrame + k);
    };

    // No output may overwrite an input, under any name (docs/robustness.md): the stream and
    // the reconstructed frames are compared with the cfg files, the GOM list, the dataset and
    // the frames to be read, by file identity, before anything is read or written.
    {
      InputFiles inputs;
      for (const std::string& cfg : table.filesRead())
        inputs.add(cfg);
      inputs.add(params.gomListFile);
      for (size_t k = 0; k < (animation ? std::min<size_t>(source.count, 1) : source.count); ++k)
        inputs.add(framePathOf(k));
      // Every frame of the input sequence, also those this run does not code (FrameCount).
      if (!params.inputMeshPattern.empty() && !animation)
        inputs.addPattern(params.inputMeshPattern, 0, INT_MAX);
      if (input) addDatasetFiles(inputs, *input);  // every file of the dataset
      inputs.checkOutput(params.bitstreamFile);
      if (!params.reconMeshPattern.empty())
        for (size_t k = 0; k < source.count; ++k)
          inputs.checkOutput(reconName(static_cast<int>(k)));
    }
    StagedFiles outputs;
    EncodedSequence coded;
    {
      // The encoder library reads the frames twice (bounding box and texture boxes, then GOM
      // by GOM) and makes the MD5 lines, printed here as they come (a GOM's frame lines, then
      // its texture lines, then the header line).
      std::optional<Progress> reading(std::in_place, "reading frames", source.count);
      std::optional<Progress> encoding;
      std::optional<Grid> grid;
      coded = encoder.encode(
          source,
          [&](int frame, const IntMesh& recon) {
            if (!encoding) {
              reading.reset();
              encoding.emplace("encoding frames", source.count);
            }
            // MD5 lines and files carry the input's frame numbers (sh_first_frame + frame).
            std::printf("%s\n", geometryHashLine(params.firstFrame + frame, recon).c_str());
            if (!params.reconMeshPattern.empty()) {
              if (!grid) grid = encoder.grid();
              outputs.write(reconName(frame),
                            formatMeshFile(grid->dequantise(recon),
                                           meshOutputFormat(params.reconMeshPattern)));
            }
            encoding->tick(frame + 1);
          },
          [&](int frame, int camera, const YuvPicture& picture, const Image&) {
            std::printf("%s\n",
                        textureHashLine(params.firstFrame + frame, camera, picture).c_str());
          },
          [&](size_t k) { reading->tick(k + 1); });
    }
    std::printf("%s\n", coded.md5Lines.back().c_str());
    outputs.write(params.bitstreamFile, coded.stream.data(), coded.stream.size());
    outputs.commit();

    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double bits = 8.0 * coded.stream.size();
    std::printf("# summary\n");
    // With the frame numbers, which a Dataset may have chosen (FirstFrame not set).
    std::printf(
        "frames              : %zu (frame numbers %lld .. %lld)\n", source.count,
        static_cast<long long>(params.firstFrame),
        static_cast<long long>(params.firstFrame) + static_cast<long long>(source.count) - 1);
    // The rate used (FrameRate, or the Dataset's), exactly.
    std::printf("frame rate          : %s\n", formatDouble(params.frameRate).c_str());
    std::printf("stream              : %s\n", params.bitstreamFile.c_str());
    if (!encoder.qualityReport().empty())
      std::printf("quality             : %s\n", encoder.qualityReport().c_str());
    std::printf("grid                : %d bits, step %.9g\n", encoder.grid().bits,
                encoder.grid().step);
    std::printf(
        "bytes               : %zu (headers %llu, I meshes %llu, vertex orders %llu, "
        "attributes %llu, P meshes %llu, textures %llu)\n",
        coded.stream.size(), static_cast<unsigned long long>(coded.headerBytes),
        static_cast<unsigned long long>(coded.iMeshBytes),
        static_cast<unsigned long long>(coded.orderBytes),
        static_cast<unsigned long long>(coded.attributeBytes),
        static_cast<unsigned long long>(coded.pMeshBytes),
        static_cast<unsigned long long>(coded.textureBytes));
    const double geometryBits = 8.0 * (coded.stream.size() - coded.textureBytes);
    if (params.pmeshMode != PMeshMode::kIntra) {
      size_t keyframes = 0;
      std::string perGom;
      for (size_t k : coded.gomKeyframes) {
        keyframes += k;
        perGom += (perGom.empty() ? "" : " ") + std::to_string(k);
      }
      // With Quality's choices: its B meshes, and the quantiser their step derives from.
      const EncoderParams& used = encoder.codedParams();
      std::string others;
      if (keyframes < source.count)
        others = used.bMeshGap > 0 && used.pmeshMode == PMeshMode::kD3dmc
                     ? "; the others are B meshes (BMeshGap " + std::to_string(used.bMeshGap) +
                           ", BMeshQuantStep " + std::to_string(used.effectiveBMeshQuantStep()) +
                           ", BMeshLambdaGrowth " + formatDouble(used.bMeshLambdaGrowth) + ")"
                     : "; the others are interpolated";
      std::printf("keyframes           : %zu of %zu frames (per GOM: %s)%s\n", keyframes,
                  source.count, perGom.c_str(), others.c_str());
    }
    std::printf("bits/vertex/frame   : %.4f (geometry and headers only)\n",
                geometryBits / static_cast<double>(coded.vertexFrames));
    if (coded.textureBytes > 0)
      std::printf("texture kbit/s      : %.3f (all cameras)\n",
                  8.0 * coded.textureBytes / 1000.0 / (source.count / params.frameRate));
    std::printf("kbit/s at %g fps    : %.3f\n", params.frameRate,
                bits / 1000.0 / (source.count / params.frameRate));
    // Even a lossless coding is lossless on the grid: quantising the input moved each coordinate
    // to the nearest grid point, which this line says, with how far that can be.
    std::printf(
        "grid error          : RMSE %.4f, max %lld (grid units, vs the quantised input; quantising "
        "moved each input coordinate by up to half a step, %.9g)\n",
        std::sqrt(coded.sumSquaredError / (3.0 * coded.vertexFrames)),
        static_cast<long long>(coded.maxAbsError), encoder.grid().step / 2);
    std::printf("time                : %.3f s\n", seconds);
    return 0;
  });
}
