// NeRF-style transforms.json (Mildenhall et al. 2020; also the instant-ngp fields).
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/sequence.h"
#include "common/media/json_text.h"
#include "common/media/png_io.h"
#include "tools/multiview/importers.h"

namespace tdvo {

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

// Whether a PNG carries an alpha channel (colour type 4 or 6), read from its header.
bool pngHasAlpha(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  check(f != nullptr, path + ": cannot open");
  noteFileRead(f);
  uint8_t head[26];
  const size_t n = std::fread(head, 1, sizeof head, f);
  std::fclose(f);
  check(n == sizeof head && std::memcmp(head + 12, "IHDR", 4) == 0, path + ": not a PNG file");
  return head[25] == 4 || head[25] == 6;
}

double number(const Json& object, const char* key, const std::string& where) {
  check(object.contains(key) && object[key].is_number(),
        where + ": missing or non-numeric \"" + key + "\"");
  const double v = object[key].get<double>();
  check(std::isfinite(v), where + ": \"" + key + "\" must be finite");
  return v;
}

}  // namespace

Dataset importNerf(const std::string& transformsFile) {
  const std::vector<uint8_t> bytes =
      readFileBytes(transformsFile, kMaxTextFileBytes, "a calibration file");
  const Json root = parseJsonText<Json>(bytes.begin(), bytes.end(), transformsFile);
  check(root.is_object(), transformsFile + ": must be a JSON object");
  check(root.contains("frames") && root["frames"].is_array() && !root["frames"].empty(),
        transformsFile + ": needs a non-empty \"frames\" array");
  const fs::path folder = fs::path(transformsFile).parent_path();
  Dataset d;
  d.folder = folder.empty() ? "." : folder.generic_string();
  d.description = "NeRF transforms " + fs::path(transformsFile).filename().string();
  d.frameCount = 1;

  const Json& frames = root["frames"];
  for (size_t i = 0; i < frames.size(); ++i) {
    const Json& f = frames[i];
    const std::string where = transformsFile + ": frames[" + std::to_string(i) + "]";
    check(f.is_object() && f.contains("file_path") && f["file_path"].is_string(),
          where + ": needs a \"file_path\" string");
    std::string file = f["file_path"].get<std::string>();
    if (fs::path(file).extension().empty()) file += ".png";
    DatasetCamera dc;
    Camera& c = dc.camera;
    const std::string normal = fs::path(file).lexically_normal().generic_string();
    dc.images = escapePercent(normal);  // a file name, as a dataset path's text
    c.name = fs::path(file).stem().string();
    const std::string imagePath = d.resolve(normal);
    if (root.contains("w") && root.contains("h")) {
      // Checked before the conversion to int, which is undefined for values beyond its range.
      const double w = number(root, "w", transformsFile), h = number(root, "h", transformsFile);
      check(w >= 1 && w <= 32767 && h >= 1 && h <= 32767,
            transformsFile + ": \"w\" and \"h\" must be in [1, 32767]");
      c.width = static_cast<int>(w);
      c.height = static_cast<int>(h);
    } else {
      readPngSize(imagePath, c.width, c.height);
    }
    dc.alphaMask = pngHasAlpha(imagePath);
    // Focal length from the horizontal field of view unless given in pixels.
    if (root.contains("fl_x")) {
      c.fx = number(root, "fl_x", transformsFile);
      c.fy = root.contains("fl_y") ? number(root, "fl_y", transformsFile) : c.fx;
    } else {
      const double angle = number(root, "camera_angle_x", transformsFile);
      check(angle > 0 && angle < M_PI, transformsFile + ": camera_angle_x out of range");
      c.fx = c.fy = 0.5 * c.width / std::tan(0.5 * angle);
    }
    c.cx = root.contains("cx") ? number(root, "cx", transformsFile) : 0.5 * c.width;
    c.cy = root.contains("cy") ? number(root, "cy", transformsFile) : 0.5 * c.height;
    if (root.contains("k1") || root.contains("k2") || root.contains("p1") || root.contains("p2")) {
      auto opt = [&](const char* key) {
        return root.contains(key) ? number(root, key, transformsFile) : 0.0;
      };
      c.distortion = {opt("k1"), opt("k2"), opt("p1"), opt("p2"), opt("k3")};
    }
    check(f.contains("transform_matrix") && f["transform_matrix"].is_array() &&
              f["transform_matrix"].size() == 4,
          where + ": needs a 4x4 \"transform_matrix\"");
    Mat4d m;
    for (size_t r = 0; r < 4; ++r) {
      const Json& row = f["transform_matrix"][r];
      check(row.is_array() && row.size() == 4, where + ": transform_matrix must be 4x4");
      for (size_t col = 0; col < 4; ++col) {
        check(row[col].is_number() && std::isfinite(row[col].get<double>()),
              where + ": transform_matrix must hold finite numbers");
        m[r][col] = row[col].get<double>();
      }
    }
    Mat3d rotation;
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col)
        rotation[r][col] = m[r][col];
    check(isRotation(rotation, 1e-4),
          where + ": the rotation part of transform_matrix is not a rotation (scaled camera?)");
    setFromOpenGlCameraToWorld(c, m);
    d.cameras.push_back(std::move(dc));
  }
  checkDataset(d, transformsFile);
  return d;
}

}  // namespace tdvo
