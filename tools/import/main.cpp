// 3dvo-import: turns a published multi-view calibration (Middlebury *_par.txt, OpenCV XML per
// camera, NeRF transforms.json) into the 3DVO dataset layout: OUT/dataset.json referring to the
// original images and videos (relative paths), checked before it is written.
//
//   3dvo-import -i ../shared/data/multiview/middlebury-dinoSparseRing -o dino
//   3dvo-import -i ../shared/data/multiview/uu-4cam -o uu --Up=0,0,-1
#include <cstdio>

#include "common/core/app.h"
#include "common/core/config.h"
#include "common/core/file_io.h"
#include "common/media/dataset.h"
#include "common/media/media_version.h"
#include "tools/multiview/importers.h"

int main(int argc, char** argv) {
  return tdvo::runApp("3dvo-import", [&]() {
    std::string input, output;
    bool validate = true;
    tdvo::ImportOptions options;
    tdvo::OptionTable table("3dvo-import", "3dvo-import -i INPUT -o DIR [--Key=value ...]");
    table.section("Input and output");
    table.add("Input", input,
              "calibration file or folder (*_par.txt, transforms*.json, OpenCV *.xml per camera "
              "folder, or an existing dataset.json)",
              "-i");
    table.add("Output", output, "dataset folder to write (dataset.json)", "-o");
    table.addEnum("Format", options.format,
                  {{"auto", tdvo::ImportFormat::automatic},
                   {"dataset", tdvo::ImportFormat::dataset},
                   {"middlebury", tdvo::ImportFormat::middlebury},
                   {"opencv", tdvo::ImportFormat::opencv},
                   {"nerf", tdvo::ImportFormat::nerf}},
                  "input format");
    table.add("Validate", validate,
              "check every referenced image/video/mesh before writing (sizes, frame counts)");
    table.section("OpenCV camera folders");
    table.add("Video", options.video, "video file name beside each calibration file");
    table.add("BackgroundVideo", options.backgroundVideo,
              "background video file name beside each calibration file (used when present)");
    table.add("Images", options.images,
              "image sequence pattern beside each calibration file (e.g. %04d.png), instead of "
              "a video");
    table.section("World");
    table.add("Up", options.up, "the world's up direction x,y,z (empty: unknown)");
    table.addVersionLines(tdvo::mediaLibraryVersions());
    if (!table.parseCommandLine(argc, argv)) return 0;
    tdvo::check(!input.empty(), "no input given (-i INPUT); see --help");
    tdvo::check(!output.empty(), "no output folder given (-o DIR); see --help");
    // The dataset.json written must not be the input (e.g. -i DIR -o DIR on a dataset folder).
    {
      tdvo::InputFiles inputs;
      for (const std::string& cfg : table.filesRead())
        inputs.add(cfg);
      inputs.add(input);
      inputs.add(input + "/" + tdvo::kDatasetFileName);
      inputs.checkOutput(output + "/" + tdvo::kDatasetFileName);
    }
    const tdvo::Dataset d = tdvo::importAny(input, options);
    if (validate) tdvo::validateDatasetFiles(d);
    tdvo::writeDataset(d, output);
    std::printf("3dvo-import: %zu cameras, %d frames -> %s/%s\n", d.cameras.size(), d.frameCount,
                output.c_str(), tdvo::kDatasetFileName);
    return 0;
  });
}
