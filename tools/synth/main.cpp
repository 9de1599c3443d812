// 3dvo-synth: renders a mesh sequence (by default a built-in deforming blob) into a ring or dome
// of calibrated cameras and writes a dataset with exact masks and ground-truth meshes.
//
//   3dvo-synth -o DIR                                  8 cameras, 320x240, 10 blob frames
//   3dvo-synth -o DIR --InputMeshPattern=samba/mesh_%04d.obj.gz --Cameras=12 --Layout=dome
#include <cstdio>

#include "common/core/app.h"
#include "common/core/config.h"
#include "common/media/media_version.h"
#include "tools/multiview/synth_rig.h"

int main(int argc, char** argv) {
  return tdvo::runApp("3dvo-synth", [&]() {
    tdvo::SynthParams params;
    tdvo::OptionTable table("3dvo-synth", "3dvo-synth -o DIR [-c rig.cfg] [--Key=value ...]");
    tdvo::addSynthOptions(table, params);
    table.addVersionLines(tdvo::mediaLibraryVersions());
    if (!table.parseCommandLine(argc, argv)) return 0;
    tdvo::check(!params.output.empty(), "no output folder given (-o DIR); see --help");
    const tdvo::Dataset d = tdvo::writeSyntheticDataset(params);
    std::printf("3dvo-synth: wrote %zu cameras x %d frames (%dx%d) to %s\n", d.cameras.size(),
                d.frameCount, params.width, params.height, params.output.c_str());
    return 0;
  });
}
