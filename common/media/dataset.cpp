#include "common/media/dataset.h"

#include <algorithm>

#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/mesh_io.h"
#include "common/core/obj_io.h"
#include "common/core/sequence.h"
#include "common/media/json_text.h"
#include "common/media/png_io.h"
#include "common/media/video_reader.h"

namespace tdvo {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

constexpr const char* kFormatName = "3dvo-dataset";
constexpr int kFormatVersion = 1;

// Reads typed fields of one JSON object, naming the field (JSON-pointer style) in errors, and
// complains about keys that nobody asked for.
class ObjectReader {
 public:
  ObjectReader(const Json& object, std::string where) : object_(object), where_(std::move(where)) {
    check(object.is_object(), where_ + ": must be a JSON object");
  }

  bool has(const char* key) {
    seen_.insert(key);
    return object_.contains(key);
  }
  const Json& get(const char* key) {
    check(has(key), where_ + ": missing field \"" + key + "\"");
    return object_.at(key);
  }
  std::string field(const char* key) const { return where_ + "." + key; }

  double number(const char* key) {
    const Json& v = get(key);
    check(v.is_number() && std::isfinite(v.get<double>()),
          field(key) + ": must be a finite number");
    return v.get<double>();
  }
  double number(const char* key, double fallback) { return has(key) ? number(key) : fallback; }
  int integer(const char* key, int min, int max) {
    const Json& v = get(key);
    check(v.is_number_integer(), field(key) + ": must be an integer");
    // An unsigned JSON integer beyond int64 (2^63 and up) is out of range as it is written.
    const bool huge = v.is_number_unsigned() && v.get<uint64_t>() > uint64_t(INT64_MAX);
    const int64_t i = huge ? INT64_MAX : v.get<int64_t>();
    check(i >= min && i <= max, field(key) + ": " + (huge ? v.dump() : std::to_string(i)) +
                                    " out of range [" + std::to_string(min) + ", " +
                                    std::to_string(max) + "]");
    return static_cast<int>(i);
  }
  int integer(const char* key, int min, int max, int fallback) {
    return has(key) ? integer(key, min, max) : fallback;
  }
  std::string string(const char* key, const std::string& fallback = "") {
    if (!has(key)) return fallback;
    const Json& v = object_.at(key);
    check(v.is_string(), field(key) + ": must be a string");
    return v.get<std::string>();
  }
  bool boolean(const char* key, bool fallback) {
    if (!has(key)) return fallback;
    const Json& v = object_.at(key);
    check(v.is_boolean(), field(key) + ": must be true or false");
    return v.get<bool>();
  }
  std::vector<double> numbers(const char* key, size_t count) {
    const Json& v = get(key);
    check(v.is_array() && v.size() == count,
          field(key) + ": must be an array of " + std::to_string(count) + " numbers");
    std::vector<double> out;
    for (const Json& e : v) {
      check(e.is_number() && std::isfinite(e.get<double>()),
            field(key) + ": must be an array of " + std::to_string(count) + " finite numbers");
      out.push_back(e.get<double>());
    }
    return out;
  }
  void noOtherKeys() const {
    for (auto it = object_.begin(); it != object_.end(); ++it)
      check(seen_.count(it.key()) > 0, where_ + ": unknown field \"" + it.key() + "\"");
  }

 private:
  const Json& object_;
  std::string where_;
  std::set<std::string> seen_;
};

void checkPath(const std::string& path, const std::string& field) {
  if (path.empty()) return;
  if (hasFrameConversion(path)) checkFramePattern(path, field);
}

std::string sizeText(int w, int h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

}  // namespace

bool hasFrameConversion(const std::string& path) {
  for (size_t i = 0; i < path.size(); ++i) {
    if (path[i] != '%') continue;
    if (i + 1 < path.size() && path[i + 1] == '%') {
      ++i;
      continue;
    }
    return true;
  }
  return false;
}

std::string Dataset::resolve(const std::string& path) const {
  if (path.empty() || fs::path(path).is_absolute() || folder.empty()) return path;
  return (fs::path(folder) / path).generic_string();
}

std::string Dataset::framePath(const std::string& pattern, int frame) const {
  check(frame >= 0 && frame < frameCount, "frame index " + std::to_string(frame) +
                                              " out of range (the dataset has " +
                                              std::to_string(frameCount) + " frames)");
  if (!hasFrameConversion(pattern)) return resolve(unescapePercent(pattern));
  return resolve(tdvo::framePath(pattern, firstFrame + frame));
}

namespace {

// The files a dataset names, resolved: each camera's, then the meshes. A sequence is its
// pattern text; a still file or a video its literal path.
struct NamedPath {
  std::string path;
  bool sequence;
};

std::vector<NamedPath> namedPaths(const Dataset& d) {
  std::vector<NamedPath> paths;
  const auto patternText = [&](const std::string& text) {
    if (text.empty()) return;
    if (hasFrameConversion(text))  // the folder's name as pattern text too
      paths.push_back({fs::path(text).is_absolute() || d.folder.empty()
                           ? text
                           : (fs::path(escapePercent(d.folder)) / text).generic_string(),
                       true});
    else
      paths.push_back({d.framePath(text, 0), false});
  };
  for (const DatasetCamera& c : d.cameras) {
    for (const std::string* text : {&c.images, &c.masks, &c.background})
      patternText(*text);
    for (const std::string* video : {&c.video, &c.backgroundVideo})
      if (!video->empty()) paths.push_back({d.resolve(*video), false});
  }
  patternText(d.meshes);
  return paths;
}

}  // namespace

void addDatasetFiles(InputFiles& inputs, const Dataset& d) {
  inputs.add(d.resolve(kDatasetFileName));
  for (const NamedPath& named : namedPaths(d)) {
    if (named.sequence)
      inputs.addPattern(named.path, d.firstFrame, d.frameCount);
    else
      inputs.add(named.path);
  }
}

std::vector<std::string> datasetPaths(const Dataset& d) {
  std::vector<std::string> paths = {d.resolve(kDatasetFileName)};
  for (const NamedPath& named : namedPaths(d)) {
    if (!named.sequence) {
      paths.push_back(named.path);
      continue;
    }
    // The sequence's folder: the path up to the last '/' before the conversion, its "%%" the
    // percent signs they stand for.
    const std::string& path = named.path;
    std::string folder;
    for (size_t i = 0; i < path.size(); ++i) {
      if (path[i] == '%' && i + 1 < path.size() && path[i + 1] == '%') {
        folder += path[i++];
        continue;
      }
      if (path[i] == '%') break;
      folder += path[i];
    }
    const size_t slash = folder.rfind('/');
    paths.push_back(slash == std::string::npos ? "." : slash == 0 ? "/" : folder.substr(0, slash));
  }
  return paths;
}

size_t Dataset::cameraIndex(const std::string& name) const {
  for (size_t i = 0; i < cameras.size(); ++i)
    if (cameras[i].camera.name == name) return i;
  throw Error("dataset has no camera named '" + name + "'");
}

void checkCameraName(const std::string& name, const std::string& where) {
  bool safe = !name.empty() && name != "." && name != ".." && name.size() <= 255;
  for (unsigned char c : name)
    safe = safe && c != '/' && c != '\\' && c >= 0x20 && c != 0x7f;
  // Error shows control characters as \xNN (oneLine): the message stays one line.
  check(safe, where + ": camera name '" + name +
                  "' cannot name a folder (it must be one file name: not '.' or '..', no '/', "
                  "'\\' or control characters, at most 255 bytes)");
}

void checkDataset(const Dataset& d, const std::string& name) {
  check(d.frameCount >= 1, name + ": frames.count must be at least 1");
  check(d.firstFrame >= 0, name + ": frames.first must not be negative");
  check(std::isfinite(d.frameRate) && d.frameRate > 0, name + ": frames.rate must be positive");
  if (d.up) {
    // Its length is computed (normalised for the renderer): squares of components beyond
    // 1e150 overflow, below 1e-150 underflow; such an `up` gave a wrong or no direction.
    const Vec3d& u = *d.up;
    const double largest = std::max({std::fabs(u[0]), std::fabs(u[1]), std::fabs(u[2])});
    check(largest > 0, name + ": up must not be the zero vector");
    check(largest >= 1e-150 && largest <= 1e150,
          name +
              ": up: its largest component must be between 1e-150 and 1e150 in magnitude "
              "(scale it; only its direction counts)");
  }
  checkPath(d.meshes, name + ": meshes");
  check(!d.cameras.empty(), name + ": the dataset has no cameras");
  std::set<std::string> names;
  for (size_t i = 0; i < d.cameras.size(); ++i) {
    const DatasetCamera& dc = d.cameras[i];
    const Camera& c = dc.camera;
    const std::string where = name + ": cameras[" + std::to_string(i) + "]";
    check(!c.name.empty(), where + ".name: must not be empty");
    checkCameraName(c.name, where + ".name");
    check(names.insert(c.name).second, where + ".name: camera name '" + c.name + "' repeats");
    check(c.width >= 1 && c.width <= 32767 && c.height >= 1 && c.height <= 32767,
          where + ": image size " + sizeText(c.width, c.height) + " out of range");
    check(std::isfinite(c.fx) && c.fx > 0 && std::isfinite(c.fy) && c.fy > 0,
          where + ": fx and fy must be positive");
    check(std::isfinite(c.cx) && std::isfinite(c.cy), where + ": cx and cy must be finite");
    const Distortion& k = c.distortion;
    check(std::isfinite(k.k1) && std::isfinite(k.k2) && std::isfinite(k.p1) &&
              std::isfinite(k.p2) && std::isfinite(k.k3),
          where + ".distortion: must be finite");
    check(isRotation(c.R, 1e-6), where + ".R: not a rotation matrix (orthonormal, det +1)");
    check(std::isfinite(c.t[0]) && std::isfinite(c.t[1]) && std::isfinite(c.t[2]),
          where + ".t: must be finite");
    // Camera positions and view directions are computed from t (squares of distances):
    // beyond 1e150 they overflow, and orbits and leave-one-out views failed with messages that
    // named no file.
    check(std::fabs(c.t[0]) <= 1e150 && std::fabs(c.t[1]) <= 1e150 && std::fabs(c.t[2]) <= 1e150,
          where + ".t: components must be within 1e150 in magnitude");
    check(dc.images.empty() != dc.video.empty(),
          where + ": needs exactly one of \"images\" and \"video\"");
    checkPath(dc.images, where + ".images");
    checkPath(dc.masks, where + ".masks");
    checkPath(dc.background, where + ".background");
    check(!(dc.alphaMask && !dc.masks.empty()),
          where + ": \"alphaMask\" and \"masks\" cannot both be given");
    check(!(dc.alphaMask && !dc.video.empty()),
          where + ": \"alphaMask\" needs images with an alpha channel, not a video");
  }
}

Dataset parseDataset(const std::string& text, const std::string& name, const std::string& folder) {
  const Json root = parseJsonText<Json>(text.begin(), text.end(), name);
  Dataset d;
  d.folder = folder;
  ObjectReader top(root, name);
  check(top.string("format") == kFormatName,
        name + ": \"format\" must be \"" + std::string(kFormatName) + "\"");
  const int version = top.integer("version", 1, 1000000);
  check(version == kFormatVersion, name + ": dataset version " + std::to_string(version) +
                                       " is not supported (this build reads version " +
                                       std::to_string(kFormatVersion) + ")");
  d.description = top.string("description");
  {
    ObjectReader frames(top.get("frames"), name + ": frames");
    d.firstFrame = frames.integer("first", 0, 1 << 30, 0);
    d.frameCount = frames.integer("count", 1, 1 << 30);
    d.frameRate = frames.number("rate", 25);
    frames.noOtherKeys();
  }
  if (top.has("up")) {
    const std::vector<double> up = top.numbers("up", 3);
    d.up = Vec3d{up[0], up[1], up[2]};
  }
  d.meshes = top.string("meshes");
  const Json& cameras = top.get("cameras");
  check(cameras.is_array(), name + ": cameras: must be an array");
  for (size_t i = 0; i < cameras.size(); ++i) {
    const std::string where = name + ": cameras[" + std::to_string(i) + "]";
    ObjectReader r(cameras[i], where);
    DatasetCamera dc;
    Camera& c = dc.camera;
    c.name = r.string("name");
    c.width = r.integer("width", 1, 32767);
    c.height = r.integer("height", 1, 32767);
    c.fx = r.number("fx");
    c.fy = r.number("fy");
    c.cx = r.number("cx");
    c.cy = r.number("cy");
    if (r.has("distortion")) {
      const std::vector<double> k = r.numbers("distortion", 5);
      c.distortion = {k[0], k[1], k[2], k[3], k[4]};
    }
    const Json& rows = r.get("R");
    check(rows.is_array() && rows.size() == 3, r.field("R") + ": must be 3 rows of 3 numbers");
    for (size_t row = 0; row < 3; ++row) {
      check(rows[row].is_array() && rows[row].size() == 3,
            r.field("R") + ": must be 3 rows of 3 numbers");
      for (size_t col = 0; col < 3; ++col) {
        check(rows[row][col].is_number() && std::isfinite(rows[row][col].get<double>()),
              r.field("R") + ": must be 3 rows of 3 finite numbers");
        c.R[row][col] = rows[row][col].get<double>();
      }
    }
    const std::vector<double> t = r.numbers("t", 3);
    c.t = {t[0], t[1], t[2]};
    dc.images = r.string("images");
    dc.video = r.string("video");
    dc.masks = r.string("masks");
    dc.alphaMask = r.boolean("alphaMask", false);
    dc.background = r.string("background");
    dc.backgroundVideo = r.string("backgroundVideo");
    if (r.has("textureBox")) {
      const Json& b = r.get("textureBox");
      const std::string what = r.field("textureBox") +
                               ": must be [x, y, width, height], integers with x, y >= 0 and "
                               "width, height >= 1";
      check(b.is_array() && b.size() == 4, what);
      std::array<int, 4> box{};
      for (size_t k = 0; k < 4; ++k) {
        check(b[k].is_number_integer(), what);
        const int64_t v = b[k].get<int64_t>();
        check(v >= (k < 2 ? 0 : 1) && v <= 65535, what);
        box[k] = static_cast<int>(v);
      }
      dc.textureBox = box;
    }
    r.noOtherKeys();
    d.cameras.push_back(std::move(dc));
  }
  top.noOtherKeys();
  checkDataset(d, name);
  return d;
}

Dataset readDataset(const std::string& folderOrFile) {
  fs::path file = folderOrFile;
  std::error_code ec;
  if (fs::is_directory(file, ec)) file /= kDatasetFileName;
  const std::vector<uint8_t> bytes =
      readFileBytes(file.string(), kMaxTextFileBytes, "a dataset file");
  std::string folder = file.parent_path().generic_string();
  if (folder.empty()) folder = ".";
  return parseDataset(std::string(bytes.begin(), bytes.end()), file.string(), folder);
}

namespace {

// JSON text of one value (strings escaped, doubles in the shortest form that reads back
// exactly; -0.0 stays -0.0: what was read is written).
std::string jsonValue(double v) {
  return Json(v).dump();
}
std::string jsonValue(int v) {
  return Json(v).dump();
}
std::string jsonValue(const std::string& v) {
  try {
    return Json(v).dump();
  } catch (const Json::type_error&) {  // not UTF-8: JSON text cannot hold it
    // (Error shows the bytes that are not UTF-8 as \xNN.)
    throw Error("'" + v + "' is not UTF-8 text, which a dataset.json (JSON) cannot hold; " +
                "rename the file, folder or camera");
  }
}
template <size_t N>
std::string jsonArray(const std::array<double, N>& values) {
  std::string out = "[";
  for (size_t i = 0; i < N; ++i)
    out += (i ? ", " : "") + jsonValue(values[i]);
  return out + "]";
}

// Writes `"key": value` members of one object, one per line, at a given indentation.
class ObjectWriter {
 public:
  ObjectWriter(std::string& out, int indent) : out_(out), indent_(indent) { out_ += "{"; }
  void member(const char* key, const std::string& valueText) {
    out_ += (first_ ? "\n" : ",\n") + std::string(static_cast<size_t>(indent_ + 2), ' ') +
            jsonValue(std::string(key)) + ": " + valueText;
    first_ = false;
  }
  void close() { out_ += "\n" + std::string(static_cast<size_t>(indent_), ' ') + "}"; }

 private:
  std::string& out_;
  int indent_;
  bool first_ = true;
};

}  // namespace

std::string formatDataset(const Dataset& d, const std::string& outputFolder) {
  checkDataset(d, "dataset");
  // Paths are relative to d.folder, a literal folder name. Image, mask, background and mesh
  // paths are pattern text ("%%" a percent sign), video paths literal. Both folders are taken
  // as they are on disk (links resolved, so that ".." leads where the file system's ".."
  // does), and written as the field's kind of text.
  const auto real = [](const std::string& folder) {
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(fs::absolute(folder), ec);
    return (ec ? fs::absolute(folder).lexically_normal() : canonical).generic_string();
  };
  const std::string base = real(outputFolder), from = real(d.folder);
  auto relative = [&](const std::string& path, bool patternText) -> std::string {
    if (fs::path(path).is_absolute()) return jsonValue(path);
    const auto text = [&](const std::string& folder) {
      return fs::path(patternText ? escapePercent(folder) : folder);
    };
    const fs::path absolutePath = (text(from) / path).lexically_normal();
    const fs::path baseText = text(base);
    // Relative only when both lie under the same top-level folder: "../../work/…" from /tmp
    // would be correct but would break as soon as either side moves.
    auto top = [](const fs::path& p) {
      auto it = p.begin();
      return ++it == p.end() ? fs::path() : *it;  // the component after the root
    };
    const fs::path rel = absolutePath.lexically_relative(baseText);
    const bool sameTop = top(absolutePath) == top(baseText);
    return jsonValue(rel.empty() || !sameTop ? absolutePath.generic_string()
                                             : rel.generic_string());
  };
  std::string out;
  ObjectWriter top(out, 0);
  top.member("format", jsonValue(std::string(kFormatName)));
  top.member("version", jsonValue(kFormatVersion));
  if (!d.description.empty()) top.member("description", jsonValue(d.description));
  top.member("frames", "{\"first\": " + jsonValue(d.firstFrame) + ", \"count\": " +
                           jsonValue(d.frameCount) + ", \"rate\": " + jsonValue(d.frameRate) + "}");
  if (d.up) top.member("up", jsonArray(*d.up));
  if (!d.meshes.empty()) top.member("meshes", relative(d.meshes, true));
  std::string cameras = "[";
  for (size_t i = 0; i < d.cameras.size(); ++i) {
    const DatasetCamera& dc = d.cameras[i];
    const Camera& c = dc.camera;
    cameras += i ? ",\n    " : "\n    ";
    ObjectWriter j(cameras, 4);
    j.member("name", jsonValue(c.name));
    j.member("width", jsonValue(c.width));
    j.member("height", jsonValue(c.height));
    j.member("fx", jsonValue(c.fx));
    j.member("fy", jsonValue(c.fy));
    j.member("cx", jsonValue(c.cx));
    j.member("cy", jsonValue(c.cy));
    if (!c.distortion.isZero()) {
      const Distortion& k = c.distortion;
      j.member("distortion", "[" + jsonValue(k.k1) + ", " + jsonValue(k.k2) + ", " +
                                 jsonValue(k.p1) + ", " + jsonValue(k.p2) + ", " + jsonValue(k.k3) +
                                 "]");
    }
    j.member("R", "[" + jsonArray(c.R[0]) + ",\n" + std::string(12, ' ') + jsonArray(c.R[1]) +
                      ",\n" + std::string(12, ' ') + jsonArray(c.R[2]) + "]");
    j.member("t", jsonArray(c.t));
    if (!dc.images.empty()) j.member("images", relative(dc.images, true));
    if (!dc.video.empty()) j.member("video", relative(dc.video, false));
    if (!dc.masks.empty()) j.member("masks", relative(dc.masks, true));
    if (dc.alphaMask) j.member("alphaMask", "true");
    if (!dc.background.empty()) j.member("background", relative(dc.background, true));
    if (!dc.backgroundVideo.empty())
      j.member("backgroundVideo", relative(dc.backgroundVideo, false));
    if (dc.textureBox) {
      const std::array<int, 4>& b = *dc.textureBox;
      j.member("textureBox", "[" + jsonValue(b[0]) + ", " + jsonValue(b[1]) + ", " +
                                 jsonValue(b[2]) + ", " + jsonValue(b[3]) + "]");
    }
    j.close();
  }
  cameras += d.cameras.empty() ? "]" : "\n  ]";
  top.member("cameras", cameras);
  top.close();
  return out + "\n";
}

void writeDataset(const Dataset& dataset, const std::string& outputFolder) {
  const std::string text = formatDataset(dataset, outputFolder);
  makeDirectories(outputFolder);
  writeFileAtomic((fs::path(outputFolder) / kDatasetFileName).string(), text);
}

namespace {

void checkPngFrames(const Dataset& d, const std::string& pattern, const Camera& c,
                    const std::string& what) {
  if (pattern.empty()) return;
  const int frames = hasFrameConversion(pattern) ? d.frameCount : 1;
  for (int i = 0; i < frames; ++i) {
    const std::string path = d.framePath(pattern, i);
    int w = 0, h = 0;
    try {
      readPngSize(path, w, h);
    } catch (const Error& e) {
      throw Error("camera '" + c.name + "' " + what + ": " + e.what());
    }
    check(w == c.width && h == c.height, path + ": " + what + " is " + sizeText(w, h) +
                                             " but camera '" + c.name + "' is " +
                                             sizeText(c.width, c.height));
  }
}

void checkVideo(const Dataset& d, const std::string& path, const Camera& c, int64_t framesNeeded,
                const std::string& what) {
  if (path.empty()) return;
  const std::string file = d.resolve(path);
  VideoReader reader(file);
  check(reader.width() == c.width && reader.height() == c.height,
        file + ": " + what + " is " + sizeText(reader.width(), reader.height()) + " but camera '" +
            c.name + "' is " + sizeText(c.width, c.height));
  const int64_t declared = reader.declaredFrameCount();
  check(declared < 0 || declared >= framesNeeded,
        file + ": " + what + " has " + std::to_string(declared) + " frames, the dataset needs " +
            std::to_string(framesNeeded));
}

}  // namespace

void validateDatasetFiles(const Dataset& d) {
  checkDataset(d, "dataset");
  for (const DatasetCamera& dc : d.cameras) {
    checkPngFrames(d, dc.images, dc.camera, "image");
    checkPngFrames(d, dc.masks, dc.camera, "mask");
    checkPngFrames(d, dc.background, dc.camera, "background");
    checkVideo(d, dc.video, dc.camera, int64_t(d.firstFrame) + d.frameCount, "video");
    checkVideo(d, dc.backgroundVideo, dc.camera, 1, "background video");
  }
  if (!d.meshes.empty()) {
    const int frames = hasFrameConversion(d.meshes) ? d.frameCount : 1;
    for (int i = 0; i < frames; ++i) {
      const std::string path = d.framePath(d.meshes, i);
      std::error_code ec;
      check(fs::is_regular_file(path, ec), path + ": ground-truth mesh file is missing");
    }
  }
}

CameraFrames::CameraFrames(const Dataset& dataset, size_t camera)
    : dataset_(&dataset), camera_(camera) {
  check(camera < dataset.cameras.size(), "camera index " + std::to_string(camera) +
                                             " out of range (the dataset has " +
                                             std::to_string(dataset.cameras.size()) + " cameras)");
}

CameraFrames::~CameraFrames() = default;
CameraFrames::CameraFrames(CameraFrames&&) noexcept = default;

Image CameraFrames::frame(int index) {
  const DatasetCamera& dc = dataset_->cameras[camera_];
  const Camera& c = dc.camera;
  Image image;
  std::string source;
  if (!dc.images.empty()) {
    source = dataset_->framePath(dc.images, index);
    image = readPng(source);
  } else {
    check(index >= 0 && index < dataset_->frameCount,
          "frame index " + std::to_string(index) + " out of range");
    source = dataset_->resolve(dc.video);
    const int64_t target = int64_t(dataset_->firstFrame) + index;
    if (!video_ || video_->position() > target) video_ = std::make_unique<VideoReader>(source);
    bool ok = true;
    while (ok && video_->position() < target)
      ok = video_->skip();
    ok = ok && video_->read(image);
    check(ok, source + ": the video ends after " + std::to_string(video_->position()) +
                  " frames; frame " + std::to_string(target) + " is needed");
  }
  check(image.width == c.width && image.height == c.height,
        source + ": image is " + sizeText(image.width, image.height) + " but camera '" + c.name +
            "' is " + sizeText(c.width, c.height));
  return image;
}

bool CameraFrames::hasMasks() const {
  const DatasetCamera& dc = dataset_->cameras[camera_];
  return !dc.masks.empty() || dc.alphaMask;
}

Image CameraFrames::mask(int index) {
  const DatasetCamera& dc = dataset_->cameras[camera_];
  const Camera& c = dc.camera;
  check(hasMasks(), "camera '" + c.name + "' has no masks");
  Image source;
  int channel = 0;
  std::string name;
  if (dc.alphaMask) {
    source = frame(index);
    name = dc.images;
    check(source.channels == 2 || source.channels == 4,
          dataset_->framePath(dc.images, index) + ": \"alphaMask\" is set but the image has no " +
              "alpha channel");
    channel = source.channels - 1;
  } else {
    name = dataset_->framePath(dc.masks, index);
    source = readPng(name);
    check(source.width == c.width && source.height == c.height,
          name + ": mask is " + sizeText(source.width, source.height) + " but camera '" + c.name +
              "' is " + sizeText(c.width, c.height));
  }
  Image mask(source.width, source.height, 1);
  for (size_t i = 0; i < mask.pixels.size(); ++i)
    mask.pixels[i] =
        source.pixels[i * static_cast<size_t>(source.channels) + static_cast<size_t>(channel)] >=
                128
            ? 255
            : 0;
  return mask;
}

Mesh readDatasetMesh(const Dataset& dataset, int frame) {
  check(!dataset.meshes.empty(), "the dataset has no ground-truth meshes");
  return readMesh(dataset.framePath(dataset.meshes, frame));
}

}  // namespace tdvo
