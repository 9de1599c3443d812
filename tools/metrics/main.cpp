// 3dvo-metrics: geometry distortion between a reference and a test mesh sequence (or two single
// meshes): point-to-surface Hausdorff distances per frame, vertex RMSE, D_A and the KG error
// when the vertex counts match, and STED when the connectivity matches too. With ReferenceDataset
// and TestDataset instead: texture PSNR (object and frame) between an original dataset and a
// decoded one (texture_metrics.h). Formulas and conventions: docs/metrics.md.
#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bitstream/syntax.h"
#include "common/core/app.h"
#include "common/core/config.h"
#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/gom_list.h"
#include "common/core/mesh_io.h"
#include "common/core/number_text.h"
#include "common/core/obj_io.h"
#include "common/core/progress.h"
#include "common/core/sequence.h"
#include "common/media/media_version.h"
#include "tools/eval/metrics.h"
#include "tools/metrics/texture_metrics.h"

using namespace tdvo;

namespace {

enum class Correspondence { kIdentity, kNearest };

struct Params {
  std::string referenceMeshes, testMeshes, csvFile, groupStarts;
  int referenceFirstFrame = 0, testFirstFrame = 0, frameCount = 0, groupSize = 1;
  Correspondence correspondence = Correspondence::kIdentity;
  bool relative = false;
  StedParams sted;
  TextureMetricsParams texture;  // the texture mode's own keys (ReferenceDataset, ...)

  void registerOptions(OptionTable& t) {
    t.section("Reference");
    t.add("ReferenceMeshes", referenceMeshes,
          "reference meshes (OBJ, PLY or glTF by extension; .gz for OBJ and PLY): one file, or a "
          "printf pattern such as "
          "seq/%04d.obj.gz for a sequence",
          "-r");
    t.add("ReferenceFirstFrame", referenceFirstFrame, 0, 1000000000,
          "number of the first reference frame (sequences only)");
    t.section("Test");
    t.add("TestMeshes", testMeshes,
          "test meshes (e.g. decoded output): one file, or a pattern such as out/%04d.obj", "-t");
    t.add("TestFirstFrame", testFirstFrame, 0, 1000000000,
          "number of the first test frame (sequences only; 3dvo-dec names its files with the "
          "input's frame numbers: the encoder's FirstFrame, or 0 with --RenumberFrames)");
    t.section("Comparison");
    t.add("FrameCount", frameCount, 0, 10000000,
          "frames to compare (sequences only); 0 = from the first frames on, as long as "
          "both sequences have the frame");
    t.addEnum("Correspondence", correspondence,
              {{"identity", Correspondence::kIdentity}, {"nearest", Correspondence::kNearest}},
              "vertex order for RMSE, D_A and KG: identity = vertex i is vertex i; nearest = "
              "match each test vertex to its nearest reference vertex at the first frame of "
              "each group (for coders that reorder vertices; 3DVO output keeps the input's order)");
    t.add("GroupSize", groupSize, 1, 10000000,
          "frames per group for Correspondence nearest: one matching per group, made at its "
          "first frame (set to the encoder's GOMSize; 1 = match every frame)");
    t.add("GroupStarts", groupStarts,
          "instead of GroupSize: file of the test frame numbers where groups start, e.g. the "
          "gom_starts.txt 3dvo-dec writes (for GOMs of different lengths); the first compared "
          "frame always starts one");
    t.add("Relative", relative,
          "report distances divided by the diagonal of the reference bounding box (over all "
          "compared frames) instead of in OBJ units");
    t.section("STED (spatio-temporal edge difference, Vasa & Skala 2011)");
    t.add("StedWidth", sted.width, 0.0, 1.0,
          "w: a vertex's spatial neighbourhood is its 1-ring and the vertices within along-edge "
          "distance w x D of it (D = diagonal of the first reference frame's bounding box; "
          "0 = the 1-ring alone)");
    t.add("StedTimeStep", sted.timeStep, 1e-6, 100.0,
          "dt: the time component of a temporal edge (a vertex's move from one frame to the "
          "next), as a fraction of D");
    t.add("StedWeight", sted.temporalWeight, 0.0, 1000.0,
          "c: STED = sqrt(STED_s^2 + c^2 STED_t^2)");
    t.section("Textures (instead of meshes)");
    t.add("ReferenceDataset", texture.referenceDataset,
          "texture mode: the original dataset (folder or dataset.json) whose camera frames were "
          "coded; frame indices are ReferenceFirstFrame + k");
    t.add("TestDataset", texture.testDataset,
          "texture mode: the decoded dataset written by 3dvo-dec -o (RGBA frames, alpha = the "
          "decoded shape); frame indices are TestFirstFrame + k");
    t.add("Bitstream", texture.bitstream,
          "texture mode: the stream that was decoded; the frame PSNR is then taken over each "
          "camera's texture box instead of the whole frame");
    t.section("Output");
    t.add("CsvFile", csvFile, "also write the per-frame and summary figures as CSV to this file");
  }
};

bool isPattern(const std::string& name) {
  return name.find('%') != std::string::npos;
}

// Figures of one compared frame, in OBJ units.
struct FrameResult {
  int referenceFrame = 0, testFrame = 0;
  size_t referenceVertices = 0, testVertices = 0;
  SurfaceDistance surface;
  std::optional<double> rmse, meanError;  // absent when the vertex errors are undefined
};

// CSV cells carry 10 significant digits, the text report 6; an absent value is an empty cell
// in CSV and "n/a" in text.
std::string format(double value, int digits = 10) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
  return buffer;
}

std::string csvCell(const std::optional<double>& value) {
  return value ? format(*value) : std::string();
}

std::string textCell(const std::optional<double>& value) {
  return value ? format(*value, 6) : std::string("n/a");
}

// Squared distances overflow double precision beyond about 1e154: coordinates beyond 1e150 in
// magnitude (which the mesh readers take) would give infinite or NaN figures, so they are an
// error here. At the other end they underflow: on a mesh smaller than 1e-140 across, the
// squared errors (a fraction of its size, squared) fall below the smallest normal double and
// the figures come out 0, so such a mesh is an error too (one point, extent 0, is not: its
// figures are defined or said to be undefined).
void checkMeasurable(const Mesh& mesh, const std::string& path) {
  constexpr double kMaxCoordinate = 1e150, kMinExtent = 1e-140;
  Vec3d lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (size_t v = 0; v < mesh.positions.size(); ++v)
    for (int a = 0; a < 3; ++a) {
      const double c = mesh.positions[v][a];
      check(std::fabs(c) <= kMaxCoordinate,
            path + ": vertex " + std::to_string(v + 1) + " has a coordinate (" + formatDouble(c) +
                ") beyond 1e150 in magnitude, where distances overflow double precision");
      lo[a] = std::min(lo[a], c);
      hi[a] = std::max(hi[a], c);
    }
  double extent = 0;
  for (int a = 0; a < 3 && !mesh.positions.empty(); ++a)
    extent = std::max(extent, hi[a] - lo[a]);
  check(extent == 0 || extent >= kMinExtent,
        path + ": the mesh is " + formatDouble(extent) +
            " across, below 1e-140, where squared distances underflow double precision (the "
            "figures would be 0): scale the meshes up");
}

}  // namespace

int main(int argc, char** argv) {
  return runApp("3dvo-metrics", [&]() {
    Params p;
    OptionTable table("3dvo-metrics",
                      "3dvo-metrics -r REFERENCE -t TEST [--Key=value ...]\n"
                      "  or   3dvo-metrics --ReferenceDataset=DIR --TestDataset=DECODED "
                      "[--Bitstream=S.3dvo] [--Key=value ...]\n"
                      "  e.g. 3dvo-metrics -r seq/%04d.obj.gz --ReferenceFirstFrame=1 "
                      "-t out/%04d.obj --TestFirstFrame=1 --Correspondence=nearest --GroupSize=8 "
                      "--CsvFile=m.csv");
    p.registerOptions(table);
    table.addVersionLines({"stream syntax version " + std::to_string(kSyntaxVersion)});
    table.addVersionLines(mediaLibraryVersions());
    if (!table.parseCommandLine(argc, argv)) return 0;
    if (!p.csvFile.empty()) {  // nor a cfg file (the inputs of each kind of run: below)
      InputFiles cfgs;
      for (const std::string& cfg : table.filesRead())
        cfgs.add(cfg);
      cfgs.checkOutput(p.csvFile);
    }
    if (!p.texture.referenceDataset.empty() || !p.texture.testDataset.empty()) {
      check(p.referenceMeshes.empty() && p.testMeshes.empty(),
            "give meshes (ReferenceMeshes, TestMeshes) or datasets (ReferenceDataset, "
            "TestDataset), not both");
      check(p.correspondence == Correspondence::kIdentity && p.groupSize == 1 &&
                p.groupStarts.empty() && !p.relative,
            "Correspondence, GroupSize, GroupStarts and Relative are for meshes, not for texture "
            "metrics");
      p.texture.referenceFirstFrame = p.referenceFirstFrame;
      p.texture.testFirstFrame = p.testFirstFrame;
      p.texture.frameCount = p.frameCount;
      p.texture.csvFile = p.csvFile;
      return runTextureMetrics(p.texture);
    }
    check(p.texture.bitstream.empty(),
          "Bitstream is for texture metrics (with ReferenceDataset "
          "and TestDataset)");
    check(!p.referenceMeshes.empty(), "no reference given (-r FILE or PATTERN; see --help)");
    check(!p.testMeshes.empty(), "no test meshes given (-t FILE or PATTERN; see --help)");
    const bool sequence = isPattern(p.referenceMeshes);
    check(sequence == isPattern(p.testMeshes),
          "ReferenceMeshes and TestMeshes must both be single files or both be frame patterns");
    const auto start = std::chrono::steady_clock::now();

    // The files to compare.
    std::vector<std::string> referencePaths, testPaths;
    std::vector<int> referenceFrames, testFrames;
    if (!sequence) {
      referencePaths = {p.referenceMeshes};
      testPaths = {p.testMeshes};
      referenceFrames = testFrames = {0};
    } else {
      checkFramePattern(p.referenceMeshes, "ReferenceMeshes");
      checkFramePattern(p.testMeshes, "TestMeshes");
      int count = p.frameCount;
      if (count == 0) {
        // Compare as long as both sequences have the frame (the count is printed below).
        while (
            std::filesystem::exists(framePath(p.referenceMeshes, p.referenceFirstFrame + count)) &&
            std::filesystem::exists(framePath(p.testMeshes, p.testFirstFrame + count)))
          ++count;
        if (count == 0) {
          // Name the side that lacks its first frame (or both), with the key that chose it.
          const std::string reference = framePath(p.referenceMeshes, p.referenceFirstFrame);
          const std::string test = framePath(p.testMeshes, p.testFirstFrame);
          std::vector<std::string> missing;
          if (!std::filesystem::exists(reference))
            missing.push_back("'" + reference + "' (ReferenceFirstFrame " +
                              std::to_string(p.referenceFirstFrame) + ")");
          if (!std::filesystem::exists(test))
            missing.push_back("'" + test + "' (TestFirstFrame " + std::to_string(p.testFirstFrame) +
                              ")");
          throw Error("no frames to compare: " +
                      (missing.size() == 2 ? missing[0] + " and " + missing[1] + " do not exist"
                                           : missing[0] + " does not exist"));
        }
      }
      for (int k = 0; k < count; ++k) {
        referenceFrames.push_back(p.referenceFirstFrame + k);
        testFrames.push_back(p.testFirstFrame + k);
        referencePaths.push_back(framePath(p.referenceMeshes, referenceFrames.back()));
        testPaths.push_back(framePath(p.testMeshes, testFrames.back()));
      }
    }
    const size_t frames = referencePaths.size();
    // The CSV file may not replace an input (docs/user-guide.md, "Output files"): the meshes
    // compared and the GroupStarts file, by file identity, before any is read.
    if (!p.csvFile.empty()) {
      InputFiles inputs;
      inputs.add(p.groupStarts);
      for (size_t k = 0; k < frames; ++k) {
        inputs.add(referencePaths[k]);
        inputs.add(testPaths[k]);
      }
      // Every frame of a sequence given, also those this run does not compare (FrameCount).
      for (const std::string* pattern : {&p.referenceMeshes, &p.testMeshes})
        if (pattern->find('%') != std::string::npos) inputs.addPattern(*pattern, 0, INT_MAX);
      inputs.checkOutput(p.csvFile);
    }
    // Where the groups of the nearest correspondence start (positions k in the comparison).
    check(p.groupStarts.empty() || p.groupSize == 1, "give GroupSize or GroupStarts, not both");
    std::vector<bool> groupStarts(frames, false);
    if (p.groupStarts.empty()) {
      for (size_t k = 0; k < frames; k += static_cast<size_t>(p.groupSize))
        groupStarts[k] = true;
    } else {
      const std::vector<int> starts = readGomStarts(p.groupStarts);
      for (size_t k = 0; k < frames; ++k)
        groupStarts[k] = k == 0 || std::binary_search(starts.begin(), starts.end(), testFrames[k]);
    }

    // Per frame: surface distances always; vertex errors while the vertex counts allow them.
    std::vector<FrameResult> results(frames);
    BoundingBox box;
    SequenceErrorAccumulator sequenceErrors;
    std::string vertexErrorsMissing;  // why the sequence vertex errors are undefined, if they are
    StedAccumulator stedErrors(p.sted);
    std::string stedMissing;  // why STED is undefined, if it is
    if (p.correspondence != Correspondence::kIdentity)
      stedMissing = "STED needs the same vertex order on both sides (Correspondence identity)";
    std::vector<uint32_t> correspondence;
    bool haveCorrespondence = false;
    {
      Progress progress("comparing frames", frames);
      for (size_t k = 0; k < frames; ++k) {
        const Mesh reference = readMesh(referencePaths[k]);
        const Mesh test = readMesh(testPaths[k]);
        checkMeasurable(reference, referencePaths[k]);
        checkMeasurable(test, testPaths[k]);
        FrameResult& r = results[k];
        r.referenceFrame = referenceFrames[k];
        r.testFrame = testFrames[k];
        r.referenceVertices = reference.positions.size();
        r.testVertices = test.positions.size();
        box.extend(reference.positions);
        r.surface = surfaceDistance(reference, test);

        const bool groupStart = groupStarts[k];
        if (groupStart) haveCorrespondence = false;
        std::string problem;
        if (r.referenceVertices != r.testVertices) {
          problem = testPaths[k] + " has " + std::to_string(r.testVertices) + " vertices, " +
                    referencePaths[k] + " " + std::to_string(r.referenceVertices);
        } else if (p.correspondence == Correspondence::kNearest && !haveCorrespondence) {
          if (groupStart) {
            correspondence = nearestVertexCorrespondence(reference.positions, test.positions);
            haveCorrespondence = true;
          } else {
            problem = "no vertex correspondence for " + testPaths[k] +
                      " (the first frame of its group had none)";
          }
        } else if (p.correspondence == Correspondence::kNearest &&
                   correspondence.size() != r.testVertices) {
          problem = testPaths[k] +
                    " has a different vertex count than the first frame of its "
                    "group";
        }
        if (problem.empty()) {
          const std::vector<Vec3d> aligned = p.correspondence == Correspondence::kNearest
                                                 ? inReferenceOrder(test.positions, correspondence)
                                                 : test.positions;
          SequenceErrorAccumulator frameErrors;
          frameErrors.addFrame(reference.positions, aligned);
          r.rmse = frameErrors.vertexRmse();
          r.meanError = frameErrors.temporalAverageError();
          if (sequenceErrors.frameCount() > 0 &&
              sequenceErrors.vertexCount() != reference.positions.size())
            problem = referencePaths[k] + " has " + std::to_string(r.referenceVertices) +
                      " vertices, earlier frames " + std::to_string(sequenceErrors.vertexCount());
          else if (vertexErrorsMissing.empty())
            sequenceErrors.addFrame(reference.positions, aligned);
        }
        if (!problem.empty() && vertexErrorsMissing.empty()) vertexErrorsMissing = problem;
        if (stedMissing.empty()) {
          try {
            stedErrors.addFrame(reference, test);
          } catch (const Error& e) {
            stedMissing = testPaths[k] + ": " + e.what();
          }
        }
        progress.tick(k + 1);
      }
    }

    // Reporting, in OBJ units or relative to the reference diagonal.
    const double diagonal = box.diagonal();
    check(!p.relative || diagonal > 0,
          "Relative: the reference bounding box has zero diagonal (all vertices at one point)");
    const double unit = p.relative ? diagonal : 1.0;
    auto scaled = [&](double v) { return v / unit; };
    auto scaledOpt = [&](const std::optional<double>& v) {
      return v ? std::optional<double>(*v / unit) : std::nullopt;
    };

    std::printf("# 3dvo-metrics\n");
    if (sequence) {
      std::printf("reference           : %s, frames %d..%d\n", p.referenceMeshes.c_str(),
                  referenceFrames.front(), referenceFrames.back());
      std::printf("test                : %s, frames %d..%d\n", p.testMeshes.c_str(),
                  testFrames.front(), testFrames.back());
    } else {
      std::printf("reference           : %s\n", p.referenceMeshes.c_str());
      std::printf("test                : %s\n", p.testMeshes.c_str());
    }
    if (p.correspondence == Correspondence::kNearest && !p.groupStarts.empty())
      std::printf(
          "correspondence      : nearest reference vertex, matched at the first frame "
          "of each group, %zu groups starting at the frames of %s\n",
          static_cast<size_t>(std::count(groupStarts.begin(), groupStarts.end(), true)),
          p.groupStarts.c_str());
    else if (p.correspondence == Correspondence::kNearest)
      std::printf(
          "correspondence      : nearest reference vertex, matched at the first frame "
          "of each group of %d\n",
          p.groupSize);
    else
      std::printf("correspondence      : identity (vertex i is vertex i)\n");
    std::printf("reference diagonal  : %s\n", format(diagonal, 6).c_str());
    std::printf("distances           : %s\n",
                p.relative ? "relative to the reference diagonal" : "OBJ units");
    std::printf(
        "STED parameters     : w %s, dt %s, c %s (fractions of the first reference "
        "frame's diagonal)\n",
        format(p.sted.width, 6).c_str(), format(p.sted.timeStep, 6).c_str(),
        format(p.sted.temporalWeight, 6).c_str());

    std::printf("# per frame: H = symmetric Hausdorff, r->t / t->r = one-sided (max, mean)\n");
    std::printf("%6s %6s %6s %8s %8s %11s %11s %11s %11s %11s %11s %11s %11s\n", "frame", "ref",
                "test", "ref_v", "test_v", "H_max", "H_mean", "r->t_max", "r->t_mean", "t->r_max",
                "t->r_mean", "v_rmse", "v_mean");
    std::string csv =
        "frame,reference_frame,test_frame,reference_vertices,test_vertices,hausdorff_max,"
        "hausdorff_mean,reference_to_test_max,reference_to_test_mean,test_to_reference_max,"
        "test_to_reference_mean,vertex_rmse,vertex_mean_error,kg_error,sted_s,sted_t,sted,unit,"
        "diagonal\n";
    const std::string unitName = p.relative ? "diagonal" : "absolute";
    double hausdorffMax = 0, hausdorffMeanSum = 0, rtMax = 0, rtMeanSum = 0, trMax = 0,
           trMeanSum = 0;
    for (size_t k = 0; k < frames; ++k) {
      const FrameResult& r = results[k];
      const SurfaceDistance& s = r.surface;
      hausdorffMax = std::max(hausdorffMax, s.hausdorff());
      hausdorffMeanSum += s.mean();
      rtMax = std::max(rtMax, s.referenceToTest.max);
      rtMeanSum += s.referenceToTest.mean;
      trMax = std::max(trMax, s.testToReference.max);
      trMeanSum += s.testToReference.mean;
      const std::vector<std::optional<double>> values = {scaled(s.hausdorff()),
                                                         scaled(s.mean()),
                                                         scaled(s.referenceToTest.max),
                                                         scaled(s.referenceToTest.mean),
                                                         scaled(s.testToReference.max),
                                                         scaled(s.testToReference.mean),
                                                         scaledOpt(r.rmse),
                                                         scaledOpt(r.meanError)};
      std::printf("%6zu %6d %6d %8zu %8zu", k, r.referenceFrame, r.testFrame, r.referenceVertices,
                  r.testVertices);
      for (const auto& v : values)
        std::printf(" %11s", textCell(v).c_str());
      std::printf("\n");
      csv += std::to_string(k) + "," + std::to_string(r.referenceFrame) + "," +
             std::to_string(r.testFrame) + "," + std::to_string(r.referenceVertices) + "," +
             std::to_string(r.testVertices);
      for (const auto& v : values)
        csv += "," + csvCell(v);
      csv += ",,,,," + unitName + "," + format(diagonal) + "\n";
    }

    const double n = static_cast<double>(frames);
    std::optional<double> rmse, da, kg, stedSpatial, stedTemporal, stedCombined;
    if (vertexErrorsMissing.empty()) {
      rmse = sequenceErrors.vertexRmse();
      da = sequenceErrors.temporalAverageError();
      kg = sequenceErrors.kgError();
    }
    if (stedMissing.empty()) {
      stedSpatial = stedErrors.spatial();
      stedTemporal = stedErrors.temporal();
      stedCombined = stedErrors.combined();
    }
    const std::vector<std::optional<double>> summary = {scaled(hausdorffMax),
                                                        scaled(hausdorffMeanSum / n),
                                                        scaled(rtMax),
                                                        scaled(rtMeanSum / n),
                                                        scaled(trMax),
                                                        scaled(trMeanSum / n),
                                                        scaledOpt(rmse),
                                                        scaledOpt(da),
                                                        kg,
                                                        stedSpatial,
                                                        stedTemporal,
                                                        stedCombined};
    csv += "all,,,,";
    for (const auto& v : summary)
      csv += "," + csvCell(v);
    csv += "," + unitName + "," + format(diagonal) + "\n";
    if (!p.csvFile.empty()) writeFileAtomic(p.csvFile, csv);

    auto line = [](const char* name, const std::optional<double>& value, const char* note) {
      std::printf("%-22s: %s%s\n", name, textCell(value).c_str(), value ? note : "");
    };
    std::printf("# summary\n");
    std::printf("%-22s: %zu\n", "frames", frames);
    line("Hausdorff max", summary[0], "  (largest over frames)");
    line("Hausdorff mean", summary[1], "  (mean over frames)");
    line("reference->test max", summary[2], "");
    line("reference->test mean", summary[3], "");
    line("test->reference max", summary[4], "");
    line("test->reference mean", summary[5], "");
    line("vertex RMSE", summary[6], "  (all frames and vertices)");
    line("D_A", summary[7], "  (mean Euclidean vertex error)");
    line("KG error", summary[8], " %");
    line("STED_s", summary[9], "  (spatial: local deviation of relative edge differences)");
    line("STED_t", summary[10], "  (temporal: relative temporal edge differences)");
    line("STED", summary[11], "  (sqrt(STED_s^2 + c^2 STED_t^2))");
    if (!vertexErrorsMissing.empty())
      std::printf("%-22s: %s\n", "no vertex errors", vertexErrorsMissing.c_str());
    if (!stedMissing.empty()) std::printf("%-22s: %s\n", "no STED", stedMissing.c_str());
    if (!p.csvFile.empty()) std::printf("%-22s: %s\n", "csv", p.csvFile.c_str());
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%-22s: %.3f s\n", "time", seconds);
    return 0;
  });
}
