// 3dvo-recon: multi-camera images or video to a time-consistent mesh sequence in GOMs, the
// content-creation side of 3DVO (docs/reconstruction.md).
//
//   3dvo-recon -c cfg/recon/dino.cfg
//   3dvo-recon -i DATASET -o OUT [--OctreeDepth=8] [--Key=value ...]
//   3dvo-recon --InputMeshPattern=seq/%04d.obj --FrameCount=10 -o OUT   (tracking only)
#include <cstdio>

#include "common/core/app.h"
#include "common/core/config.h"
#include "common/media/media_version.h"
#include "tools/recon/recon_pipeline.h"

int main(int argc, char** argv) {
  return tdvo::runApp("3dvo-recon", [&]() {
    tdvo::ReconParams params;
    tdvo::OptionTable table("3dvo-recon",
                            "3dvo-recon [-c recon.cfg] -i INPUT -o DIR [--Key=value ...]");
    tdvo::addReconOptions(table, params);
    table.addVersionLines(tdvo::mediaLibraryVersions());
    if (!table.parseCommandLine(argc, argv)) return 0;
    tdvo::checkReconParams(params);
    params.cfgFiles = table.filesRead();
    std::printf("# 3dvo-recon effective configuration\n%s", table.effectiveConfig().c_str());
    std::fflush(stdout);
    tdvo::runReconstruction(params, stdout);
    return 0;
  });
}
