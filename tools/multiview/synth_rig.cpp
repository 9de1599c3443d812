#include "tools/multiview/synth_rig.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <random>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/mesh_io.h"
#include "common/core/obj_io.h"
#include "common/core/progress.h"
#include "common/core/sequence.h"
#include "common/media/png_io.h"
#include "common/views/image.h"
#include "common/views/rasteriser.h"
#include "tools/eval/sample_mesh.h"
#include "tools/multiview/importers.h"

namespace tdvo {

namespace fs = std::filesystem;

void addSynthOptions(OptionTable& table, SynthParams& p) {
  table.section("Output");
  table.add("Output", p.output, "dataset folder to write", "-o");
  table.add(
      "Overwrite", p.overwrite,
      "replace the contents of a non-empty output folder (without it such a folder is refused)",
      "--Overwrite");
  table.section("Content");
  table.add("InputMeshPattern", p.inputMeshPattern,
            "mesh sequence: OBJ, PLY or glTF frames (e.g. samba/mesh_%04d.obj.gz, constant "
            "connectivity); empty: the built-in deforming blob");
  table.add("FirstFrame", p.firstFrame, 0, 1 << 30, "number of the first input mesh");
  table.add("FrameCount", p.frameCount, 1, 100000, "frames to render");
  table.add("BlobSubdivisions", p.blobSubdivisions, 0, 7,
            "built-in blob: icosphere subdivision level");
  table.section("Rig");
  table.add("Cameras", p.cameras, 1, 1000, "number of cameras");
  table.addEnum("Layout", p.layout, {{"ring", RigLayout::ring}, {"dome", RigLayout::dome}},
                "camera placement: a ring at one elevation, or a dome (spiral over the upper "
                "hemisphere, 5 to 75 degrees)");
  table.add("Width", p.width, 16, 8192, "image width in pixels");
  table.add("Height", p.height, 16, 8192, "image height in pixels");
  table.add("FieldOfView", p.fieldOfView, 5, 150, "horizontal field of view, degrees");
  table.add("FocalLength", p.focalLength, 0, 1e6, "focal length in pixels (0: from FieldOfView)");
  table.add("Elevation", p.elevation, -89, 89, "ring elevation above the object's centre, degrees");
  table.add("Distance", p.distance, 0, 1e9,
            "camera distance to the object's centre (0: fit the object in every view)");
  table.add("Up", p.up, "the world's up direction x,y,z");
  table.section("Appearance");
  table.add("BackgroundColour", p.backgroundColour, "background colour r,g,b (0..255)");
  table.add("BackgroundImage", p.backgroundImage,
            "background PNG, scaled to the image size (replaces BackgroundColour)");
  table.add("NoiseSigma", p.noiseSigma, 0, 100, "camera noise standard deviation, grey levels");
  table.add("Seed", p.seed, 0, 2147483647, "noise seed");
}

namespace {

constexpr double kPi = 3.14159265358979323846;

// Two unit vectors that complete `up` to an orthonormal basis (fixed choice for a given up).
void basisAround(const Vec3d& up, Vec3d& a, Vec3d& b) {
  const Vec3d helper = std::fabs(up[2]) < 0.9 ? Vec3d{0, 0, 1} : Vec3d{1, 0, 0};
  a = normalized(cross(helper, up));
  b = cross(up, a);
}

double focalPixels(const SynthParams& p) {
  return p.focalLength > 0 ? p.focalLength
                           : 0.5 * p.width / std::tan(0.5 * p.fieldOfView * kPi / 180);
}

std::array<uint8_t, 3> parseColour(const std::string& text) {
  std::array<uint8_t, 3> c{};
  int values[3];
  char tail = 0;
  check(std::sscanf(text.c_str(), "%d,%d,%d%c", &values[0], &values[1], &values[2], &tail) == 3,
        "BackgroundColour: '" + text + "' is not r,g,b");
  for (int i = 0; i < 3; ++i) {
    check(values[i] >= 0 && values[i] <= 255,
          "BackgroundColour: '" + text + "': components must be in 0..255");
    c[static_cast<size_t>(i)] = static_cast<uint8_t>(values[i]);
  }
  return c;
}

// Scales an RGB image to width × height by bilinear sampling (pixel centres aligned).
Image scaleImage(const Image& in, int width, int height) {
  if (in.width == width && in.height == height) return in;
  Image out(width, height, 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double sx = std::clamp((x + 0.5) * in.width / width - 0.5, 0.0, in.width - 1.0);
      const double sy = std::clamp((y + 0.5) * in.height / height - 0.5, 0.0, in.height - 1.0);
      const int x0 = static_cast<int>(sx), y0 = static_cast<int>(sy);
      const int x1 = std::min(x0 + 1, in.width - 1), y1 = std::min(y0 + 1, in.height - 1);
      const double ax = sx - x0, ay = sy - y0;
      for (int c = 0; c < 3; ++c) {
        const double v = (1 - ay) * ((1 - ax) * in.at(x0, y0, c) + ax * in.at(x1, y0, c)) +
                         ay * ((1 - ax) * in.at(x0, y1, c) + ax * in.at(x1, y1, c));
        out.at(x, y, c) = static_cast<uint8_t>(std::lround(v));
      }
    }
  return out;
}

// Area-weighted vertex normals (not normalised; the renderer normalises per pixel).
std::vector<Vec3d> vertexNormals(const Mesh& m) {
  std::vector<Vec3d> n(m.positions.size(), Vec3d{0, 0, 0});
  for (const Triangle& t : m.triangles) {
    const Vec3d f =
        cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
    for (uint32_t v : t)
      n[v] = n[v] + f;
  }
  return n;
}

// The surface texture: smooth colour bands times a 3D checkerboard, a function of the point's
// position in the first frame (so it stays attached to the surface as the mesh moves).
// `u` is that position relative to the first frame's bounding sphere.
Vec3d albedo(const Vec3d& u) {
  const Vec3d base = {0.55 + 0.35 * std::sin(3.1 * u[0] + 1.0),
                      0.55 + 0.35 * std::sin(2.3 * u[1] + 2.0),
                      0.55 + 0.35 * std::sin(2.7 * u[2] + 3.0)};
  const long cells = static_cast<long>(std::floor(4 * u[0])) +
                     static_cast<long>(std::floor(4 * u[1])) +
                     static_cast<long>(std::floor(4 * u[2]));
  return (cells & 1) ? 0.6 * base : base;
}

// Approximately Gaussian noise with a fixed, platform-independent generator: the Irwin–Hall sum
// of four uniform samples, scaled to unit variance.
class Noise {
 public:
  explicit Noise(uint64_t seed) : engine_(seed) {}
  double next() {
    double sum = 0;
    for (int i = 0; i < 4; ++i)
      sum += static_cast<double>(engine_() >> 11) * 0x1.0p-53;
    return (sum - 2.0) * std::sqrt(3.0);
  }

 private:
  std::mt19937_64 engine_;
};

struct Content {
  std::vector<Mesh> frames;
  Vec3d centre{0, 0, 0};     // of the first frame's bounding box
  double radius = 0;         // bounding sphere over all frames, around `centre`
  double textureRadius = 0;  // first frame only: scales the texture
  std::string description;
};

Content loadContent(const SynthParams& p) {
  Content c;
  if (p.inputMeshPattern.empty()) {
    c.frames = deformingBlob(p.blobSubdivisions, p.frameCount);
    c.description =
        "3dvo-synth: built-in deforming blob, " + std::to_string(p.frameCount) + " frames";
  } else {
    checkFramePattern(p.inputMeshPattern, "InputMeshPattern");
    for (int f = 0; f < p.frameCount; ++f) {
      const std::string path = framePath(p.inputMeshPattern, p.firstFrame + f);
      c.frames.push_back(readMesh(path));
      const Mesh& first = c.frames.front();
      check(c.frames.back().positions.size() == first.positions.size() &&
                c.frames.back().triangles == first.triangles,
            path +
                ": connectivity differs from the first frame; the rig's surface texture "
                "needs a time-consistent sequence");
    }
    c.description = "3dvo-synth: " + p.inputMeshPattern + " from frame " +
                    std::to_string(p.firstFrame) + ", " + std::to_string(p.frameCount) + " frames";
  }
  const Mesh& first = c.frames.front();
  const double inf = std::numeric_limits<double>::infinity();
  Vec3d lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  for (const Vec3d& v : first.positions)
    for (int i = 0; i < 3; ++i)
      lo[i] = std::min(lo[i], v[i]), hi[i] = std::max(hi[i], v[i]);
  c.centre = 0.5 * (lo + hi);
  for (const Vec3d& v : first.positions)
    c.textureRadius = std::max(c.textureRadius, norm(v - c.centre));
  for (const Mesh& m : c.frames)
    for (const Vec3d& v : m.positions)
      c.radius = std::max(c.radius, norm(v - c.centre));
  check(c.radius > 0, "the input mesh has no extent");
  return c;
}

uint8_t toByte(double v) {
  return static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
}

}  // namespace

std::vector<Camera> makeRigCameras(const SynthParams& p, const Vec3d& centre, double radius) {
  const Vec3d up = normalized(parseDirection(p.up, "Up"));
  Vec3d a, b;
  basisAround(up, a, b);
  const double f = focalPixels(p);
  // Fit the bounding sphere into the narrower half field of view with a 10% margin.
  const double halfAngle = std::atan(0.5 * std::min(p.width, p.height) / f);
  const double distance = p.distance > 0 ? p.distance : 1.1 * radius / std::sin(halfAngle);
  check(distance > radius, "Distance: the cameras would be inside the object");
  std::vector<Camera> cameras;
  for (int k = 0; k < p.cameras; ++k) {
    double azimuth, elevation;
    if (p.layout == RigLayout::ring) {
      azimuth = 2 * kPi * k / p.cameras;
      elevation = p.elevation * kPi / 180;
    } else {
      // Equal-area spiral: heights evenly spaced between sin 5° and sin 75°, golden-angle turns.
      const double lo = std::sin(5 * kPi / 180), hi = std::sin(75 * kPi / 180);
      elevation = std::asin(lo + (hi - lo) * (k + 0.5) / p.cameras);
      azimuth = k * kPi * (3 - std::sqrt(5.0));
    }
    const Vec3d direction = std::cos(elevation) * (std::cos(azimuth) * a + std::sin(azimuth) * b) +
                            std::sin(elevation) * up;
    Camera c;
    char name[32];
    std::snprintf(name, sizeof name, "cam%02d", k);
    c.name = name;
    c.width = p.width;
    c.height = p.height;
    c.fx = c.fy = f;
    c.cx = 0.5 * (p.width - 1);  // the image centre in pixel-centre coordinates
    c.cy = 0.5 * (p.height - 1);
    lookAt(c, centre + distance * direction, centre, up);
    cameras.push_back(c);
  }
  return cameras;
}

Dataset writeSyntheticDataset(const SynthParams& p) {
  check(!p.output.empty(), "no output folder given (-o DIR)");
  const Content content = loadContent(p);
  const std::vector<Camera> cameras = makeRigCameras(p, content.centre, content.radius);
  const Vec3d up = normalized(parseDirection(p.up, "Up"));
  Vec3d a, b;
  basisAround(up, a, b);
  const Vec3d light = normalized(up + 0.6 * a + 0.3 * b);

  Image background;
  if (!p.backgroundImage.empty()) {
    background = scaleImage(convertChannels(readPng(p.backgroundImage), 3), p.width, p.height);
  } else {
    const std::array<uint8_t, 3> colour = parseColour(p.backgroundColour);
    background = Image(p.width, p.height, 3);
    for (size_t i = 0; i < background.pixels.size(); ++i)
      background.pixels[i] = colour[i % 3];
  }

  Dataset d;
  d.folder = p.output;
  d.description = content.description;
  d.firstFrame = 0;
  d.frameCount = p.frameCount;
  d.frameRate = 25;
  d.up = up;
  d.meshes = "meshes/%04d.obj";
  for (const Camera& c : cameras) {
    DatasetCamera dc;
    dc.camera = c;
    const std::string folder = escapePercent(c.name);  // the name, as a dataset path's text
    dc.images = folder + "/%04d.png";
    dc.masks = folder + "/mask_%04d.png";
    dc.background = folder + "/background.png";
    d.cameras.push_back(dc);
  }

  // Every input frame (a file this run reads inside the folder would also stop the commit, but
  // only after the work).
  std::vector<std::string> inputs = {p.backgroundImage};
  if (!p.inputMeshPattern.empty())
    for (int k = 0; k < p.frameCount; ++k)
      inputs.push_back(framePath(p.inputMeshPattern, p.firstFrame + k));
  OutputFolder files(p.output, p.overwrite, inputs);
  auto stagePng = [&](const std::string& path, const Image& image) {
    const std::vector<uint8_t> bytes = encodePng(image);
    files.write(path, bytes.data(), bytes.size());
  };
  for (const DatasetCamera& dc : d.cameras)
    stagePng(d.framePath(dc.background, 0), background);

  const Mesh& first = content.frames.front();
  std::vector<Vec3d> texturePosition(first.positions.size());
  for (size_t i = 0; i < first.positions.size(); ++i)
    texturePosition[i] = (1.0 / content.textureRadius) * (first.positions[i] - content.centre);

  Progress progress("3dvo-synth: rendering", static_cast<size_t>(p.frameCount) * cameras.size());
  size_t done = 0;
  for (int f = 0; f < p.frameCount; ++f) {
    const Mesh& mesh = content.frames[static_cast<size_t>(f)];
    files.write(d.framePath(d.meshes, f), formatObj(mesh));
    const std::vector<Vec3d> normals = vertexNormals(mesh);
    for (size_t k = 0; k < cameras.size(); ++k) {
      const Camera& camera = cameras[k];
      const Fragments fragments = rasterise(mesh, camera);
      Image image = background;
      const Vec3d eye = camera.centre();
      for (int y = 0; y < camera.height; ++y)
        for (int x = 0; x < camera.width; ++x) {
          if (fragments.triangle[fragments.index(x, y)] < 0) continue;
          const Vec3d u = interpolate(fragments, mesh, texturePosition, x, y);
          const Vec3d surface = interpolate(fragments, mesh, mesh.positions, x, y);
          Vec3d n = interpolate(fragments, mesh, normals, x, y);
          const double length = norm(n);
          n = length > 0 ? (1.0 / length) * n : Vec3d{0, 0, 0};
          if (dot(n, eye - surface) < 0) n = -1.0 * n;  // light the side the camera sees
          const double shade = 0.35 + 0.65 * std::max(0.0, dot(n, light));
          const Vec3d colour = (255 * shade) * albedo(u);
          for (int c = 0; c < 3; ++c)
            image.at(x, y, c) = toByte(colour[static_cast<size_t>(c)]);
        }
      if (p.noiseSigma > 0) {
        // One generator per image, seeded from (Seed, camera, frame): images do not depend on
        // the order in which they are made.
        Noise noise(static_cast<uint64_t>(p.seed) * 1000003u * 1000003u +
                    static_cast<uint64_t>(k) * 1000003u + static_cast<uint64_t>(f));
        for (uint8_t& v : image.pixels)
          v = toByte(v + p.noiseSigma * noise.next());
      }
      const DatasetCamera& dc = d.cameras[k];
      stagePng(d.framePath(dc.images, f), image);
      stagePng(d.framePath(dc.masks, f), renderMask(mesh, camera));
      progress.tick(++done);
    }
  }
  files.write((fs::path(p.output) / kDatasetFileName).string(), formatDataset(d, p.output));
  files.commit();
  return d;
}

}  // namespace tdvo
