// 3dvo-enc: encodes an OBJ mesh sequence into a .3dvo stream.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>

#include "bitstream/header_hash.h"
#include "common/app.h"
#include "common/dataset.h"
#include "common/file_io.h"
#include "common/md5.h"
#include "common/obj_io.h"
#include "common/progress.h"
#include "common/sequence.h"
#include "common/yuv.h"
#include "decoder/decoder_version.h"
#include "encoder/sequence_encoder.h"
#include "encoder/texture_encoder.h"

extern "C" {
#include <x264.h>
}

using namespace tdvo;

int main(int argc, char** argv) {
  return runApp("3dvo-enc", [&]() {
    EncoderParams params;
    OptionTable table("3dvo-enc", "3dvo-enc -c cfg/FILE.cfg [-c ...] [--Key=value ...]");
    params.registerOptions(table);
    table.addVersionLines(decoderVersionLines());
    table.addVersionLines(
        {std::string("x264 ") + X264_POINTVER + " (build " + std::to_string(X264_BUILD) + ")"});
    if (!table.parseCommandLine(argc, argv)) return 0;
    params.validate();
    const auto start = std::chrono::steady_clock::now();
    std::printf("# 3dvo-enc effective configuration\n%s\n", table.effectiveConfig().c_str());

    // Input. OBJ frames, named by InputMeshPattern or by the dataset's meshes, are read frame
    // by frame, never all at once: a first pass takes the sequence's bounding box (the grid
    // needs it) and, with a dataset, the texture boxes, then the encoder reads each GOM's
    // frames when it codes that GOM, so memory is bounded by a few GOMs, not by the sequence.
    FrameSource source;
    Dataset dataset;
    if (!params.dataset.empty()) dataset = readDataset(params.dataset);
    source.count = static_cast<size_t>(params.frameCount);
    if (!params.inputMeshPattern.empty()) {
      source.name = [&params](size_t k) {
        return framePath(params.inputMeshPattern, params.firstFrame + static_cast<int>(k));
      };
    } else {
      checkDatasetMeshes(dataset, params.firstFrame, params.frameCount);
      source.name = [&params, &dataset](size_t k) {
        return dataset.framePath(dataset.meshes, params.firstFrame + static_cast<int>(k));
      };
    }
    source.read = [&source](size_t k) { return readObj(source.name(k)); };
    std::optional<TextureBoxFinder> boxes;
    if (!params.dataset.empty()) boxes.emplace(params, dataset, source.count);

    Grid grid;
    {
      Progress progress("reading frames", source.count);
      grid = gridForSequence(
          source, params.gridBits, params.threadCount(), [&](size_t k) { progress.tick(k + 1); },
          boxes ? [&](size_t, const Mesh& mesh) { boxes->add(mesh); }
                : std::function<void(size_t, const Mesh&)>());
    }
    std::unique_ptr<TextureEncoder> textures;
    if (boxes) textures = std::make_unique<TextureEncoder>(params, dataset, boxes->boxes());
    StagedFiles outputs;
    EncodedSequence coded;
    {
      Progress progress("encoding frames", source.count);
      coded = encodeSequence(
          params, grid, source,
          [&](int frame, const IntMesh& recon) {
            std::printf("%s\n", geometryHashLine(frame, recon).c_str());
            if (!params.reconMeshPattern.empty())
              outputs.write(framePath(params.reconMeshPattern, frame),
                            formatObj(grid.dequantise(recon)));
            progress.tick(frame + 1);
          },
          textures.get(),
          [&](int frame, int camera, const YuvPicture& picture, const Image&) {
            std::printf("%s\n", textureHashLine(frame, camera, picture).c_str());
          });
    }
    std::printf("%s\n", sequenceHeaderHashLine(coded.stream, params.bitstreamFile).c_str());
    outputs.write(params.bitstreamFile, coded.stream.data(), coded.stream.size());
    outputs.commit();

    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double bits = 8.0 * coded.stream.size();
    std::printf("# summary\n");
    std::printf("frames              : %zu\n", source.count);
    std::printf("stream              : %s\n", params.bitstreamFile.c_str());
    std::printf(
        "bytes               : %zu (headers %llu, I meshes %llu, P meshes %llu, "
        "textures %llu)\n",
        coded.stream.size(), static_cast<unsigned long long>(coded.headerBytes),
        static_cast<unsigned long long>(coded.iMeshBytes),
        static_cast<unsigned long long>(coded.pMeshBytes),
        static_cast<unsigned long long>(coded.textureBytes));
    const double geometryBits = 8.0 * (coded.stream.size() - coded.textureBytes);
    std::printf("bits/vertex/frame   : %.4f (geometry and headers only)\n",
                geometryBits / static_cast<double>(coded.vertexFrames));
    if (coded.textureBytes > 0)
      std::printf("texture kbit/s      : %.3f (all cameras)\n",
                  8.0 * coded.textureBytes / 1000.0 / (source.count / params.frameRate));
    std::printf("kbit/s at %g fps    : %.3f\n", params.frameRate,
                bits / 1000.0 / (source.count / params.frameRate));
    std::printf("grid error          : RMSE %.4f, max %lld (grid units, vs the quantised input)\n",
                std::sqrt(coded.sumSquaredError / (3.0 * coded.vertexFrames)),
                static_cast<long long>(coded.maxAbsError));
    std::printf("time                : %.3f s\n", seconds);
    return 0;
  });
}
