// Middlebury multi-view stereo calibration (*_par.txt).
#include <charconv>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/sequence.h"
#include "common/media/png_io.h"
#include "tools/multiview/importers.h"

namespace tdvo {

namespace fs = std::filesystem;

namespace {

double parseNumber(const std::string& token, const std::string& where) {
  double value = 0;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  check(ec == std::errc() && ptr == token.data() + token.size() && std::isfinite(value),
        where + ": '" + token + "' is not a number");
  return value;
}

}  // namespace

Dataset importMiddlebury(const std::string& parFile) {
  std::istringstream in(readTextFile(parFile, kMaxTextFileBytes, "a calibration file"));
  const fs::path folder = fs::path(parFile).parent_path();
  Dataset d;
  d.folder = folder.empty() ? "." : folder.generic_string();
  d.description =
      "Middlebury multi-view stereo calibration " + fs::path(parFile).filename().string();
  d.frameCount = 1;

  std::string line;
  int lineNumber = 0;
  int declared = -1;
  while (std::getline(in, line)) {
    ++lineNumber;
    const std::string where = parFile + ":" + std::to_string(lineNumber);
    std::istringstream tokens(line);
    std::vector<std::string> t;
    for (std::string s; tokens >> s;)
      t.push_back(s);
    if (t.empty()) continue;
    if (declared < 0) {
      check(t.size() == 1, where + ": the first line must hold the view count");
      const double n = parseNumber(t[0], where);
      check(n >= 1 && n <= 100000 && n == std::floor(n), where + ": invalid view count " + t[0]);
      declared = static_cast<int>(n);
      continue;
    }
    check(t.size() == 22, where +
                              ": expected 'name k11..k33 r11..r33 t1 t2 t3' (22 fields), found " +
                              std::to_string(t.size()));
    double v[21];
    for (int i = 0; i < 21; ++i)
      v[i] = parseNumber(t[static_cast<size_t>(i) + 1], where);
    // K = [fx s cx; 0 fy cy; 0 0 1]; this model has no skew.
    check(v[3] == 0 && v[6] == 0 && v[7] == 0 && v[8] == 1,
          where + ": K must have the form [fx 0 cx; 0 fy cy; 0 0 1]");
    check(std::fabs(v[1]) <= 1e-9 * std::fabs(v[0]),
          where + ": K has a skew term " + t[2] + ", which the camera model does not support");
    DatasetCamera dc;
    Camera& c = dc.camera;
    c.name = fs::path(t[0]).stem().string();
    c.fx = v[0];
    c.cx = v[2];
    c.fy = v[4];
    c.cy = v[5];
    Mat3d R;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        R[i][j] = v[9 + 3 * i + j];
    check(isRotation(R, 1e-4), where + ": R is not a rotation matrix");
    c.R = nearestRotation(R);
    c.t = {v[18], v[19], v[20]};
    dc.images = escapePercent(t[0]);  // a file name, as a dataset path's text
    readPngSize(d.resolve(t[0]), c.width, c.height);
    d.cameras.push_back(std::move(dc));
  }
  check(declared >= 0, parFile + ": empty calibration file");
  check(static_cast<int>(d.cameras.size()) == declared,
        parFile + ": the first line declares " + std::to_string(declared) + " views but " +
            std::to_string(d.cameras.size()) + " follow");
  checkDataset(d, parFile);
  return d;
}

}  // namespace tdvo
