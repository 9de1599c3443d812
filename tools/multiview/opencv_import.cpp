// OpenCV FileStorage XML calibration files (one per camera).
#include <tinyxml2.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/sequence.h"
#include "common/core/warnings.h"
#include "common/media/png_io.h"
#include "common/media/video_reader.h"
#include "common/views/image.h"
#include "tools/multiview/importers.h"

namespace tdvo {

namespace fs = std::filesystem;

namespace {

struct XmlMatrix {
  int rows = 0, cols = 0;
  std::vector<double> data;
};

const tinyxml2::XMLElement* findNode(const tinyxml2::XMLElement* root,
                                     std::initializer_list<const char*> names) {
  for (const char* name : names)
    if (const tinyxml2::XMLElement* e = root->FirstChildElement(name)) return e;
  return nullptr;
}

int childInteger(const tinyxml2::XMLElement* e, const char* name, const std::string& where) {
  const tinyxml2::XMLElement* c = e->FirstChildElement(name);
  int value = 0;
  check(c && c->QueryIntText(&value) == tinyxml2::XML_SUCCESS,
        where + ": missing or invalid <" + name + ">");
  return value;
}

// Reads an `opencv-matrix` node: <rows>, <cols>, <data> with rows·cols numbers.
XmlMatrix readMatrix(const tinyxml2::XMLElement* e, const std::string& file) {
  const std::string where = file + ":" + std::to_string(e->GetLineNum()) + ": " + e->Name();
  XmlMatrix m;
  m.rows = childInteger(e, "rows", where);
  m.cols = childInteger(e, "cols", where);
  check(
      m.rows >= 1 && m.rows <= 16 && m.cols >= 1 && m.cols <= 16,
      where + ": unexpected matrix size " + std::to_string(m.rows) + "x" + std::to_string(m.cols));
  const tinyxml2::XMLElement* dataNode = e->FirstChildElement("data");
  check(dataNode && dataNode->GetText(), where + ": missing <data>");
  std::istringstream in(dataNode->GetText());
  for (std::string token; in >> token;) {
    double v = 0;
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
    check(ec == std::errc() && ptr == token.data() + token.size() && std::isfinite(v),
          where + ": '" + token + "' is not a number");
    m.data.push_back(v);
  }
  check(m.data.size() == static_cast<size_t>(m.rows * m.cols),
        where + ": expected " + std::to_string(m.rows * m.cols) + " numbers, found " +
            std::to_string(m.data.size()));
  return m;
}

int optionalInteger(const tinyxml2::XMLElement* root, std::initializer_list<const char*> names) {
  const tinyxml2::XMLElement* e = findNode(root, names);
  int value = 0;
  if (e && e->QueryIntText(&value) == tinyxml2::XML_SUCCESS) return value;
  return 0;
}

DatasetCamera readCameraXml(const std::string& file, const std::string& name) {
  tinyxml2::XMLDocument doc;
  const std::vector<uint8_t> bytes = readFileBytes(file, kMaxTextFileBytes, "a calibration file");
  if (doc.Parse(reinterpret_cast<const char*>(bytes.data()), bytes.size()) != tinyxml2::XML_SUCCESS)
    throw Error(file + ":" + std::to_string(doc.ErrorLineNum()) +
                ": invalid XML: " + doc.ErrorStr());
  const tinyxml2::XMLElement* root = doc.RootElement();
  check(root && std::string(root->Name()) == "opencv_storage",
        file + ": not an OpenCV FileStorage file (root element must be <opencv_storage>)");

  auto required = [&](std::initializer_list<const char*> names) {
    const tinyxml2::XMLElement* e = findNode(root, names);
    check(e != nullptr, file + ": missing <" + std::string(*names.begin()) + ">");
    return readMatrix(e, file);
  };
  DatasetCamera dc;
  Camera& c = dc.camera;
  c.name = name;

  const XmlMatrix K = required({"CameraMatrix", "camera_matrix"});
  check(K.rows == 3 && K.cols == 3, file + ": CameraMatrix must be 3x3");
  const std::vector<double>& k = K.data;
  check(k[3] == 0 && k[6] == 0 && k[7] == 0 && k[8] == 1,
        file + ": CameraMatrix must have the form [fx 0 cx; 0 fy cy; 0 0 1]");
  check(std::fabs(k[1]) <= 1e-9 * std::fabs(k[0]),
        file + ": CameraMatrix has a skew term, which the camera model does not support");
  c.fx = k[0], c.cx = k[2], c.fy = k[4], c.cy = k[5];

  if (findNode(root, {"DistortionCoeffs", "distortion_coefficients"})) {
    const XmlMatrix D = required({"DistortionCoeffs", "distortion_coefficients"});
    const size_t n = D.data.size();
    check(n == 4 || n == 5 || n == 8 || n == 12 || n == 14,
          file + ": DistortionCoeffs must hold 4, 5, 8, 12 or 14 values");
    for (size_t i = 5; i < n; ++i)
      check(D.data[i] == 0, file +
                                ": DistortionCoeffs beyond k3 (rational, thin-prism or tilt "
                                "models) are not supported");
    c.distortion = {D.data[0], D.data[1], D.data[2], D.data[3], n >= 5 ? D.data[4] : 0.0};
  }

  const XmlMatrix rotation = required({"Rotation", "rvec", "rotation"});
  if (rotation.data.size() == 3) {
    c.R = rotationFromRodrigues({rotation.data[0], rotation.data[1], rotation.data[2]});
  } else {
    check(rotation.rows == 3 && rotation.cols == 3,
          file + ": Rotation must be a Rodrigues 3-vector or a 3x3 matrix");
    Mat3d R;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        R[i][j] = rotation.data[static_cast<size_t>(3 * i + j)];
    check(isRotation(R, 1e-4), file + ": Rotation is not a rotation matrix");
    c.R = nearestRotation(R);
  }
  const XmlMatrix translation = required({"Translation", "tvec", "translation"});
  check(translation.data.size() == 3, file + ": Translation must hold 3 values");
  c.t = {translation.data[0], translation.data[1], translation.data[2]};

  c.width = optionalInteger(root, {"image_width", "ImageWidth", "width"});
  c.height = optionalInteger(root, {"image_height", "ImageHeight", "height"});
  return dc;
}

// The calibration file of one camera folder: config.xml, else its only *.xml file.
std::string cameraXmlIn(const fs::path& folder) {
  if (fs::is_regular_file(folder / "config.xml")) return (folder / "config.xml").string();
  std::vector<std::string> xml;
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.is_regular_file() && entry.path().extension() == ".xml")
      xml.push_back(entry.path().string());
  if (xml.size() == 1) return xml[0];
  return "";
}

// `path` relative to `folder` (both made absolute first).
std::string relativeTo(const std::string& folder, const fs::path& path) {
  const fs::path absolutePath = fs::absolute(path).lexically_normal();
  const fs::path rel = absolutePath.lexically_relative(fs::absolute(folder).lexically_normal());
  return rel.empty() ? absolutePath.generic_string() : rel.generic_string();
}

}  // namespace

Dataset importOpenCv(const std::string& input, const ImportOptions& options) {
  std::vector<std::pair<std::string, std::string>> cameras;  // name, XML file
  std::error_code ec;
  Dataset d;
  if (fs::is_directory(input, ec)) {
    std::vector<fs::path> folders;
    for (const auto& entry : fs::directory_iterator(input))
      if (entry.is_directory()) folders.push_back(entry.path());
    std::sort(folders.begin(), folders.end());
    for (const fs::path& folder : folders) {
      const std::string xml = cameraXmlIn(folder);
      if (!xml.empty()) cameras.emplace_back(folder.filename().string(), xml);
    }
    check(!cameras.empty(),
          input + ": no camera sub-folders with an OpenCV calibration (config.xml) found");
    d.folder = input;
  } else {
    cameras.emplace_back(fs::path(input).stem().string(), input);
    const fs::path parent = fs::path(input).parent_path();
    d.folder = parent.empty() ? "." : parent.generic_string();
  }
  d.description = "OpenCV XML calibration " + input;

  int64_t frames = -1;
  for (const auto& [name, xml] : cameras) {
    DatasetCamera dc = readCameraXml(xml, name);
    Camera& c = dc.camera;
    const fs::path folder = fs::path(xml).parent_path();
    const fs::path video = folder / options.video;
    const fs::path background = folder / options.backgroundVideo;
    if (!options.images.empty()) {
      checkFramePattern(options.images, "Images");
      const fs::path pattern = folder / options.images;
      // Numbering starts at 0 or 1; the sequence ends at the first missing file.
      const int first = fs::is_regular_file(framePath(pattern.string(), 0), ec) ? 0 : 1;
      int64_t n = 0;
      while (fs::is_regular_file(framePath(pattern.string(), first + static_cast<int>(n)), ec))
        ++n;
      check(n > 0, pattern.string() + ": no images found (numbered from 0 or 1)");
      if (const std::optional<std::string> later =
              firstFileAfter(pattern.string(), first + static_cast<int>(n)))
        warn(*later + " exists, after " + framePath(pattern.string(), first + static_cast<int>(n)) +
             ", which does not exist: the images after that gap are not imported (a sequence "
             "ends at its first missing file); number the files without a gap");
      check(frames < 0 || d.firstFrame == first, pattern.string() + ": numbering starts at " +
                                                     std::to_string(first) +
                                                     " unlike the previous cameras");
      d.firstFrame = first;
      frames = frames < 0 ? n : std::min(frames, n);
      int w = 0, h = 0;
      readPngSize(framePath(pattern.string(), first), w, h);
      check(c.width == 0 || (c.width == w && c.height == h),
            pattern.string() + ": image size differs from the calibration's image size");
      c.width = w;
      c.height = h;
      dc.images = relativeTo(d.folder, pattern);
    } else if (!options.video.empty() && fs::is_regular_file(video, ec)) {
      VideoReader reader(video.string());
      check(c.width == 0 || (c.width == reader.width() && c.height == reader.height()),
            video.string() + ": video size differs from the calibration's image size");
      c.width = reader.width();
      c.height = reader.height();
      // Decoded, not declared: AVI headers may count packets that hold no picture.
      const int64_t n = countVideoFrames(video.string());
      frames = frames < 0 ? n : std::min(frames, n);
      if (reader.frameRate() > 0) d.frameRate = reader.frameRate();
      dc.video = relativeTo(d.folder, video);
    }
    if (!options.backgroundVideo.empty() && fs::is_regular_file(background, ec))
      dc.backgroundVideo = relativeTo(d.folder, background);
    check(!dc.video.empty() || !dc.images.empty(),
          xml + ": no video '" + options.video +
              "' beside the calibration (set --Video to its file name, or --Images)");
    d.cameras.push_back(std::move(dc));
  }
  check(frames > 0, input + ": the videos have no frames");
  check(frames <= (1 << 30), input + ": too many frames");
  d.frameCount = static_cast<int>(frames);
  checkDataset(d, input);
  return d;
}

}  // namespace tdvo
