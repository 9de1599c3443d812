// 3dvo-enc: encodes an OBJ mesh sequence into a .3dvo stream.
#include <chrono>
#include <cmath>
#include <cstdio>

#include "common/app.h"
#include "common/file_io.h"
#include "common/md5.h"
#include "common/obj_io.h"
#include "common/progress.h"
#include "common/sequence.h"
#include "encoder/sequence_encoder.h"

using namespace tdvo;

int main(int argc, char** argv) {
  return runApp("3dvo-enc", [&]() {
    EncoderParams params;
    OptionTable table("3dvo-enc", "3dvo-enc -c cfg/FILE.cfg [-c ...] [--Key=value ...]");
    params.registerOptions(table);
    if (!table.parseCommandLine(argc, argv)) return 0;
    params.validate();
    const auto start = std::chrono::steady_clock::now();
    std::printf("# 3dvo-enc effective configuration\n%s\n", table.effectiveConfig().c_str());

    std::vector<Mesh> frames;
    std::vector<std::string> names;
    {
      Progress progress("reading frames", params.frameCount);
      for (int k = 0; k < params.frameCount; ++k) {
        names.push_back(framePath(params.inputMeshPattern, params.firstFrame + k));
        frames.push_back(readObj(names.back()));
        progress.tick(k + 1);
      }
    }

    const Grid grid = gridForSequence(frames, params.gridBits);
    StagedFiles outputs;
    EncodedSequence coded;
    {
      Progress progress("encoding frames", frames.size());
      coded = encodeSequence(params, grid, frames, names, [&](int frame, const IntMesh& recon) {
        std::printf("%s\n", geometryHashLine(frame, recon).c_str());
        if (!params.reconMeshPattern.empty())
          outputs.write(framePath(params.reconMeshPattern, frame),
                        formatObj(grid.dequantise(recon)));
        progress.tick(frame + 1);
      });
    }
    outputs.write(params.bitstreamFile, coded.stream.data(), coded.stream.size());
    outputs.commit();

    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double bits = 8.0 * coded.stream.size();
    std::printf("# summary\n");
    std::printf("frames              : %zu\n", frames.size());
    std::printf("stream              : %s\n", params.bitstreamFile.c_str());
    std::printf("bytes               : %zu (headers %llu, I meshes %llu, P meshes %llu)\n",
                coded.stream.size(), static_cast<unsigned long long>(coded.headerBytes),
                static_cast<unsigned long long>(coded.iMeshBytes),
                static_cast<unsigned long long>(coded.pMeshBytes));
    std::printf("bits/vertex/frame   : %.4f\n", bits / static_cast<double>(coded.vertexFrames));
    std::printf("kbit/s at %g fps    : %.3f\n", params.frameRate,
                bits / 1000.0 / (frames.size() / params.frameRate));
    std::printf("grid error          : RMSE %.4f, max %lld (grid units, vs the quantised input)\n",
                std::sqrt(coded.sumSquaredError / (3.0 * coded.vertexFrames)),
                static_cast<long long>(coded.maxAbsError));
    std::printf("time                : %.3f s\n", seconds);
    return 0;
  });
}
