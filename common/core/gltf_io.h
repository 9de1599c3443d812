// glTF 2.0 reading and writing (.gltf with external or data-URI buffers, and .glb), positions,
// triangles, texture coordinates (TEXCOORD_0) and normals (NORMAL), through tinygltf (Debian's
// libtinygltf-dev; never a parser of our own).
//
// A file is read as a sequence of frames (docs/user-guide.md, "Mesh files"):
// - the frames are the keyframe times of the file's first animation (all its channels' input
//   times, merged and sorted); a file without an animation is one frame;
// - frame k is what a viewer shows of the default scene at time k (scene 0 when the file names
//   none; without scenes, every node that is no node's child): its node trees depth first in
//   the order listed, every node with a mesh giving the mesh's triangle primitives in order,
//   with the mesh's morph targets applied with the node's weights at that time (animated by the
//   animation's "weights" channel: STEP, LINEAR or CUBICSPLINE; else the node's or the mesh's
//   weights), then moved by the node's transform and its parents' (matrix, or translation,
//   rotation and scale, each possibly animated; rotations interpolated spherically). A node
//   whose scale is (0, 0, 0) hides its subtree; a mirroring transform swaps each triangle's last
//   two corners (its front stays the side a viewer sees); an identity transform changes
//   nothing. Skinned meshes are refused. TEXCOORD_0 and NORMAL become the frame's per-vertex
//   attributes (mesh.h) when every primitive shown has them (normals with the morph targets'
//   NORMAL displacements applied likewise, then turned with the transform). A file without
//   nodes is its meshes, in order.
// So a base mesh with one morph target per frame and a STEP weights animation is a sequence,
// and so is what writeGltfAnimation writes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/core/mesh.h"

namespace tdvo {

// Limits of the glTF reader (docs/robustness.md, "Input files"): a .glb (and each external
// buffer file) at most kMaxBinaryFileBytes (file_io.h), a .gltf at most kMaxGltfJsonBytes; its
// JSON at most kMaxGltfJsonBytes with
// at most kMaxGltfJsonValues values nested at most kMaxGltfJsonDepth deep (tinygltf's model
// grows with the number of JSON values, not with their bytes); each buffer's bytes read once
// (two buffers naming the same file or the same GLB chunk are refused); and a frame's vertices
// and triangles at most one of each per byte of the file and its buffers, and the morph-target
// vertices a frame adds likewise, so that meshes shown by many nodes, or meshes or targets
// sharing their data, cannot make a frame larger, or its work longer, than the file; and
// keyframes x vertices at most kMaxGltfVertexFramesPerByte per input byte.
constexpr size_t kMaxGltfJsonBytes = size_t{1} << 26;
constexpr size_t kMaxGltfJsonValues = size_t{1} << 18;
constexpr size_t kMaxGltfJsonDepth = 64;
// A sequence file's frames cost work in proportion to keyframes x vertices: at most this many
// per byte of the file and its buffers (a morph-target file holds one target per frame, about
// 1/12 per byte; blend-shape animations tens).
constexpr uint64_t kMaxGltfVertexFramesPerByte = 4096;

// A glTF file opened as a frame sequence. The whole file (and its buffers) is held, each frame
// is made when asked for; frame() is const and may be called from several threads at once.
class GltfFile {
 public:
  // Reads `path` (.gltf or .glb, told apart by their content); external buffers are read from
  // the file's folder. Throws Error naming the file for anything that cannot be read.
  explicit GltfFile(const std::string& path);
  // Parses `bytes` held in memory; `name` is used in messages; external buffers are refused.
  GltfFile(const std::vector<uint8_t>& bytes, const std::string& name);
  ~GltfFile();
  GltfFile(GltfFile&&) noexcept;
  GltfFile& operator=(GltfFile&&) noexcept;

  size_t frameCount() const;
  // The keyframe time of frame k in seconds (0 for a file without animation).
  double frameTime(size_t k) const;
  // Frame k (k < frameCount()). Throws Error naming the file and the part at fault.
  Mesh frame(size_t k) const;
  // The frame rate of frames first .. first + count - 1 when their key times are evenly spaced
  // (each within a thousandth of the spacing of its place, beyond float32 rounding): of the
  // rates p / q and p / (1.001 q) (q = 1 .. 12, simplest first), the first the keys are at
  // within float32 rounding, else the one they are nearest; else (count - 1) / (last - first
  // time); nothing for fewer than two frames, frames not in the file or uneven key times.
  std::optional<double> keyRate(size_t first, size_t count) const;

  struct Impl;  // the parsed file (gltf_io.cpp)

 private:
  std::unique_ptr<Impl> impl_;
};

// Frame 0 of a glTF file (a per-frame file).
Mesh readGltf(const std::string& path);

enum class GltfContainer { kGltf, kGlb };

// One mesh as glTF: a .gltf with its buffer as a data URI, or a .glb. Positions are stored as
// float (glTF's POSITION type), indices as unsigned int, in the mesh's order; texture
// coordinates and normals, when present, as float TEXCOORD_0 and NORMAL, made per vertex by
// splitAttributeSeams (mesh_attributes.h: vertex copies at seams follow the original vertices).
std::string formatGltf(const Mesh& mesh, GltfContainer container);
void writeGltf(const std::string& path, const Mesh& mesh, GltfContainer container);

// Builds one animated .glb of a frame sequence (docs/user-guide.md, "Animated glTF"): frames
// are cut into runs of constant connectivity (same vertex count and triangles) of at most
// kMaxGltfRunFrames frames; each run is a node with one mesh whose base is the run's first
// frame and whose morph targets are the other frames' displacements, shown by a STEP weights
// animation (one target at weight 1 per frame) and by a STEP scale animation that shows the
// node during its run only (scale 0 elsewhere). Texture coordinates are the run's (a frame with
// other ones starts a new run); normals are the base's, and each target carries the NORMAL
// displacement to its frame's normals when they differ. Frame k is at time k / frameRate.
class GltfAnimationWriter {
 public:
  explicit GltfAnimationWriter(double frameRate);
  ~GltfAnimationWriter();
  // Throws Error beyond kMaxGltfAnimationFrames frames or kMaxGltfAnimationVertexFrames
  // vertices x frames, or when the frame's time (its index / frame rate) is not a finite float.
  void add(const Mesh& frame);
  size_t frames() const { return frames_; }
  std::string finish();  // the .glb bytes

 private:
  struct Run {
    size_t first = 0;  // first frame
    size_t vertices = 0;
    std::vector<Triangle> triangles;
    std::vector<float> positions;  // frames x vertices x 3
    std::vector<Vec2f> uvs;        // the run's texture coordinates (vertices), if any
    std::vector<float> normals;    // frames x vertices x 3, if any
  };
  double frameRate_;
  size_t frames_ = 0;
  uint64_t vertexFrames_ = 0;
  std::vector<Run> runs_;
};

constexpr size_t kMaxGltfRunFrames = 256;
// What one animation file holds (GltfAnimationWriter::add refuses more): the writer keeps every
// frame until finish() (and the .glb is made in memory), so its memory is bounded by these, not
// by the stream: at most about 250 MB for the frames of a tiny mesh (per-frame accessors and
// weights) and 30 bytes per vertex-frame for large ones (docs/robustness.md, "Memory").
constexpr size_t kMaxGltfAnimationFrames = 16384;
constexpr uint64_t kMaxGltfAnimationVertexFrames = uint64_t{1} << 25;

// Throws Error when an animation file of `frames` frames is more than one holds
// (kMaxGltfAnimationFrames); 3dvo-dec asks before decoding the first frame, the writer on each.
void checkGltfAnimationFrames(uint64_t frames);

}  // namespace tdvo
