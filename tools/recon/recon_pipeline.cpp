#include "tools/recon/recon_pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <filesystem>
#include <memory>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/gom_list.h"
#include "common/core/mesh_io.h"
#include "common/core/obj_io.h"
#include "common/core/progress.h"
#include "common/core/sequence.h"
#include "common/media/dataset.h"
#include "common/media/png_io.h"
#include "common/views/rasteriser.h"
#include "tools/eval/metrics.h"
#include "tools/multiview/importers.h"
#include "tools/recon/gom_builder.h"
#include "tools/recon/reconstruction.h"
#include "tools/recon/silhouettes.h"
#include "tools/recon/surface_processing.h"

namespace tdvo {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* fmt, ...) {
  char buffer[1024];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buffer, sizeof buffer, fmt, args);
  va_end(args);
  return buffer;
}

const char* kColumns =
    "frame,source,gom,type,silhouette_s,carving_s,surface_s,smoothing_s,decimation_s,"
    "tracking_s,metrics_s,total_s,octree_cells,surface_voxels,hull_triangles,components,"
    "vertices,triangles,voxel,hull_volume,iou_mean,iou_min,fit_hausdorff,fit_mean,diagonal,"
    "truth_mean,truth_hausdorff,truth_diagonal,photo_s,photo_targets,photo_displacement";

std::string csvRow(const FrameRecord& r) {
  return format(
      "%d,%d,%d,%s,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%zu,%zu,%zu,%zu,%zu,%zu,%.6g,%.6g,"
      "%.5f,%.5f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.4f,%zu,%.4g",
      r.frame, r.source, r.gom, r.iMesh ? (r.rejectedFit ? "I*" : "I") : "P", r.silhouetteSeconds,
      r.carvingSeconds, r.surfaceSeconds, r.smoothingSeconds, r.decimationSeconds,
      r.trackingSeconds, r.metricSeconds, r.totalSeconds, r.cellsJudged, r.surfaceVoxels,
      r.hullTriangles, r.components, r.vertices, r.triangles, r.voxelSize, r.hullVolume, r.iouMean,
      r.iouMin, r.fitHausdorff, r.fitMean, r.diagonal, r.truthMean, r.truthHausdorff,
      r.truthDiagonal, r.photoSeconds, r.photoTargets, r.photoDisplacement);
}

// `dataset` (empty: none) is the refined cameras' dataset.json, which the encoder must take
// instead of the input's to code the textures (their shapes are the mesh projected into these
// cameras). It is named in a comment: the cfg codes the geometry alone, as without refinement.
std::string encoderCfg(const std::string& pattern, int first, int count, double rate, int gomSize,
                       const std::string& comment, const std::string& dataset) {
  std::string text = comment;
  text += "InputMeshPattern : " + pattern + "\n";
  if (!dataset.empty())
    text +=
        "# Textures: with the cameras RefineCalibration refined, not the input's, i.e. add\n"
        "# Dataset          : " +
        dataset + "\n";
  text += format("FirstFrame       : %d\n", first);
  text += format("FrameCount       : %d\n", count);
  text += format("FrameRate        : %.17g\n", rate);
  if (gomSize > 0) text += format("GOMSize          : %d\n", gomSize);
  return text;
}

struct Summary {
  double mean = 0, min = 1e300, max = -1e300;
  size_t count = 0;
  void add(double v) {
    if (v < 0) return;
    mean += v;
    min = std::min(min, v);
    max = std::max(max, v);
    ++count;
  }
  std::string text(const char* fmt) const {
    if (count == 0) return "(not measured)";
    return "mean " + format(fmt, mean / double(count)) + ", min " + format(fmt, min) + ", max " +
           format(fmt, max);
  }
};

std::string reportText(const ReconParams& params, const ReconResult& result,
                       const std::string& inputText, const std::string& cameraText) {
  std::string t = "# 3dvo-recon report\n";
  if (!result.calibrationText.empty()) t += result.calibrationText;
  t += "input          : " + inputText + "\n";
  if (!cameraText.empty()) t += "cameras        : " + cameraText + "\n";
  if (params.inputMeshPattern.empty()) t += format("octree depth   : %d\n", params.octreeDepth);
  t += format("frames         : %zu\n", result.frames.size());
  std::string lengths;
  for (const auto& g : result.goms)
    lengths += (lengths.empty() ? "" : " ") + std::to_string(g.second);
  t += format("GOMs           : %zu (frames per GOM: %s)\n", result.goms.size(), lengths.c_str());
  Summary total, sil, carve, surf, smooth, photo, decim, track, metric, iou, iouMin, volume, fitRel,
      fitMean, truthMean, truthH, vertices, triangles;
  for (const FrameRecord& r : result.frames) {
    total.add(r.totalSeconds);
    sil.add(r.silhouetteSeconds);
    carve.add(r.carvingSeconds);
    surf.add(r.surfaceSeconds);
    smooth.add(r.smoothingSeconds);
    photo.add(r.photoSeconds);
    decim.add(r.decimationSeconds);
    track.add(r.trackingSeconds);
    metric.add(r.metricSeconds);
    iou.add(r.iouMean);
    iouMin.add(r.iouMin);
    volume.add(r.hullVolume);
    if (r.diagonal > 0 && std::isfinite(r.diagonal) && std::isfinite(r.fitHausdorff))
      fitRel.add(r.fitHausdorff / r.diagonal);
    fitMean.add(r.fitMean);
    truthMean.add(r.truthMean);
    truthH.add(r.truthHausdorff);
    vertices.add(static_cast<double>(r.vertices));
    triangles.add(static_cast<double>(r.triangles));
  }
  t += "# each figure below: mean, min and max over the frames\n";
  t += "time per frame : " + total.text("%.3f s") + "\n";
  const std::pair<const char*, const Summary*> stages[] = {
      {"  silhouettes  : ", &sil},    {"  carving      : ", &carve}, {"  surface      : ", &surf},
      {"  smoothing    : ", &smooth}, {"  photo refine : ", &photo}, {"  decimation   : ", &decim},
      {"  tracking     : ", &track},  {"  metrics      : ", &metric}};
  for (const auto& [label, stage] : stages)
    if (stage->max > 0) t += label + stage->text("%.3f s") + "\n";
  t += "vertices       : " + vertices.text("%.0f") + "\n";
  t += "triangles      : " + triangles.text("%.0f") + "\n";
  if (iou.count > 0) {
    t += "silhouette IoU : views' mean " + iou.text("%.4f") + "\n";
    t += "                 worst view " + iouMin.text("%.4f") + "\n";
    t += "hull volume    : " + volume.text("%.6g") + "\n";
  }
  t += "fit error      : Hausdorff / diagonal " + fitRel.text("%.5f") + "\n";
  t += "                 mean distance " + fitMean.text("%.6g") + "\n";
  if (truthMean.count > 0) {
    t += "ground truth   : mean distance " + truthMean.text("%.6g") + "\n";
    t += "                 Hausdorff " + truthH.text("%.6g") + "\n";
  }
  t += "\n# per frame (type I: first frame of a GOM, I*: after a rejected fit, P: tracked)\n";
  t += kColumns;
  t += "\n";
  for (const FrameRecord& r : result.frames)
    t += csvRow(r) + "\n";
  return t;
}

// Mesh input: the frames of an OBJ sequence.
struct MeshInput {
  std::string pattern;
  int first;
  Mesh read(int index, bool weld) const {
    Mesh m = readMesh(framePath(pattern, first + index));
    if (weld) weldVertices(m);
    return m;
  }
};

}  // namespace

ReconResult runReconstruction(const ReconParams& params, std::FILE* log) {
  checkReconParams(params);
  ReconResult result;

  // Input.
  std::unique_ptr<Dataset> dataset;
  std::unique_ptr<FrameReconstructor> reconstructor;
  MeshInput meshes{params.inputMeshPattern, params.firstFrame};
  int frameCount = params.frameCount;
  std::string inputText, cameraText;
  if (!params.input.empty()) {
    dataset = std::make_unique<Dataset>(importAny(params.input, ImportOptions()));
    check(params.firstFrame < dataset->frameCount,
          "FirstFrame " + std::to_string(params.firstFrame) + " is beyond the dataset's " +
              std::to_string(dataset->frameCount) + " frames");
    if (frameCount == 0) frameCount = dataset->frameCount - params.firstFrame;
    check(params.firstFrame + frameCount <= dataset->frameCount,
          "FirstFrame + FrameCount exceeds the dataset's " + std::to_string(dataset->frameCount) +
              " frames");
    reconstructor = std::make_unique<FrameReconstructor>(*dataset, params);
    inputText = params.input +
                format(" (frames %d .. %d)", params.firstFrame, params.firstFrame + frameCount - 1);
    for (size_t u = 0; u < reconstructor->cameras().size(); ++u) {
      const std::string name = dataset->cameras[reconstructor->cameras()[u]].camera.name;
      result.cameras.push_back(name);
      cameraText += (cameraText.empty() ? "" : ", ") + name + " (" +
                    reconstructor->silhouetteMethodName(u) + ")";
    }
    cameraText = format("%zu, min views %d: ", result.cameras.size(), reconstructor->minViews()) +
                 cameraText;
  } else {
    inputText = params.inputMeshPattern +
                format(" (files %d .. %d)", params.firstFrame, params.firstFrame + frameCount - 1);
  }
  const double frameRate = dataset ? dataset->frameRate : 25.0;
  // Output files carry the input's frame numbers (the dataset's frames.first + index, or the
  // input file numbers), and encode.cfg says FirstFrame = the first: 3dvo-enc --Dataset then
  // ties each mesh to the camera images of the same frame.
  const int firstNumber = (dataset ? dataset->firstFrame : 0) + params.firstFrame;

  // Output folders; files are staged and renamed together at the end.
  namespace fs = std::filesystem;
  const std::string out = params.output;
  // --Overwrite may not delete an input: the cfg files, the dataset's files and sequence
  // folders, the input meshes' folder.
  std::vector<std::string> inputs = params.cfgFiles;
  inputs.push_back(params.input);
  if (dataset)
    for (std::string& path : datasetPaths(*dataset))
      inputs.push_back(std::move(path));
  if (!params.inputMeshPattern.empty()) {
    inputs.push_back(framePath(params.inputMeshPattern, params.firstFrame));
    const std::string folder = fs::path(params.inputMeshPattern).parent_path().string();
    inputs.push_back(folder.empty() ? "." : folder);
  }
  OutputFolder files(out, params.overwrite, inputs);

  if (reconstructor && params.refineCalibration) {
    const CalibrationRefinementResult r =
        reconstructor->refineCalibration(params.firstFrame, *dataset);
    std::string t = format(
        "calibration    : refined on frame %d in %.1f s, %d pass(es) kept; hull of all cameras "
        "vs silhouettes, mean IoU %.4f -> %.4f\n",
        params.firstFrame, r.seconds, r.passesKept, r.meanIouBefore, r.meanIouAfter);
    for (const CameraRefinement& c : r.cameras)
      t += format(
          "  %-14s IoU with the others' hull %.4f -> %.4f, rotated %.3f deg, moved %.4g, "
          "focal x %.4f\n",
          c.name.c_str(), c.iouBefore, c.iouAfter, c.rotationDegrees, c.translation, c.focalFactor);
    result.calibrationText = t;
    if (log) std::fputs(t.c_str(), log);
    // The refined cameras, for 3dvo-enc --Dataset and 3dvo-render.
    files.write(out + "/" + kDatasetFileName, formatDataset(*dataset, out));
  }

  GomBuilder builder(params);
  Progress progress("3dvo-recon: frame", static_cast<size_t>(frameCount));
  for (int i = 0; i < frameCount; ++i) {
    const auto frameStart = std::chrono::steady_clock::now();
    FrameRecord record;
    record.frame = i;
    record.source = params.firstFrame + i;
    Mesh surface;
    ReconstructedFrame recon;
    if (reconstructor) {
      recon = reconstructor->reconstruct(params.firstFrame + i);
      record.silhouetteSeconds = recon.silhouetteSeconds;
      record.carvingSeconds = recon.stats.carvingSeconds;
      record.surfaceSeconds = recon.stats.surfaceSeconds;
      record.smoothingSeconds = recon.smoothingSeconds;
      if (recon.photoRefined) {
        record.photoSeconds = recon.photo.seconds;
        record.photoTargets = recon.photo.targets;
        record.photoDisplacement = recon.photo.meanDisplacement;
      }
      record.cellsJudged = recon.stats.cellsJudged;
      record.surfaceVoxels = recon.stats.surfaceVoxels;
      record.hullTriangles = recon.hull.triangles.size();
      record.components = recon.components;
      record.voxelSize = recon.stats.voxelSize;
      record.hullVolume = enclosedVolume(recon.hull);
      surface = std::move(recon.surface);
    } else {
      surface = meshes.read(i, params.weldInput);
    }

    GomStep step = builder.add(surface, record.voxelSize > 0 ? record.voxelSize : 0);
    record.gom = step.gom;
    record.iMesh = step.iMesh;
    record.rejectedFit = step.rejectedFit;
    record.decimationSeconds = step.decimationSeconds;
    record.trackingSeconds = step.trackingSeconds;
    record.fitHausdorff = step.fitHausdorff;
    record.fitMean = step.fitMean;
    record.diagonal = step.diagonal;
    record.vertices = step.mesh.positions.size();
    record.triangles = step.mesh.triangles.size();
    record.metricSeconds = step.distanceSeconds;

    // Silhouette agreement and ground truth.
    const auto metricStart = std::chrono::steady_clock::now();
    if (reconstructor) {
      std::vector<double> ious;
      const std::vector<Camera> cameras = reconstructor->cameraModels();
      for (size_t u = 0; u < cameras.size(); ++u)
        ious.push_back(maskIoU(renderMask(step.mesh, cameras[u]), recon.silhouettes[u]));
      record.iouMin = *std::min_element(ious.begin(), ious.end());
      double sum = 0;
      for (double v : ious)
        sum += v;
      record.iouMean = sum / double(ious.size());
      result.iou.push_back(ious);
      if (!dataset->meshes.empty()) {
        const Mesh truth = readDatasetMesh(*dataset, params.firstFrame + i);
        const SurfaceDistance d = surfaceDistance(truth, step.mesh);
        BoundingBox box;
        box.extend(truth.positions);
        record.truthMean = d.mean();
        record.truthHausdorff = d.hausdorff();
        record.truthDiagonal = box.diagonal();
      }
    }
    record.metricSeconds += secondsSince(metricStart);

    // Output files.
    const std::string text = formatObj(step.mesh);
    files.write(out + "/" + framePath(params.outputMeshPattern, firstNumber + i), text);
    if (params.writeHull)
      files.write(out + "/" + framePath("hull/%04d.obj", firstNumber + i), formatObj(recon.hull));
    if (params.writeSilhouettes)
      for (size_t u = 0; u < result.cameras.size(); ++u) {
        const std::vector<uint8_t> png = encodePng(recon.silhouettes[u]);
        files.write(out + "/silhouettes/" + result.cameras[u] + "/" +
                        framePath("%04d.png", firstNumber + i),
                    png.data(), png.size());
      }
    record.totalSeconds = secondsSince(frameStart);
    result.frames.push_back(record);
    if (log) {
      std::string line = format("frame %4d  gom %3d %-2s  v %6zu  f %6zu", i, record.gom,
                                record.iMesh ? (record.rejectedFit ? "I*" : "I") : "P",
                                record.vertices, record.triangles);
      if (record.iouMean >= 0)
        line += format("  IoU %.4f (worst %.4f)  volume %.6g", record.iouMean, record.iouMin,
                       record.hullVolume);
      line += format("  fit %.3f%%",
                     record.diagonal > 0 ? 100 * record.fitHausdorff / record.diagonal : 0.0);
      if (record.truthMean >= 0) line += format("  truth mean %.5g", record.truthMean);
      line += format("  %.2f s\n", record.totalSeconds);
      std::fputs(line.c_str(), log);
      std::fflush(log);
    }
    progress.tick(static_cast<size_t>(i + 1));
  }
  result.goms = builder.goms();

  // GOM list, encoder cfg files, reports.
  // The folder's name as pattern text ("%" doubled), then the meshes' own pattern.
  const std::string pattern =
      (fs::path(escapePercent(fs::absolute(out).string())) / params.outputMeshPattern).string();
  files.write(out + "/goms.txt", formatGomList(result.goms));
  int commonSize = result.goms.front().second;
  bool uniform = true;
  for (size_t g = 0; g + 1 < result.goms.size(); ++g)
    uniform = uniform && result.goms[g].second == commonSize;
  if (result.goms.size() > 1 && result.goms.back().second > commonSize) uniform = false;
  const std::string header =
      "# 3dvo-enc input for this 3dvo-recon output, e.g.\n"
      "#   3dvo-enc -c cfg/d3dmc-lossless.cfg -c encode.cfg --BitstreamFile=out.3dvo\n";
  // GOMs of different lengths: the encoder takes the list itself (GOMListFile).
  const std::string gomList = fs::absolute(fs::path(out) / "goms.txt").string();
  const std::string refined = reconstructor && params.refineCalibration
                                  ? fs::absolute(fs::path(out) / kDatasetFileName).string()
                                  : std::string();
  files.write(out + "/encode.cfg", encoderCfg(pattern, firstNumber, frameCount, frameRate,
                                              uniform ? commonSize : 0, header, refined) +
                                       (uniform ? "" : "GOMListFile      : " + gomList + "\n"));
  for (size_t g = 0; g < result.goms.size(); ++g)
    files.write(
        out + "/encode/" + framePath("gom_%04d.cfg", static_cast<int>(g)),
        encoderCfg(pattern, firstNumber + result.goms[g].first, result.goms[g].second, frameRate,
                   result.goms[g].second,
                   format("# 3dvo-enc input for GOM %zu of this 3dvo-recon output\n", g), refined));
  std::string csv = std::string(kColumns) + "\n";
  for (const FrameRecord& r : result.frames)
    csv += csvRow(r) + "\n";
  files.write(out + "/frames.csv", csv);
  const std::string report = reportText(params, result, inputText, cameraText);
  files.write(out + "/report.txt", report);
  files.commit();
  if (log) {
    const size_t cut = report.find("\n# per frame");
    std::fputs(report.substr(0, cut).c_str(), log);
    std::fputs("\n", log);
  }
  return result;
}

}  // namespace tdvo
