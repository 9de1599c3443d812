// 3dvo-render: view-dependent rendering of a dataset-layout folder (a dataset, or a decoded 3DVO)
// from virtual cameras; leave-one-out quality. docs/rendering.md.
//
//   3dvo-render -i DATA -o out/                          36 views within the cameras' arc, PNGs
//   3dvo-render -i DATA -o out/ --Mp4=orbit.mp4          ... and an MP4
//   3dvo-render -i DATA -o out/ --Path=camera --Camera=cam03     every frame from cam03's pose
//   3dvo-render -i DATA --Mode=leave-one-out             PSNR table on stdout
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include "common/core/app.h"
#include "common/core/config.h"
#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/progress.h"
#include "common/core/sequence.h"
#include "common/media/media_version.h"
#include "common/media/png_io.h"
#include "tools/multiview/importers.h"
#include "tools/render/camera_path.h"
#include "tools/render/leave_one_out.h"
#include "tools/render/mp4_writer.h"
#include "tools/render/view_renderer.h"

using namespace tdvo;
namespace fs = std::filesystem;

namespace {

enum class Mode { render, leaveOneOut };
enum class PathKind { orbit, poses, camera };

struct Params {
  std::string input, cameras, reference;
  int cameraStep = 1, firstFrame = 0, frameCount = 0;
  Mode mode = Mode::render;
  RenderOptions render;
  std::string fallbackColour = "128,128,128", background = "0,0,0";
  PathKind path = PathKind::orbit;
  std::string camera, poses, orbitElevation = "auto", orbitTurns = "auto";
  int orbitSteps = 36, frame = -1, width = 0, height = 0;
  double orbitDistance = 0, fieldOfView = 0;
  std::string output, outputPattern = "%04d.png", mp4, csv;
  int crf = 18;
  bool saveRenders = false, overwrite = false;

  void registerOptions(OptionTable& t) {
    t.section("Input");
    t.add("Input", input, "dataset folder or dataset.json (a dataset or a decoded 3DVO)", "-i");
    t.add("Cameras", cameras,
          "comma-separated camera names to use (empty: all); the other cameras are ignored");
    t.add("CameraStep", cameraStep, 1, 100000, "use every n-th of those cameras");
    t.add("FirstFrame", firstFrame, 0, 1 << 30, "first frame index to use");
    t.add("FrameCount", frameCount, 0, 1 << 30, "frames to use (0: to the end)");
    t.add("Reference", reference,
          "Mode=leave-one-out: dataset whose images and masks the held-out renders are compared "
          "with (cameras by name, frames by frame number), e.g. the original of a decoded 3DVO "
          "given as Input; empty: Input's own");
    t.section("Mode");
    t.addEnum("Mode", mode, {{"render", Mode::render}, {"leave-one-out", Mode::leaveOneOut}},
              "render a camera path; leave-one-out PSNR and SSIM per camera");
    t.section("Weights and visibility");
    t.addEnum("Blending", render.blending, {{"angle", Blending::angle}, {"ulr", Blending::ulr}},
              "camera weights: angle, w_i ~ sin(theta_i/2)^-k; or ulr, the angle term with a "
              "resolution penalty times a factor rising from 0 at camera i's silhouette and "
              "depth edges over EdgeWidth pixels (docs/rendering.md, \"Blending\")");
    t.addEnum("ViewDirection", render.direction,
              {{"axis", ViewDirection::axis}, {"ray", ViewDirection::ray}},
              "directions whose angle makes the weights: the optical axes (axis, as in the "
              "source paper) or, per surface point, the directions to the camera centres (ray)");
    t.add("Sharpness", render.sharpness, 0.01, 1000,
          "k in w_i ~ (1 - cos theta_i)^(-k/2): larger favours the nearest camera more");
    t.add("ResolutionPenalty", render.resolutionPenalty, 0, 1000,
          "Blending=ulr: beta in s_i * (1 + beta * max(0, r_i - 1)), r_i camera i's texel "
          "footprint at the point over the view's pixel footprint");
    t.add("EdgeWidth", render.edgeWidth, 0, kMaxEdgeWidth,
          "Blending=ulr: pixels from camera i's silhouette or depth edge over which its weight "
          "rises from 0 to full (0: no edge factor)");
    t.add("DepthTolerance", render.depthTolerance, 0, 10,
          "relative depth tolerance of the visibility test (0.01: 1 % of the depth)");
    t.addEnum(
        "Fallback", render.fallback,
        {{"nearest", Fallback::nearest}, {"colour", Fallback::colour}, {"fill", Fallback::fill}},
        "where no camera sees a point: the nearest camera ignoring depth, the flat "
        "FallbackColour, or fill from the neighbouring blended pixels (push-pull)");
    t.add("FallbackColour", fallbackColour, "flat fallback colour r,g,b");
    t.add("Background", background, "colour r,g,b of pixels the mesh does not cover (alpha 0)");
    t.section("Camera path (Mode=render)");
    t.addEnum(
        "Path", path,
        {{"orbit", PathKind::orbit}, {"poses", PathKind::poses}, {"camera", PathKind::camera}},
        "views around the object (within the cameras' arc unless OrbitTurns says), poses from a "
        "file, or one dataset camera's pose for every frame");
    t.add("Camera", camera, "Path=camera: the camera's name");
    t.add("Poses", poses,
          "Path=poses: text file of 'eye target [up]' lines, or a dataset.json whose cameras are "
          "the poses");
    t.add("OrbitSteps", orbitSteps, 1, 1000000, "Path=orbit: number of views");
    t.add("OrbitElevation", orbitElevation,
          "Path=orbit: degrees above the object's centre, or 'auto' (the cameras' mean)");
    t.add("OrbitDistance", orbitDistance, 0, 1e12,
          "Path=orbit: distance from the centre (0: the cameras' mean)");
    t.add("OrbitTurns", orbitTurns,
          "Path=orbit: full turns over the views (-1000..1000, negative: clockwise), or 'auto': "
          "from one end of the arc the cameras span about the up axis to the other, a full turn "
          "when they surround the object (docs/rendering.md, \"Camera paths\")");
    t.add("Frame", frame, -1, 1 << 30,
          "frame index to show on every view of an orbit or pose list (-1: advance one frame per "
          "view, looping)");
    t.add("Width", width, 0, kMaxViewSize, "virtual image width (0: camera 0's)");
    t.add("Height", height, 0, kMaxViewSize, "virtual image height (0: camera 0's)");
    t.add("FieldOfView", fieldOfView, 0, 170,
          "virtual horizontal field of view, degrees (0: camera 0's focal length)");
    t.section("Output");
    t.add("Output", output,
          "folder for the PNG sequence (render) or the held-out renders (leave-one-out, with "
          "SaveRenders)",
          "-o");
    t.add("Overwrite", overwrite,
          "replace the contents of a non-empty output folder (without it such a folder is refused)",
          "--Overwrite");
    t.add("OutputPattern", outputPattern, "PNG file name pattern inside Output");
    t.add("Mp4", mp4, "Mode=render: also write this H.264 MP4 file");
    t.add("Crf", crf, 0, 51, "x264 constant rate factor of the MP4");
    t.add("Csv", csv, "Mode=leave-one-out: also write the table as CSV");
    t.add("SaveRenders", saveRenders, "Mode=leave-one-out: write the held-out renders to Output");
  }
};

std::array<uint8_t, 3> parseColour(const std::string& text, const std::string& key) {
  const Vec3d v = parseVector3(text, key);
  std::array<uint8_t, 3> c{};
  for (size_t i = 0; i < 3; ++i) {
    check(v[i] >= 0 && v[i] <= 255 && v[i] == std::floor(v[i]),
          key + ": '" + text + "' must be three integers in 0..255");
    c[i] = static_cast<uint8_t>(v[i]);
  }
  return c;
}

// A key that takes 'auto' (none) or a number in lo..hi.
std::optional<double> parseAuto(const std::string& text, const std::string& key,
                                const std::string& unit, double lo, double hi) {
  if (text == "auto") return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  char range[64];
  std::snprintf(range, sizeof range, "%g..%g", lo, hi);
  check(end != text.c_str() && *end == 0 && v >= lo && v <= hi,
        key + ": '" + text + "' must be 'auto' or " + unit + " in " + range);
  return v;
}

// The line saying which path OrbitTurns=auto takes.
std::string describeArc(const CameraArc& arc) {
  constexpr double kDegrees = 180 / 3.14159265358979323846;
  char line[200];
  if (arc.surrounds)
    std::snprintf(line, sizeof line,
                  "3dvo-render: orbit: a full turn (the cameras surround the object; widest "
                  "gap between them %.1f degrees)",
                  arc.widestGap * kDegrees);
  else
    std::snprintf(line, sizeof line,
                  "3dvo-render: orbit: within the cameras' arc of %.1f degrees (OrbitTurns gives "
                  "full turns)",
                  arc.span * kDegrees);
  return line;
}

// The dataset restricted to the cameras named in `names` (all when empty), every `step`-th.
Dataset selectCameras(Dataset d, const std::string& names, int step) {
  if (!names.empty()) {
    std::vector<DatasetCamera> chosen;
    std::stringstream list(names);
    std::string name;
    std::set<std::string> named;
    while (std::getline(list, name, ',')) {
      if (name.empty()) continue;
      // Twice the same camera would hold it out and render it from itself (leave-one-out).
      check(named.insert(name).second, "Cameras: '" + name + "' is named twice");
      chosen.push_back(d.cameras[d.cameraIndex(name)]);
    }
    d.cameras = chosen;
  }
  std::vector<DatasetCamera> kept;
  for (size_t i = 0; i < d.cameras.size(); i += static_cast<size_t>(step))
    kept.push_back(d.cameras[i]);
  d.cameras = kept;
  check(!d.cameras.empty(), "no cameras selected");
  return d;
}

FrameRange selectFrames(const Dataset& d, int first, int count) {
  check(first < d.frameCount, "FirstFrame " + std::to_string(first) + " is beyond the dataset's " +
                                  std::to_string(d.frameCount) + " frames");
  const int64_t last = count > 0 ? int64_t{first} + count : d.frameCount;
  check(last <= d.frameCount, "FirstFrame + FrameCount is beyond the dataset's " +
                                  std::to_string(d.frameCount) + " frames");
  return {first, static_cast<int>(last - first)};
}

// An output file (Mp4, Csv) may not replace an input (docs/user-guide.md, "Output files"),
// under any name or link: `files` (the cfg files, the poses), and every file of each dataset
// (addDatasetFiles: its dataset.json, meshes and camera files, of every frame and camera).
void checkNotAnInput(const std::string& output, const std::vector<const Dataset*>& datasets,
                     const std::vector<std::string>& files) {
  if (output.empty()) return;
  InputFiles inputs;
  for (const std::string& file : files)
    inputs.add(file);
  for (const Dataset* d : datasets)
    addDatasetFiles(inputs, *d);
  inputs.checkOutput(output);
}

// What an output folder replaced with --Overwrite may not hold: `files` and the datasets'
// files and sequence folders (datasetPaths).
std::vector<std::string> protectedPaths(const std::vector<const Dataset*>& datasets,
                                        std::vector<std::string> files) {
  for (const Dataset* d : datasets)
    for (std::string& path : datasetPaths(*d))
      files.push_back(std::move(path));
  return files;
}

void runRender(const Params& p, const Dataset& d, const FrameRange& frames,
               const std::vector<std::string>& inputs) {
  check(!p.output.empty(), "no output folder given (-o DIR)");
  checkOutputFramePattern(p.outputPattern, "OutputPattern");
  std::vector<CameraFrames> cameraFrames;
  for (size_t i = 0; i < d.cameras.size(); ++i)
    cameraFrames.emplace_back(d, i);

  // The virtual cameras, and the frame shown on each: view k is views[k % views.size()] on
  // frame viewFrame(k), for k < viewCount (a camera path is one camera over the frames; nothing
  // is held per frame, so a dataset's frame count costs no memory).
  std::vector<Camera> views;
  size_t viewCount = 0;
  std::function<int(size_t)> viewFrame;
  const Camera intrinsics = virtualIntrinsics(d, p.width, p.height, p.fieldOfView);
  if (p.path == PathKind::camera) {
    check(!p.camera.empty(), "Path=camera needs --Camera=NAME");
    const auto chosen = std::find_if(d.cameras.begin(), d.cameras.end(),
                                     [&](const auto& c) { return c.camera.name == p.camera; });
    check(chosen != d.cameras.end(), "Camera: '" + p.camera + "' is not among the cameras " +
                                         (p.cameras.empty() && p.cameraStep == 1
                                              ? std::string("of the dataset")
                                              : std::string("selected (Cameras, CameraStep)")));
    views = {chosen->camera};
    viewCount = static_cast<size_t>(frames.count);
    viewFrame = [&frames](size_t k) { return frames[k]; };
  } else {
    const Vec3d up = datasetUp(d);
    if (p.path == PathKind::orbit) {
      OrbitParams orbit;
      orbit.steps = p.orbitSteps;
      orbit.distance = p.orbitDistance;
      orbit.turns = parseAuto(p.orbitTurns, "OrbitTurns", "turns", -1000, 1000);
      orbit.elevation = parseAuto(p.orbitElevation, "OrbitElevation", "degrees", -90, 90);
      const Vec3d centre = boundingBoxCentre(readDatasetMesh(d, frames.first));
      if (!orbit.turns) std::puts(describeArc(cameraArc(d, centre, up)).c_str());
      views = orbitPath(d, centre, up, intrinsics, orbit);
    } else {
      check(!p.poses.empty(), "Path=poses needs --Poses=FILE");
      views = readPoses(p.poses, intrinsics, up);
    }
    if (p.frame >= 0)
      check(p.frame < d.frameCount, "Frame " + std::to_string(p.frame) + " is beyond the " +
                                        std::to_string(d.frameCount) + " frames");
    viewCount = views.size();
    viewFrame = [&p, &frames](size_t k) {
      return p.frame >= 0 ? p.frame : frames[k % static_cast<size_t>(frames.count)];
    };
  }

  // The MP4 may not be one of the views written into the folder.
  InputFiles written;
  written.addPattern((fs::path(p.output) / p.outputPattern).string(), 0,
                     static_cast<int>(viewCount), "this run's output");
  written.checkOutput(p.mp4);
  OutputFolder files(p.output, p.overwrite, inputs);
  std::unique_ptr<Mp4Writer> mp4;
  std::optional<FrameViews> loaded;
  int loadedFrame = -1;
  RenderStats stats;
  Progress progress("3dvo-render: rendering", viewCount);
  for (size_t k = 0; k < viewCount; ++k) {
    if (viewFrame(k) != loadedFrame) {
      loadedFrame = viewFrame(k);
      loaded = loadFrameViews(d, cameraFrames, loadedFrame);
    }
    const Image image = renderView(*loaded, views[k % views.size()], p.render, {}, &stats);
    const std::vector<uint8_t> png = encodePng(image);
    files.write((fs::path(p.output) / framePath(p.outputPattern, static_cast<int>(k))).string(),
                png.data(), png.size());
    if (!p.mp4.empty()) {
      if (!mp4)
        mp4 = std::make_unique<Mp4Writer>(p.mp4, image.width, image.height, d.frameRate, p.crf);
      mp4->write(image);
    }
    progress.tick(k + 1);
  }
  // The folder first: an MP4 inside it, made during the run, stays; one from a previous run
  // goes with the folder's previous contents and is then replaced by this run's.
  // Every output written and closed before any is put in place: an MP4 that cannot be
  // finished leaves the output folder as it was.
  if (mp4) mp4->close();
  if (mp4)
    commitAll({&files, &mp4->file()});
  else
    files.commit();
  const double covered = stats.covered ? double(stats.covered) : 1.0;
  std::printf(
      "3dvo-render: wrote %zu views to %s%s%s; of %zu object pixels %.2f %% blended, %.2f %% "
      "nearest-camera fallback, %.2f %% flat fallback, %.2f %% filled\n",
      viewCount, p.output.c_str(), p.mp4.empty() ? "" : " and ", p.mp4.c_str(), stats.covered,
      100.0 * stats.blended / covered, 100.0 * stats.fallbackNearest / covered,
      100.0 * stats.fallbackColour / covered, 100.0 * stats.fallbackFill / covered);
}

}  // namespace

int main(int argc, char** argv) {
  return runApp("3dvo-render", [&]() {
    Params p;
    OptionTable table("3dvo-render",
                      "3dvo-render -i DATASET [-o OUT] [-c render.cfg] [--Key=value ...]");
    p.registerOptions(table);
    table.addVersionLines(mediaLibraryVersions());
    if (!table.parseCommandLine(argc, argv)) return 0;
    check(!p.input.empty(), "no input dataset given (-i DATASET); see --help");
    p.render.fallbackColour = parseColour(p.fallbackColour, "FallbackColour");
    p.render.background = parseColour(p.background, "Background");
    const Dataset full = readDataset(p.input);
    const Dataset d = selectCameras(full, p.cameras, p.cameraStep);
    check(!d.meshes.empty(), p.input + ": the dataset has no meshes; the renderer needs the " +
                                 "object's surface (\"meshes\" in dataset.json)");
    const FrameRange frames = selectFrames(d, p.firstFrame, p.frameCount);
    std::vector<std::string> inputFiles = table.filesRead();
    inputFiles.push_back(p.poses);

    if (p.mode == Mode::render) {
      // Keys of the other mode are an error, not silently ignored.
      check(p.csv.empty(), "Csv is for Mode=leave-one-out (Mode=render writes views, and Mp4)");
      check(!p.saveRenders, "SaveRenders is for Mode=leave-one-out");
      check(p.reference.empty(), "Reference is for Mode=leave-one-out");
      checkNotAnInput(p.mp4, {&full}, inputFiles);
      if (!p.mp4.empty()) checkMp4FrameRate(d.frameRate, p.mp4);  // before any view is rendered
      inputFiles.push_back(p.input);
      runRender(p, d, frames, protectedPaths({&full}, inputFiles));
    } else {
      check(d.cameras.size() >= 2, "leave-one-out needs at least two cameras");
      check(p.mp4.empty(),
            "Mp4 is for Mode=render (leave-one-out writes its renders with "
            "SaveRenders)");
      check(!p.saveRenders || !p.output.empty(), "SaveRenders needs an output folder (-o DIR)");
      std::optional<Dataset> reference;
      if (!p.reference.empty()) reference = readDataset(p.reference);
      const std::vector<const Dataset*> datasets = {&full, reference ? &*reference : &full};
      checkNotAnInput(p.csv, datasets, inputFiles);
      if (p.saveRenders && !p.csv.empty()) {  // nor one of the renders it saves
        InputFiles renders;
        for (const DatasetCamera& c : d.cameras)
          renders.addPattern((fs::path(p.output) / c.camera.name / "%04d.png").string(), 0, INT_MAX,
                             "this run's output");
        renders.checkOutput(p.csv);
      }
      inputFiles.push_back(p.input);
      inputFiles.push_back(p.reference);
      const std::vector<std::string> inputs = protectedPaths(datasets, inputFiles);
      // The CSV is staged before the renders' folder is committed, and the two are put in place
      // together (commitAll): a CSV that cannot be written leaves the folder as it was.
      StagedFiles csv;
      const std::vector<LeaveOneOutRow> rows =
          leaveOneOut(d, frames, p.render, p.saveRenders ? p.output : "", p.overwrite, inputs,
                      reference ? &*reference : nullptr,
                      [&](const std::vector<LeaveOneOutRow>& all) {
                        if (!p.csv.empty()) csv.write(p.csv, formatLeaveOneOutCsv(all));
                      },
                      {&csv});
      std::fputs(formatLeaveOneOutTable(rows).c_str(), stdout);
    }
    return 0;
  });
}
