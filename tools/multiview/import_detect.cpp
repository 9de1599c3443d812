// Recognising an input's format, and the one entry point that imports anything.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>

#include "common/core/error.h"
#include "tools/multiview/importers.h"

namespace tdvo {

namespace fs = std::filesystem;

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The files of a folder whose names satisfy `accept`, sorted.
template <class Accept>
std::vector<fs::path> filesIn(const fs::path& folder, Accept accept) {
  std::vector<fs::path> out;
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.is_regular_file() && accept(entry.path().filename().string()))
      out.push_back(entry.path());
  std::sort(out.begin(), out.end());
  return out;
}

bool isParFile(const std::string& name) {
  return endsWith(name, "_par.txt");
}
bool isTransformsFile(const std::string& name) {
  return name.rfind("transforms", 0) == 0 && endsWith(name, ".json");
}

// The calibration file inside a folder for the formats that have one file (or "" when none).
std::string singleFileIn(const fs::path& folder, ImportFormat format) {
  if (format == ImportFormat::dataset) {
    const fs::path p = folder / kDatasetFileName;
    return fs::is_regular_file(p) ? p.string() : "";
  }
  if (format == ImportFormat::middlebury) {
    const auto files = filesIn(folder, isParFile);
    check(files.size() <= 1, folder.string() + ": holds several *_par.txt files; name one");
    return files.empty() ? "" : files[0].string();
  }
  if (format == ImportFormat::nerf) {
    // transforms_train.json is the one with the training views the NeRF sets publish.
    if (fs::is_regular_file(folder / "transforms_train.json"))
      return (folder / "transforms_train.json").string();
    if (fs::is_regular_file(folder / "transforms.json"))
      return (folder / "transforms.json").string();
    const auto files = filesIn(folder, isTransformsFile);
    return files.empty() ? "" : files[0].string();
  }
  return "";
}

bool hasOpenCvCameraFolders(const fs::path& folder) {
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.is_directory() &&
        !filesIn(entry.path(), [](const std::string& n) { return endsWith(n, ".xml"); }).empty())
      return true;
  return false;
}

}  // namespace

Vec3d parseVector3(const std::string& text, const std::string& what) {
  Vec3d v;
  size_t start = 0;
  for (int i = 0; i < 3; ++i) {
    const size_t comma = i < 2 ? text.find(',', start) : text.size();
    check(comma != std::string::npos, what + ": '" + text + "' is not 'x,y,z'");
    const std::string token = text.substr(start, comma - start);
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), v[i]);
    check(!token.empty() && ec == std::errc() && ptr == token.data() + token.size() &&
              std::isfinite(v[i]),
          what + ": '" + text + "' is not 'x,y,z'");
    start = comma + 1;
  }
  return v;
}

Vec3d parseDirection(const std::string& text, const std::string& what) {
  const Vec3d v = parseVector3(text, what);
  check(v[0] != 0 || v[1] != 0 || v[2] != 0,
        what + ": '" + text + "' is the zero vector, which has no direction");
  return v;
}

ImportFormat detectImportFormat(const std::string& input) {
  std::error_code ec;
  const fs::path path(input);
  if (fs::is_regular_file(path, ec)) {
    const std::string name = path.filename().string();
    if (name == kDatasetFileName) return ImportFormat::dataset;
    if (isParFile(name)) return ImportFormat::middlebury;
    if (endsWith(name, ".json")) return ImportFormat::nerf;
    if (endsWith(name, ".xml")) return ImportFormat::opencv;
    throw Error(input +
                ": unknown calibration format (expected dataset.json, *_par.txt, "
                "transforms*.json or an OpenCV *.xml)");
  }
  check(fs::is_directory(path, ec), input + ": no such file or folder");
  for (ImportFormat f : {ImportFormat::dataset, ImportFormat::middlebury, ImportFormat::nerf})
    if (!singleFileIn(path, f).empty()) return f;
  if (hasOpenCvCameraFolders(path)) return ImportFormat::opencv;
  throw Error(input +
              ": no calibration found (looked for dataset.json, *_par.txt, "
              "transforms*.json, and sub-folders with an OpenCV *.xml)");
}

Dataset importAny(const std::string& input, const ImportOptions& options) {
  const ImportFormat format =
      options.format == ImportFormat::automatic ? detectImportFormat(input) : options.format;
  std::error_code ec;
  std::string file = input;
  if (format != ImportFormat::opencv && fs::is_directory(input, ec)) {
    file = singleFileIn(input, format);
    check(!file.empty(), input + ": no calibration file of the requested format in this folder");
  }
  Dataset d;
  switch (format) {
    case ImportFormat::dataset:
      d = readDataset(file);
      break;
    case ImportFormat::middlebury:
      d = importMiddlebury(file);
      break;
    case ImportFormat::nerf:
      d = importNerf(file);
      break;
    default:
      d = importOpenCv(input, options);
      break;
  }
  if (!options.up.empty()) d.up = parseDirection(options.up, "Up");
  return d;
}

}  // namespace tdvo
