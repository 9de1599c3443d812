#include "tools/render/player_export.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/progress.h"
#include "common/media/png_io.h"
#include "tools/render/camera_path.h"

namespace tdvo {

namespace fs = std::filesystem;

namespace {

void appendU32(std::vector<uint8_t>& out, uint32_t v) {
  for (int i = 0; i < 4; ++i)
    out.push_back(static_cast<uint8_t>(v >> (8 * i)));
}

void appendF32(std::vector<uint8_t>& out, float f) {
  uint32_t v;
  std::memcpy(&v, &f, 4);
  appendU32(out, v);
}

std::vector<uint8_t> meshBytes(const Mesh& m) {
  std::vector<uint8_t> out;
  out.reserve(8 + 12 * (m.positions.size() + m.triangles.size()));
  appendU32(out, static_cast<uint32_t>(m.positions.size()));
  appendU32(out, static_cast<uint32_t>(m.triangles.size()));
  for (const Vec3d& p : m.positions)
    for (double c : p)
      appendF32(out, static_cast<float>(c));
  for (const Triangle& t : m.triangles)
    for (uint32_t v : t)
      appendU32(out, v);
  return out;
}

const char* directionName(ViewDirection d) {
  return d == ViewDirection::ray ? "ray" : "axis";
}

}  // namespace

void exportPlayerData(const Dataset& d, const PlayerExportParams& p) {
  check(!p.output.empty(), "no output folder given (-o DIR)");
  check(!p.frames.empty(), "no frames to export");
  check(!d.meshes.empty(), "the dataset has no meshes; the player needs them");
  const size_t n = d.cameras.size();
  int cellWidth = 0, cellHeight = 0;
  for (const DatasetCamera& c : d.cameras)
    cellWidth = std::max(cellWidth, c.camera.width),
    cellHeight = std::max(cellHeight, c.camera.height);
  const int columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  const int rows =
      static_cast<int>((n + static_cast<size_t>(columns) - 1) / static_cast<size_t>(columns));
  const int64_t atlasWidth = int64_t(columns) * cellWidth, atlasHeight = int64_t(rows) * cellHeight;
  check(atlasWidth <= kMaxAtlasSide && atlasHeight <= kMaxAtlasSide,
        "the texture atlas would be " + std::to_string(atlasWidth) + "x" +
            std::to_string(atlasHeight) + " pixels, more than " + std::to_string(kMaxAtlasSide) +
            " on a side; export fewer cameras (Cameras, CameraStep)");

  nlohmann::ordered_json scene;
  scene["format"] = "3dvo-player";
  scene["version"] = 1;
  scene["description"] = d.description;
  scene["frames"] = {{"count", p.frames.size()}, {"rate", d.frameRate}};
  std::vector<int> starts = p.gomStarts;
  if (starts.empty())
    for (size_t i = 0; i < p.frames.size(); ++i)
      starts.push_back(static_cast<int>(i));
  scene["gomStarts"] = starts;
  scene["meshes"] = "meshes/%04d.bin";
  scene["textures"] = "textures/%04d.png";
  scene["atlas"] = {{"width", atlasWidth},
                    {"height", atlasHeight},
                    {"columns", columns},
                    {"cellWidth", cellWidth},
                    {"cellHeight", cellHeight}};
  scene["weights"] = {{"direction", directionName(p.options.direction)},
                      {"sharpness", p.options.sharpness},
                      {"depthTolerance", p.options.depthTolerance},
                      {"fallbackColour", p.options.fallbackColour},
                      {"background", p.options.background}};
  const Vec3d up = datasetUp(d);
  scene["up"] = up;

  OutputFolder files(p.output, p.overwrite, p.inputs);
  std::vector<CameraFrames> frames;
  for (size_t i = 0; i < n; ++i)
    frames.emplace_back(d, i);
  Vec3d centre{0, 0, 0};
  double radius = 0;
  Progress progress("3dvo-render: exporting", p.frames.size());
  for (size_t k = 0; k < p.frames.size(); ++k) {
    const int f = p.frames[k];
    const Mesh mesh = readDatasetMesh(d, f);
    if (k == 0) centre = boundingBoxCentre(mesh);
    for (const Vec3d& v : mesh.positions)
      radius = std::max(radius, norm(v - centre));
    char name[32];
    std::snprintf(name, sizeof name, "%04d", static_cast<int>(k));
    const std::vector<uint8_t> bin = meshBytes(mesh);
    files.write((fs::path(p.output) / "meshes" / (std::string(name) + ".bin")).string(), bin.data(),
                bin.size());
    Image atlas(static_cast<int>(atlasWidth), static_cast<int>(atlasHeight), 4, 0);
    for (size_t i = 0; i < n; ++i) {
      const Image image = convertChannels(frames[i].frame(f), 3);
      const Image mask = frames[i].hasMasks() ? frames[i].mask(f) : Image();
      const int ox = static_cast<int>(i % static_cast<size_t>(columns)) * cellWidth;
      const int oy = static_cast<int>(i / static_cast<size_t>(columns)) * cellHeight;
      for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
          for (int c = 0; c < 3; ++c)
            atlas.at(ox + x, oy + y, c) = image.at(x, y, c);
          atlas.at(ox + x, oy + y, 3) = mask.empty() ? 255 : mask.at(x, y);
        }
    }
    const std::vector<uint8_t> png = encodePng(atlas);
    files.write((fs::path(p.output) / "textures" / (std::string(name) + ".png")).string(),
                png.data(), png.size());
    progress.tick(k + 1);
  }
  scene["centre"] = centre;
  scene["radius"] = radius;

  nlohmann::ordered_json cameras = nlohmann::ordered_json::array();
  for (size_t i = 0; i < n; ++i) {
    const Camera& c = d.cameras[i].camera;
    const Distortion& k = c.distortion;
    cameras.push_back(
        {{"name", c.name},
         {"width", c.width},
         {"height", c.height},
         {"fx", c.fx},
         {"fy", c.fy},
         {"cx", c.cx},
         {"cy", c.cy},
         {"distortion", {k.k1, k.k2, k.p1, k.p2, k.k3}},
         {"R", c.R},
         {"t", c.t},
         {"atlasX", static_cast<int>(i % static_cast<size_t>(columns)) * cellWidth},
         {"atlasY", static_cast<int>(i / static_cast<size_t>(columns)) * cellHeight}});
  }
  scene["cameras"] = cameras;
  files.write((fs::path(p.output) / "scene.json").string(), scene.dump(1) + "\n");
  files.commit();
}

}  // namespace tdvo
