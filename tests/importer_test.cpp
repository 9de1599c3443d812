// Importers: hand-made inputs (always run) and the real data sets in ../shared/data/multiview
// (skipped, saying so, when absent). The real-data checks are geometric: the calibration must
// put the object where the images show it.
#include "common/media/png_io.h"
#include "tools/multiview/importers.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/media/video_reader.h"
#include "common/views/rasteriser.h"

using namespace tdvo;
namespace fs = std::filesystem;

namespace {

const std::string kMultiview = std::string(TDVO_SHARED_DATA_DIR) + "/multiview";

#define SKIP_WITHOUT(path)                          \
  if (!fs::exists(path))                            \
  GTEST_SKIP() << "real data not found: " << (path) \
               << " (../shared/data is absent; this test needs the public multi-view sets)"

class TempFolder {
 public:
  explicit TempFolder(const std::string& tag)
      : path_(fs::temp_directory_path() /
              ("tdvo_import_" + tag + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempFolder() { fs::remove_all(path_); }
  std::string str() const { return path_.string(); }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

void writeText(const std::string& path, const std::string& text) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path) << text;
}

// Writes the dataset to a folder and reads it back: the real-data checks then run on what the
// layout stores, not on the importer's in-memory result.
Dataset throughLayout(const Dataset& d, const std::string& folder) {
  writeDataset(d, folder);
  return readDataset(folder);
}

// ---- small image operations for silhouettes ----

// Binary dilation with a disk of radius r (pixels outside the image count as background).
Image dilate(const Image& mask, int r) {
  const int w = mask.width, h = mask.height;
  Image out(w, h, 1, 0);
  std::vector<int> prefix(static_cast<size_t>(w) + 1);
  std::vector<std::vector<int>> rows(static_cast<size_t>(h));
  for (int y = 0; y < h; ++y) {
    std::vector<int>& p = rows[static_cast<size_t>(y)];
    p.assign(static_cast<size_t>(w) + 1, 0);
    for (int x = 0; x < w; ++x)
      p[static_cast<size_t>(x) + 1] = p[static_cast<size_t>(x)] + (mask.at(x, y) ? 1 : 0);
  }
  for (int dy = -r; dy <= r; ++dy) {
    const int half = static_cast<int>(std::floor(std::sqrt(double(r * r - dy * dy))));
    for (int y = 0; y < h; ++y) {
      const int sy = y + dy;
      if (sy < 0 || sy >= h) continue;
      const std::vector<int>& p = rows[static_cast<size_t>(sy)];
      for (int x = 0; x < w; ++x) {
        const int a = std::max(0, x - half), b = std::min(w, x + half + 1);
        if (p[static_cast<size_t>(b)] > p[static_cast<size_t>(a)]) out.at(x, y) = 255;
      }
    }
  }
  return out;
}

Image invert(const Image& mask) {
  Image out = mask;
  for (uint8_t& v : out.pixels)
    v = v ? 0 : 255;
  return out;
}

// Binary erosion with a disk (outside the image counts as foreground, as in Matlab's imerode).
Image erode(const Image& mask, int r) {
  return invert(dilate(invert(mask), r));
}

struct Overlap {
  size_t both = 0, onlyA = 0, onlyB = 0;
  double iou() const { return double(both) / double(std::max<size_t>(1, both + onlyA + onlyB)); }
};

Overlap overlap(const Image& a, const Image& b) {
  Overlap o;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    const bool x = a.pixels[i] != 0, y = b.pixels[i] != 0;
    o.both += x && y;
    o.onlyA += x && !y;
    o.onlyB += !x && y;
  }
  return o;
}

// ---- a simple voxel carving: the visual hull of silhouettes ----

struct VoxelGrid {
  Vec3d lo;
  double step = 0;
  int n = 0;  // n × n × n voxels
  std::vector<uint8_t> inside;
  Vec3d centre(int i, int j, int k) const {
    return {lo[0] + (i + 0.5) * step, lo[1] + (j + 0.5) * step, lo[2] + (k + 0.5) * step};
  }
  size_t index(int i, int j, int k) const {
    return (static_cast<size_t>(k) * static_cast<size_t>(n) + static_cast<size_t>(j)) *
               static_cast<size_t>(n) +
           static_cast<size_t>(i);
  }
  size_t count() const { return static_cast<size_t>(std::count(inside.begin(), inside.end(), 1)); }
};

// Keeps the voxels whose centre projects into every silhouette. A view in which the centre falls
// outside the image carves it away, unless `keepOutside` (objects partly outside the field of
// view, as in some dino views).
VoxelGrid carve(const Vec3d& lo, double size, int n, const std::vector<Camera>& cameras,
                const std::vector<Image>& silhouettes, bool keepOutside) {
  VoxelGrid g;
  g.lo = lo;
  g.n = n;
  g.step = size / n;
  g.inside.assign(static_cast<size_t>(n) * n * n, 0);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Vec3d p = g.centre(i, j, k);
        bool keep = true;
        for (size_t v = 0; v < cameras.size() && keep; ++v) {
          Vec2d pixel;
          if (!cameras[v].project(p, pixel)) {
            keep = keepOutside;
            continue;
          }
          const long x = std::lround(pixel[0]), y = std::lround(pixel[1]);
          if (x < 0 || y < 0 || x >= cameras[v].width || y >= cameras[v].height) {
            keep = keepOutside;
            continue;
          }
          keep = silhouettes[v].at(static_cast<int>(x), static_cast<int>(y)) != 0;
        }
        g.inside[g.index(i, j, k)] = keep ? 1 : 0;
      }
  return g;
}

// The bounding box of the kept voxels, one voxel larger on every side: [lo, lo + size] cube.
void hullBounds(const VoxelGrid& g, Vec3d& lo, double& size) {
  int mn[3] = {g.n, g.n, g.n}, mx[3] = {-1, -1, -1};
  for (int k = 0; k < g.n; ++k)
    for (int j = 0; j < g.n; ++j)
      for (int i = 0; i < g.n; ++i)
        if (g.inside[g.index(i, j, k)]) {
          const int c[3] = {i, j, k};
          for (int a = 0; a < 3; ++a)
            mn[a] = std::min(mn[a], c[a]), mx[a] = std::max(mx[a], c[a]);
        }
  size = 0;
  for (int a = 0; a < 3; ++a) {
    lo[a] = g.lo[a] + (mn[a] - 1) * g.step;
    size = std::max(size, (mx[a] - mn[a] + 3) * g.step);
  }
}

// The boundary faces of the kept voxels as a triangle mesh.
Mesh voxelSurface(const VoxelGrid& g) {
  Mesh m;
  auto filled = [&](int i, int j, int k) {
    return i >= 0 && j >= 0 && k >= 0 && i < g.n && j < g.n && k < g.n &&
           g.inside[g.index(i, j, k)];
  };
  for (int k = 0; k < g.n; ++k)
    for (int j = 0; j < g.n; ++j)
      for (int i = 0; i < g.n; ++i) {
        if (!filled(i, j, k)) continue;
        for (int axis = 0; axis < 3; ++axis)
          for (int side = 0; side < 2; ++side) {
            int c[3] = {i, j, k};
            c[axis] += side ? 1 : -1;
            if (filled(c[0], c[1], c[2])) continue;
            // The face's four corners.
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            const uint32_t base = static_cast<uint32_t>(m.positions.size());
            for (int corner = 0; corner < 4; ++corner) {
              double p[3] = {g.lo[0] + i * g.step, g.lo[1] + j * g.step, g.lo[2] + k * g.step};
              p[axis] += side * g.step;
              p[u] += ((corner == 1 || corner == 2) ? 1 : 0) * g.step;
              p[v] += (corner >= 2 ? 1 : 0) * g.step;
              m.positions.push_back({p[0], p[1], p[2]});
            }
            m.triangles.push_back({base, base + 1, base + 2});
            m.triangles.push_back({base, base + 2, base + 3});
          }
      }
  return m;
}

Mesh boxMesh(const Vec3d& lo, const Vec3d& hi) {
  Mesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.push_back(
        {(i & 1) ? hi[0] : lo[0], (i & 2) ? hi[1] : lo[1], (i & 4) ? hi[2] : lo[2]});
  m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return m;
}

std::vector<Camera> camerasOf(const Dataset& d) {
  std::vector<Camera> out;
  for (const DatasetCamera& dc : d.cameras)
    out.push_back(dc.camera);
  return out;
}

}  // namespace

// ---------------------------------------------------------------- hand-made inputs

// A calibration file starting with a UTF-8 byte-order mark reads as without it (it was "'16' is
// not a number", the mark invisible).
// The world's up (--Up of 3dvo-import and 3dvo-synth) is a direction: the zero vector is
// refused as such (3dvo-synth said "up direction is parallel to the view direction").
TEST(Importer, UpIsADirection) {
  EXPECT_EQ(parseDirection("0,0,-2", "Up"), (Vec3d{0, 0, -2}));
  try {
    parseDirection("0,0,0", "Up");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "Up: '0,0,0' is the zero vector, which has no direction");
  }
  EXPECT_THROW(parseDirection("0,0", "Up"), Error);
}

TEST(Importer, MiddleburyParFileWithByteOrderMark) {
  TempFolder dir("mb-bom");
  writePng(dir / "v1.png", Image(40, 30, 3));
  writeText(dir / "x_par.txt",
            "\xEF\xBB\xBF"
            "1\r\n"
            "v1.png 100 0 19.5 0 110 14.5 0 0 1  1 0 0 0 1 0 0 0 1  0.1 0.2 3\r\n");
  const Dataset d = importAny(dir.str(), {});
  ASSERT_EQ(d.cameras.size(), 1u);
  EXPECT_EQ(d.cameras[0].camera.name, "v1");
}

TEST(Importer, MiddleburyParFile) {
  TempFolder dir("mb");
  writePng(dir / "v1.png", Image(40, 30, 3));
  writePng(dir / "v2.png", Image(40, 30, 3));
  writeText(dir / "x_par.txt",
            "2\n"
            "v1.png 100 0 19.5 0 110 14.5 0 0 1  1 0 0 0 1 0 0 0 1  0.1 0.2 3\n"
            "v2.png 100 0 19.5 0 110 14.5 0 0 1  0 -1 0 1 0 0 0 0 1  0 0 4\n");
  EXPECT_EQ(detectImportFormat(dir.str()), ImportFormat::middlebury);
  const Dataset d = importAny(dir.str(), {});
  ASSERT_EQ(d.cameras.size(), 2u);
  const Camera& c = d.cameras[1].camera;
  EXPECT_EQ(c.name, "v2");
  EXPECT_EQ(c.width, 40);
  EXPECT_EQ(c.height, 30);
  EXPECT_EQ(c.fx, 100);
  EXPECT_EQ(c.fy, 110);
  EXPECT_EQ(c.cx, 19.5);
  EXPECT_EQ(c.t, (Vec3d{0, 0, 4}));
  // P = K [R | t]: the world point (1, 0, 0) → camera (0, 1, 4) → pixel (19.5, 14.5 + 27.5).
  Vec2d p;
  ASSERT_TRUE(c.project({1, 0, 0}, p));
  EXPECT_NEAR(p[0], 19.5, 1e-12);
  EXPECT_NEAR(p[1], 42.0, 1e-12);
  EXPECT_EQ(d.frameCount, 1);
  EXPECT_EQ(fs::path(d.framePath(d.cameras[0].images, 0)), fs::path(dir / "v1.png"));

  writeText(dir / "x_par.txt", "3\nv1.png 100 0 19.5 0 110 14.5 0 0 1 1 0 0 0 1 0 0 0 1 0 0 3\n");
  EXPECT_THROW(importMiddlebury(dir / "x_par.txt"), Error);  // count mismatch
  writeText(dir / "x_par.txt", "1\nv1.png 100 0 19.5 0 110 14.5 0 0 1 1 0 0 0 1 0 0 0 1 0 0\n");
  try {
    importMiddlebury(dir / "x_par.txt");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("x_par.txt:2"), std::string::npos) << e.what();
  }
}

TEST(Importer, OpenCvXmlCameraFolders) {
  TempFolder dir("cv");
  const std::string xml =
      "<?xml version=\"1.0\"?>\n<opencv_storage>\n"
      "<CameraMatrix type_id=\"opencv-matrix\"><rows>3</rows><cols>3</cols><dt>f</dt>\n"
      "  <data>500. 0. 320. 0. 505. 240. 0. 0. 1.</data></CameraMatrix>\n"
      "<DistortionCoeffs type_id=\"opencv-matrix\"><rows>1</rows><cols>5</cols><dt>f</dt>\n"
      "  <data>-0.2 0.05 0.001 0.002 -0.01</data></DistortionCoeffs>\n"
      "<Rotation type_id=\"opencv-matrix\"><rows>3</rows><cols>1</cols><dt>d</dt>\n"
      "  <data>0. 0. 1.5707963267948966</data></Rotation>\n"
      "<Translation type_id=\"opencv-matrix\"><rows>3</rows><cols>1</cols><dt>d</dt>\n"
      "  <data>10. 20. 3000.</data></Translation>\n"
      "<image_width>640</image_width><image_height>480</image_height>\n"
      "</opencv_storage>\n";
  writeText(dir / "camB/config.xml", xml);
  writeText(dir / "camA/config.xml", xml);
  EXPECT_EQ(detectImportFormat(dir.str()), ImportFormat::opencv);
  ImportOptions options;
  try {
    importOpenCv(dir.str(), options);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no video 'video.avi'"), std::string::npos) << e.what();
  }
  // Calibration plus image sequences beside it (numbered from 1 here; camB has one frame less).
  for (int f = 1; f <= 3; ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "/%04d.png", f);
    writePng(dir / ("camA" + std::string(name)), Image(640, 480, 3));
    if (f < 3) writePng(dir / ("camB" + std::string(name)), Image(640, 480, 3));
  }
  options.images = "%04d.png";
  const Dataset d = importAny(dir.str(), options);
  ASSERT_EQ(d.cameras.size(), 2u);
  EXPECT_EQ(d.cameras[0].camera.name, "camA");  // sub-folders in name order
  EXPECT_EQ(d.firstFrame, 1);
  EXPECT_EQ(d.frameCount, 2);
  const Camera& c = d.cameras[1].camera;
  EXPECT_EQ(c.width, 640);
  EXPECT_EQ(c.fx, 500);
  EXPECT_EQ(c.fy, 505);
  EXPECT_EQ(c.distortion.k1, -0.2);
  EXPECT_EQ(c.distortion.k3, -0.01);
  // Rodrigues (0, 0, π/2): R = [0 −1 0; 1 0 0; 0 0 1]; X = (1, 0, 0) → (0, 1, 0) + t.
  const Vec3d p = c.toCamera({1, 0, 0});
  EXPECT_NEAR(p[0], 10, 1e-12);
  EXPECT_NEAR(p[1], 21, 1e-12);
  EXPECT_NEAR(p[2], 3000, 1e-12);
  EXPECT_NO_THROW(validateDatasetFiles(throughLayout(d, dir / "out")));
  // Errors name the file and line.
  const std::string broken = std::string(xml).replace(xml.find("500. 0."), 7, "500.");
  writeText(dir / "broken/cam.xml", broken);
  try {
    importOpenCv(dir / "broken/cam.xml", options);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cam.xml:3: CameraMatrix: expected 9 numbers, found 8"),
              std::string::npos)
        << e.what();
  }
  writeText(dir / "bad/cam.xml", "<opencv_storage><CameraMatrix>");
  EXPECT_THROW(importOpenCv(dir / "bad/cam.xml", options), Error);
}

TEST(Importer, NerfTransformsHandComputed) {
  TempFolder dir("nerf");
  Image rgba(20, 10, 4, 0);
  rgba.at(3, 4, 3) = 255;
  writePng(dir / "train/r_0.png", (fs::create_directories(dir / "train"), rgba));
  // camera_angle_x = 2 atan(1/2) → f = 0.5 · 20 / (1/2) = 20 px.
  const double angle = 2 * std::atan(0.5);
  char json[1024];
  std::snprintf(json, sizeof json,
                "{\"camera_angle_x\": %.17g, \"frames\": [{\"file_path\": \"./train/r_0\", "
                "\"transform_matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,5],[0,0,0,1]]}]}",
                angle);
  writeText(dir / "transforms_train.json", json);
  EXPECT_EQ(detectImportFormat(dir.str()), ImportFormat::nerf);
  const Dataset d = importAny(dir.str(), {});
  ASSERT_EQ(d.cameras.size(), 1u);
  const DatasetCamera& dc = d.cameras[0];
  EXPECT_EQ(dc.camera.name, "r_0");
  EXPECT_TRUE(dc.alphaMask);
  EXPECT_NEAR(dc.camera.fx, 20, 1e-12);
  EXPECT_EQ(dc.camera.cx, 10);
  EXPECT_EQ(dc.camera.cy, 5);
  Vec2d p;
  ASSERT_TRUE(dc.camera.project({0, 1, 0}, p));  // OpenGL y up → image up
  EXPECT_NEAR(p[0], 10, 1e-12);
  EXPECT_NEAR(p[1], 1, 1e-12);
  const Dataset r = throughLayout(d, dir / "out");
  CameraFrames frames(r, 0);
  const Image mask = frames.mask(0);
  EXPECT_EQ(mask.at(3, 4), 255);
  EXPECT_EQ(mask.at(4, 4), 0);
}

// ---------------------------------------------------------------- real data

TEST(ImporterRealData, DinoBoundingBoxAndSilhouettes) {
  const std::string folder = kMultiview + "/middlebury-dinoSparseRing";
  SKIP_WITHOUT(folder);
  TempFolder out("dino");
  const Dataset d = throughLayout(importAny(folder, {}), out.str());
  ASSERT_EQ(d.cameras.size(), 16u);

  // The README's tight bounding box and the list of views with usable silhouettes.
  const Vec3d lo = {-0.061897, -0.018874, -0.057845}, hi = {0.010897, 0.068227, 0.015495};
  std::vector<std::string> good;
  {
    std::ifstream in(folder + "/dinoSR_good_silhouette_images.txt");
    for (std::string name; in >> name;)
      good.push_back(fs::path(name).stem().string());
  }
  ASSERT_EQ(good.size(), 15u);

  // Silhouettes by the data set's recipe: threshold 0.19, dilate 10 px, erode 7 px.
  std::vector<Camera> cameras;
  std::vector<Image> silhouettes;
  for (const std::string& name : good) {
    const size_t k = d.cameraIndex(name);
    const Image image = CameraFrames(d, k).frame(0);
    Image mask(image.width, image.height, 1, 0);
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) {
        int v = 0;
        for (int c = 0; c < 3; ++c)
          v = std::max<int>(v, image.at(x, y, c));
        mask.at(x, y) = v > 0.19 * 255 ? 255 : 0;
      }
    silhouettes.push_back(erode(dilate(mask, 10), 7));
    cameras.push_back(d.cameras[k].camera);
  }

  // 1. The box projects around each silhouette, tightly: (almost) every silhouette pixel lies
  //    inside the box's projection, and the silhouette fills a good part of that projection.
  const Mesh box = boxMesh(lo, hi);
  double worstContained = 1, worstFill = 1;
  for (size_t v = 0; v < cameras.size(); ++v) {
    const Overlap o = overlap(silhouettes[v], renderMask(box, cameras[v]));
    ASSERT_GT(o.both + o.onlyA, 5000u) << good[v] << ": empty silhouette";
    const double contained = double(o.both) / double(o.both + o.onlyA);
    const double fill = double(o.both) / double(o.both + o.onlyB);
    worstContained = std::min(worstContained, contained);
    worstFill = std::min(worstFill, fill);
    EXPECT_GT(contained, 0.99) << good[v] << ": silhouette pixels inside the projected box";
    EXPECT_GT(fill, 0.25) << good[v] << ": the projected box is far larger than the silhouette";
  }
  // 2. A hull carved inside the box (a cube 1.1 times its largest side around it) from all good
  //    silhouettes re-projects onto each of them. (The views all lie on one ring at latitude
  //    −74°, so outside the box the cones are not bounded along the ring's axis: the box is the
  //    prior that makes the hull finite.)
  const Vec3d extent = hi - lo;
  const double cube = std::max({extent[0], extent[1], extent[2]}) * 1.1;
  const Vec3d start = 0.5 * (lo + hi) - Vec3d{cube / 2, cube / 2, cube / 2};
  const VoxelGrid hull = carve(start, cube, 96, cameras, silhouettes, true);
  ASSERT_GT(hull.count(), 1000u);
  const Mesh surface = voxelSurface(hull);
  double worstIou = 1, sumIou = 0;
  for (size_t v = 0; v < cameras.size(); ++v) {
    const double iou = overlap(silhouettes[v], renderMask(surface, cameras[v])).iou();
    worstIou = std::min(worstIou, iou);
    sumIou += iou;
    EXPECT_GT(iou, 0.9) << good[v] << ": hull re-projection vs silhouette";
  }
  std::printf(
      "dino: silhouette pixels inside the projected README box >= %.4f, silhouette fills "
      ">= %.3f of the box's projection (worst views); hull IoU mean %.3f, worst %.3f over "
      "%zu good views\n",
      worstContained, worstFill, sumIou / cameras.size(), worstIou, cameras.size());
}

TEST(ImporterRealData, LegoAlphaMasksAgreeWithCarvedHull) {
  const std::string folder = kMultiview + "/nerf-lego";
  SKIP_WITHOUT(folder);
  TempFolder out("lego");
  const Dataset d = throughLayout(importAny(folder, {}), out.str());
  ASSERT_EQ(d.cameras.size(), 100u);
  // Carve with the even views, check against all: the odd ones were not used to carve.
  std::vector<Camera> cameras = camerasOf(d);
  std::vector<Image> masks;
  for (size_t k = 0; k < d.cameras.size(); ++k) {
    CameraFrames frames(d, k);
    ASSERT_TRUE(frames.hasMasks());
    masks.push_back(frames.mask(0));
  }
  std::vector<Camera> carveCameras;
  std::vector<Image> carveMasks;
  for (size_t k = 0; k < cameras.size(); k += 2) {
    carveCameras.push_back(cameras[k]);
    carveMasks.push_back(masks[k]);
  }
  // Coarse pass over a generous cube, then a finer one around what is left.
  const VoxelGrid coarse = carve({-2, -2, -2}, 4, 48, carveCameras, carveMasks, false);
  ASSERT_GT(coarse.count(), 50u) << "nothing left after carving: the calibration is wrong";
  Vec3d lo;
  double size;
  hullBounds(coarse, lo, size);
  const VoxelGrid hull = carve(lo, size, 96, carveCameras, carveMasks, false);
  const Mesh surface = voxelSurface(hull);
  double sumHeld = 0, worstHeld = 1, sumUsed = 0;
  for (size_t k = 0; k < cameras.size(); ++k) {
    const double iou = overlap(masks[k], renderMask(surface, cameras[k])).iou();
    if (k % 2) {
      // A hull is larger than the object where no carving view looks into a concavity, which
      // shows most in held-out views from unusual angles (e.g. r_95, nearly from above).
      sumHeld += iou;
      worstHeld = std::min(worstHeld, iou);
      EXPECT_GT(iou, 0.8) << d.cameras[k].camera.name << " (held out)";
    } else {
      sumUsed += iou;
      EXPECT_GT(iou, 0.9) << d.cameras[k].camera.name << " (used for carving)";
    }
  }
  EXPECT_GT(sumUsed / 50, 0.95);
  EXPECT_GT(sumHeld / 50, 0.93);
  std::printf(
      "lego: hull (%zu voxels, 96^3 over a %.2f cube) vs alpha masks: IoU mean %.3f on "
      "the 50 carving views, mean %.3f / worst %.3f on the 50 held-out views\n",
      hull.count(), size, sumUsed / 50, sumHeld / 50, worstHeld);
}

TEST(ImporterRealData, UuFourCamerasSeeThePersonConsistently) {
  const std::string folder = kMultiview + "/uu-4cam";
  SKIP_WITHOUT(folder);
  TempFolder out("uu");
  ImportOptions options;
  options.up = "0,0,-1";  // the README: world up is −Z
  const Dataset d = throughLayout(importAny(folder, options), out.str());
  ASSERT_EQ(d.cameras.size(), 4u);
  EXPECT_EQ(d.cameras[0].camera.width, 644);
  EXPECT_EQ(d.cameras[0].camera.height, 486);
  EXPECT_GE(d.frameCount, 400);
  EXPECT_NO_THROW(validateDatasetFiles(d));

  // Background subtraction on undistorted frames: the first video frame against the mean of
  // the first background frames, per-pixel largest channel difference, then clean-up.
  std::vector<Camera> cameras;
  std::vector<Image> foreground;
  for (size_t k = 0; k < d.cameras.size(); ++k) {
    const Camera& camera = d.cameras[k].camera;
    const Image frame = undistortImage(CameraFrames(d, k).frame(0), camera);
    VideoReader backgroundVideo(d.resolve(d.cameras[k].backgroundVideo));
    std::vector<double> mean(frame.pixels.size(), 0.0);
    const int n = 10;
    Image b;
    for (int i = 0; i < n; ++i) {
      ASSERT_TRUE(backgroundVideo.read(b));
      for (size_t p = 0; p < mean.size(); ++p)
        mean[p] += b.pixels[p] / double(n);
    }
    Image background(b.width, b.height, 3);
    for (size_t p = 0; p < mean.size(); ++p)
      background.pixels[p] = static_cast<uint8_t>(std::lround(mean[p]));
    background = undistortImage(background, camera);
    Image mask(frame.width, frame.height, 1, 0);
    for (size_t p = 0; p < mask.pixels.size(); ++p) {
      int diff = 0;
      for (size_t c = 0; c < 3; ++c)
        diff = std::max(diff,
                        std::abs(int(frame.pixels[3 * p + c]) - int(background.pixels[3 * p + c])));
      mask.pixels[p] = diff > 40 ? 255 : 0;
    }
    // Opening removes speckle, closing fills small holes.
    mask = erode(dilate(dilate(erode(mask, 2), 2), 6), 6);
    foreground.push_back(mask);
    cameras.push_back(camera.withoutDistortion());  // the undistorted images' camera
  }

  // Where the four optical axes pass closest to each other: the point the rig looks at.
  Mat3d A = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
  Vec3d rhs = {0, 0, 0};
  for (const Camera& c : cameras) {
    const Vec3d o = c.centre(), v = c.viewingDirection();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j)
        A[i][j] += (i == j ? 1.0 : 0.0) - v[i] * v[j];
      rhs[i] += o[i] - v[i] * dot(v, o);
    }
  }
  // Solve A x = rhs by Cramer's rule.
  const double det = determinant(A);
  ASSERT_GT(std::fabs(det), 1e-9);
  Vec3d focus;
  for (int col = 0; col < 3; ++col) {
    Mat3d m = A;
    for (int i = 0; i < 3; ++i)
      m[i][col] = rhs[i];
    focus[col] = determinant(m) / det;
  }

  // Carve a 4 m cube around that point (units: mm) and keep voxels every camera sees as
  // foreground; the person is the hull.
  const double cube = 4000;
  const VoxelGrid coarse =
      carve(focus - Vec3d{cube / 2, cube / 2, cube / 2}, cube, 64, cameras, foreground, false);
  ASSERT_GT(coarse.count(), 20u) << "no 3D point is foreground in all four views";
  Vec3d lo;
  double size;
  hullBounds(coarse, lo, size);
  const VoxelGrid hull = carve(lo, size, 96, cameras, foreground, false);
  // The hull's centroid: one 3D point near the person.
  Vec3d centroid = {0, 0, 0};
  size_t count = 0;
  for (int k = 0; k < hull.n; ++k)
    for (int j = 0; j < hull.n; ++j)
      for (int i = 0; i < hull.n; ++i)
        if (hull.inside[hull.index(i, j, k)]) centroid = centroid + hull.centre(i, j, k), ++count;
  ASSERT_GT(count, 100u);
  centroid = (1.0 / count) * centroid;

  const Mesh surface = voxelSurface(hull);
  double sumIou = 0, worstIou = 1;
  for (size_t k = 0; k < cameras.size(); ++k) {
    // The point lands inside every image, on the person (foreground in a 5×5 neighbourhood).
    Vec2d p;
    ASSERT_TRUE(cameras[k].project(centroid, p)) << d.cameras[k].camera.name;
    const int x = static_cast<int>(std::lround(p[0])), y = static_cast<int>(std::lround(p[1]));
    ASSERT_TRUE(x >= 2 && y >= 2 && x < cameras[k].width - 2 && y < cameras[k].height - 2)
        << d.cameras[k].camera.name << ": point projects outside the image";
    int fg = 0;
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx)
        fg += foreground[k].at(x + dx, y + dy) != 0;
    EXPECT_GE(fg, 20) << d.cameras[k].camera.name << ": the point is not on the person";
    const double iou = overlap(foreground[k], renderMask(surface, cameras[k])).iou();
    sumIou += iou;
    worstIou = std::min(worstIou, iou);
    EXPECT_GT(iou, 0.6) << d.cameras[k].camera.name << ": hull re-projection vs foreground";
    std::printf("uu-4cam %s: point (%.0f, %.0f, %.0f) mm -> pixel (%.1f, %.1f); hull IoU %.3f\n",
                d.cameras[k].camera.name.c_str(), centroid[0], centroid[1], centroid[2], p[0], p[1],
                iou);
  }
  std::printf("uu-4cam: hull %zu voxels (96^3 over a %.0f mm cube); IoU mean %.3f, worst %.3f\n",
              count, size, sumIou / cameras.size(), worstIou);
}
