#include "encoder/encoder.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "bitstream/header_hash.h"
#include "bitstream/syntax.h"
#include "common/core/config.h"
#include "common/core/error.h"
#include "common/core/md5.h"
#include "common/core/warnings.h"
#include "common/media/dataset.h"
#include "encoder/input_frames.h"
#include "encoder/quality.h"
#include "encoder/texture_encoder.h"

namespace tdvo {

// The option table is bound to the fields of `params` (it must not move: State is held by
// pointer). `resolved` is what encode() uses: the keys checked, and with a Dataset its frame
// numbers and rate where the keys leave them open.
struct Encoder::State {
  EncoderParams params;
  OptionTable table{"3dvo-enc", "3dvo-enc -c cfg/FILE.cfg [-c ...] [--Key=value ...]"};
  std::optional<EncoderParams> resolved;
  std::optional<Dataset> dataset;
  Grid grid;                  // the last encode()'s
  std::string qualityReport;  // the last encode()'s (resolveQuality)
  EncoderParams coded;        // the last encode()'s parameters, Quality resolved

  State() { params.registerOptions(table); }
};

Encoder::Encoder() : s_(std::make_unique<State>()) {}
Encoder::Encoder(Encoder&&) noexcept = default;
Encoder& Encoder::operator=(Encoder&&) noexcept = default;
Encoder::~Encoder() = default;

void Encoder::set(const std::string& key, const std::string& value) {
  s_->resolved.reset();
  // Named as 3dvo-enc names a --Key=value option, so that errors read the same.
  s_->table.set(key, value, "option --" + key + "=" + value);
}

void Encoder::readConfig(const std::string& path) {
  s_->resolved.reset();
  s_->table.parseFile(path);
}

std::string Encoder::effectiveConfig() const {
  return s_->table.effectiveConfig();
}

const Grid& Encoder::grid() const {
  return s_->grid;
}

const std::string& Encoder::qualityReport() const {
  return s_->qualityReport;
}

const EncoderParams& Encoder::codedParams() const {
  return s_->coded;
}

bool Encoder::wasSet(const std::string& key) const {
  return s_->table.wasSet(key);
}

OptionTable& Encoder::options() {
  s_->resolved.reset();
  return s_->table;
}

const EncoderParams& Encoder::params() {
  State& s = *s_;
  if (s.resolved) return *s.resolved;
  EncoderParams p = s.params;
  p.validateCoding();
  const IsSetFunction isSet = [&s](const std::string& key) { return s.table.wasSet(key); };
  for (const char* key : {"BMeshQuantStep", "BMeshLambdaGrowth"})
    check(!isSet(key) || p.bMeshGap > 0 || qualityCodesBMeshes(p, isSet),
          std::string(key) +
              " is set, but no B meshes are coded: set BMeshGap (2 or more), or let Quality "
              "code them (PMeshMode d3dmc, no keyframe key, GridBits and MotionQuantStep not "
              "set)");
  s.dataset.reset();
  if (!p.dataset.empty()) {
    s.dataset = readDataset(p.dataset);
    // Frame numbers are the dataset's (frames.first + index): start at its first frame ...
    if (!s.table.wasSet("FirstFrame")) {
      check(s.dataset->firstFrame >= 0 &&
                static_cast<uint32_t>(s.dataset->firstFrame) <= kMaxFirstFrame,
            s.dataset->resolve(kDatasetFileName) + ": frames.first " +
                std::to_string(s.dataset->firstFrame) + " is outside FirstFrame's range 0 .. " +
                std::to_string(kMaxFirstFrame) + " (the stream's frame numbers)");
      p.firstFrame = s.dataset->firstFrame;
    }
    // ... and its frame rate, which the stream carries to the decoded dataset.
    if (!s.table.wasSet("FrameRate")) {
      check(s.dataset->frameRate >= 0.001 && s.dataset->frameRate <= 1000,
            s.dataset->resolve(kDatasetFileName) +
                ": frames.rate is outside FrameRate's range 0.001 .. 1000; set FrameRate");
      p.frameRate = s.dataset->frameRate;
    }
  }
  s.resolved = std::move(p);
  return *s.resolved;
}

const Dataset* Encoder::dataset() {
  params();
  return s_->dataset ? &*s_->dataset : nullptr;
}

namespace {

// Every index of `triangles` below `count`, the number of `values` the frame has (`what`: one of
// them).
void checkIndices(const std::vector<Triangle>& triangles, size_t count, const std::string& name,
                  const char* what, const char* values) {
  for (size_t t = 0; t < triangles.size(); ++t)
    for (uint32_t i : triangles[t])
      check(i < count, name + ": triangle " + std::to_string(t) + ": " + what + " index " +
                           std::to_string(i) + " out of range (the frame has " +
                           std::to_string(count) + " " + values + ")");
}

// A frame given from memory, checked as a mesh file's reader checks one: positions finite and
// within the readers' range, triangle indices within the positions; counts within the codec's
// limits (bitstream/syntax.h).
void checkFrame(const Mesh& mesh, const std::string& name) {
  check(!mesh.positions.empty(), name + ": no vertices");
  check(!mesh.triangles.empty(), name + ": no faces");
  check(mesh.positions.size() <= kMaxVertices,
        name + ": more than " + std::to_string(kMaxVertices) + " vertices (the codec's limit)");
  check(mesh.triangles.size() <= kMaxTriangles,
        name + ": more than " + std::to_string(kMaxTriangles) + " triangles (the codec's limit)");
  for (size_t v = 0; v < mesh.positions.size(); ++v)
    for (double c : mesh.positions[v]) {
      check(std::isfinite(c),
            name + ": vertex " + std::to_string(v) + " has a non-finite coordinate");
      check(!isBeyondCoordinateRange(c), name + ": vertex " + std::to_string(v) + ": coordinate " +
                                             coordinateText(c) + kBeyondCoordinateRange);
    }
  checkIndices(mesh.triangles, mesh.positions.size(), name, "vertex", "vertices");
  // Texture coordinates and normals (mesh.h): one index triangle per triangle, indices within
  // the values, finite values.
  const MeshAttributes& a = mesh.attributes;
  check(a.uvs.empty() == a.uvTriangles.empty() && a.normals.empty() == a.normalTriangles.empty(),
        name + ": texture coordinates or normals without their index triangles (or the reverse)");
  check(a.uvTriangles.empty() || a.uvTriangles.size() == mesh.triangles.size(),
        name + ": " + std::to_string(a.uvTriangles.size()) + " texture-coordinate triangles for " +
            std::to_string(mesh.triangles.size()) + " triangles");
  check(a.normalTriangles.empty() || a.normalTriangles.size() == mesh.triangles.size(),
        name + ": " + std::to_string(a.normalTriangles.size()) + " normal triangles for " +
            std::to_string(mesh.triangles.size()) + " triangles");
  checkIndices(a.uvTriangles, a.uvs.size(), name, "texture-coordinate", "texture coordinates");
  checkIndices(a.normalTriangles, a.normals.size(), name, "normal", "normals");
  for (const Vec2f& uv : a.uvs)
    check(std::isfinite(uv[0]) && std::isfinite(uv[1]),
          name + ": a texture coordinate is not finite");
  for (const Vec3f& n : a.normals)
    check(std::isfinite(n[0]) && std::isfinite(n[1]) && std::isfinite(n[2]),
          name + ": a normal is not finite");
}

}  // namespace

EncodedSequence Encoder::encode(const std::vector<Mesh>& frames, const FrameCallback& onFrame,
                                const TextureCallback& onTexture) {
  FrameSource source;
  source.count = frames.size();
  source.name = [](size_t k) { return "frame " + std::to_string(k); };
  source.read = [&frames](size_t k) { return frames[k]; };  // checked by the encode below
  EncodedSequence coded = encode(source, onFrame, onTexture);
  coded.frameInputIndex.clear();
  return coded;
}

EncodedSequence Encoder::encode(const FrameSource& given, const FrameCallback& onFrame,
                                const TextureCallback& onTexture,
                                const std::function<void(size_t frame)>& onFramesRead) {
  // A frame read more than once (the bounds pass, Quality's trial, the coding) warns once.
  WarnOnceScope once;
  // Every frame is checked as it is read, like a mesh file (finite positions, triangle indices
  // within its vertices), whatever the source: the coding tools assume it.
  FrameSource source = given;
  source.read = [&given](size_t k) {
    Mesh mesh = given.read(k);
    checkFrame(mesh, given.name(k));
    return mesh;
  };
  EncoderParams p = params();
  const Dataset* input = dataset();
  check(source.count > 0, "no frames to encode");
  check(p.frameCount == 0 || static_cast<size_t>(p.frameCount) == source.count,
        "FrameCount " + std::to_string(p.frameCount) + " but " + std::to_string(source.count) +
            " frames given");
  p.frameCount = static_cast<int>(source.count);
  p.goms(source.count);  // a GOMListFile is checked against the frames before any is read
  if (input) checkTextureFrames(p, *input, p.frameCount);

  std::optional<TextureBoxFinder> boxes;
  if (input) boxes.emplace(p, *input, source.count);
  const IsSetFunction isSet = [this](const std::string& key) { return s_->table.wasSet(key); };
  // The frames Quality's trial codes, kept from the bounds pass for the trial: like every frame
  // they are read twice (bounds, encode), not a third time for the trial.
  std::vector<size_t> trialFrames;  // in frame order
  for (const TrialWindow& w : qualityTrialWindows(p, source.count, isSet))
    for (size_t k = w.first; k < w.first + w.count; ++k)
      trialFrames.push_back(k);
  std::vector<Mesh> kept(trialFrames.size());
  auto keptIndex = [&trialFrames](size_t k) {
    const auto at = std::lower_bound(trialFrames.begin(), trialFrames.end(), k);
    return at != trialFrames.end() && *at == k ? static_cast<size_t>(at - trialFrames.begin())
                                               : trialFrames.size();
  };
  const SequenceBounds bounds =
      boundsOfSequence(source, p.threadCount(), onFramesRead, [&](size_t k, const Mesh& mesh) {
        if (boxes) boxes->add(mesh);
        const size_t i = keptIndex(k);
        if (i < kept.size()) kept[i] = mesh;  // each k from one thread: no lock
      });
  // Quality's choices, with the keys the user set kept (encoder/quality.h).
  s_->qualityReport.clear();
  {
    FrameSource trial = source;
    trial.read = [&kept, &keptIndex](size_t k) { return kept.at(keptIndex(k)); };
    p = resolveQuality(p, bounds, trial, isSet, &s_->qualityReport);
  }
  s_->coded = p;
  kept = {};  // the encode holds no more than its GOMs
  const Grid grid = s_->grid = gridFor(bounds, p.gridBits, p.gridFit);
  std::unique_ptr<TextureEncoder> textures;
  if (boxes) textures = std::make_unique<TextureEncoder>(p, *input, boxes->boxes());

  // The MD5 lines in the order 3dvo-enc prints them: a GOM's frame lines, then its texture
  // lines, then the header line (docs/bitstream.md, section 8).
  std::vector<std::string> lines;
  EncodedSequence coded = encodeSequence(
      p, grid, source,
      [&](int frame, const IntMesh& recon) {
        lines.push_back(geometryHashLine(p.firstFrame + frame, recon));
        if (onFrame) onFrame(frame, recon);
      },
      textures.get(),
      [&](int frame, int camera, const YuvPicture& picture, const Image& shape) {
        lines.push_back(textureHashLine(p.firstFrame + frame, camera, picture));
        if (onTexture) onTexture(frame, camera, picture, shape);
      });
  lines.push_back(sequenceHeaderHashLine(coded.stream, "the encoded stream"));
  coded.md5Lines = std::move(lines);
  warnIfDecodersRefuse(coded.stream);
  return coded;
}

}  // namespace tdvo
