// 3dvo-sample: writes the bundled default sample, a deforming blob mesh sequence, as OBJ frames.
#include <cstdio>

#include "common/core/app.h"
#include "common/core/config.h"
#include "common/core/file_io.h"
#include "common/core/mesh_io.h"
#include "common/core/sequence.h"
#include "common/media/media_version.h"
#include "tools/eval/sample_mesh.h"

using namespace tdvo;

int main(int argc, char** argv) {
  return runApp("3dvo-sample", [&]() {
    std::string outputDir, pattern = "%04d.obj";
    int subdivisions = 4, frameCount = 30;
    bool overwrite = false;
    OptionTable table("3dvo-sample", "3dvo-sample -o DIR [--Key=value ...]");
    table.section("Sample");
    table.add("OutputDir", outputDir, "folder for the frames", "-o");
    table.add(
        "Overwrite", overwrite,
        "replace the contents of a non-empty output folder (without it such a folder is refused)",
        "--Overwrite");
    table.add("OutputMeshPattern", pattern,
              "file name of frame n (printf pattern, n from 0); .ply, .gltf and .glb names are "
              "written in that format, others as OBJ");
    table.add("Subdivisions", subdivisions, 0, 8,
              "icosphere subdivisions (10*4^s+2 vertices, 20*4^s triangles)");
    table.add("FrameCount", frameCount, 1, 100000, "number of frames (one loop of the motion)");
    table.addVersionLines(mediaLibraryVersions());
    if (!table.parseCommandLine(argc, argv)) return 0;
    check(!outputDir.empty(), "no output folder given (-o DIR; see --help)");
    checkOutputFramePattern(pattern, "OutputMeshPattern");
    OutputFolder outputs(outputDir, overwrite, table.filesRead());
    const std::vector<Mesh> frames = deformingBlob(subdivisions, frameCount);
    for (int f = 0; f < frameCount; ++f)
      outputs.write(outputDir + "/" + framePath(pattern, f),
                    formatMeshFile(frames[f], meshOutputFormat(pattern)));
    outputs.commit();
    std::printf("3dvo-sample: wrote %d frames of %zu vertices / %zu triangles to %s/%s\n",
                frameCount, frames[0].positions.size(), frames[0].triangles.size(),
                outputDir.c_str(), pattern.c_str());
    return 0;
  });
}
