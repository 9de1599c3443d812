// The GOM decoding process (docs/bitstream.md, sections 4 and 5): a GOM's frames, in frame
// order, from its coded units: each frame's I mesh in an intra GOM; in a GOM of P meshes the
// I mesh (or the previous GOM's last frame), the P mesh of every further keyframe predicted from
// the previous keyframe (d3dmc or afxic, by gh_pmesh_mode), and the frames between keyframes
// interpolated or, in a GOM of B meshes, each coded as a B mesh predicted from the interpolation
// of the nearest decoded frames around it (docs/bitstream.md, "B meshes"). Written once: the stream
// decoder (its geometry pass and its texture pass, decoder/stream_decoder.cpp) and the encoder's
// closed loop (encoder/gom_coder.cpp) all make their frames with a GomDecoder, so the encoder's
// reconstruction is the decoder's.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "bitstream/pmesh_syntax.h"
#include "bitstream/syntax.h"
#include "common/core/mesh.h"

namespace tdvo {

// A P mesh's CABAC payload as a GomDecoder reads it.
struct PMeshPayload {
  const uint8_t* data = nullptr;  // valid until the GomDecoder asks for the next unit
  size_t size = 0;
  std::string where;           // names the unit in error messages
  std::FILE* trace = nullptr;  // receives every syntax element read, when given
};

// Where a GomDecoder takes a GOM's coded frames from, as it needs them: in stream order, each
// once. The stream decoder reads them from the stream; the encoder codes them on demand.
class GomUnits {
 public:
  virtual ~GomUnits() = default;
  // The decoded I mesh of the GOM's frame `k` (every frame of an intra GOM; frame 0 of a GOM
  // of P meshes that is a random access point), into `mesh`; `where` names it in messages
  // about its connectivity (GomTopology::build).
  virtual void iMesh(uint32_t k, IntMesh& mesh, std::string& where) = 0;
  // The P mesh of the GOM's keyframe `k` (offset in the GOM), or the B mesh of its frame `k`.
  virtual PMeshPayload pMesh(uint32_t k) = 0;
};

// What a GOM of P meshes starts from: the connectivity (the I mesh's triangles, in the GOM's
// vertex order) with the positions of its first reference (the I mesh's, or the previous GOM's
// last frame, which a continuing GOM's first P mesh is predicted from), and the topology of
// d3dmc prediction (null until a d3dmc GOM needs it).
struct GomReference {
  IntMesh mesh;
  std::shared_ptr<const GomTopology> topology;
};

class GomDecoder {
 public:
  GomDecoder() = default;
  // Not copied or moved: reference() and params() point into the decoder itself.
  GomDecoder(const GomDecoder&) = delete;
  GomDecoder& operator=(const GomDecoder&) = delete;

  // Starts GOM `gh` of a stream whose grid has `gridBits` bits; `where` names its GOM header
  // in messages. A GOM with gh_random_access 0 continues this decoder's last GOM of P meshes,
  // or `first` when given. With `first` and gh_random_access 1, `first` is the GOM's I mesh
  // (no I mesh is asked for). Throws Error when gh_random_access is 0 and there is nothing to
  // continue, or when a d3dmc GOM's gh_max_octree_depth exceeds the grid's bits.
  void start(const GomHeader& gh, int gridBits, const std::string& where,
             const GomReference* first = nullptr);

  // Makes the GOM's next frame (`produced()` before the call) and returns its positions, in the
  // GOM's vertex order, valid until the next call; `triangles()` is its connectivity. Asks
  // `units` for the I and P meshes it needs. Throws Error on a malformed unit.
  const std::vector<Vec3i>& next(GomUnits& units);
  const std::vector<Triangle>& triangles() const { return mesh_.triangles; }
  uint32_t produced() const { return produced_; }
  // Decoded frames waiting to be handed out (with B meshes: at most about log2 of the keyframe
  // gap + 1; otherwise at most the next keyframe).
  size_t waitingFrames() const { return bMeshes_ ? stackSize_ : 1; }
  bool done() const { return produced_ == frameCount_; }

  // With `keep`, the first reference of every GOM of P meshes is kept (a copy of one frame) for
  // firstReference(): the stream decoder's texture pass makes the GOM's frames again from it.
  void keepFirstReference(bool keep) { keepFirst_ = keep; }
  // Valid once the first frame of a GOM of P meshes has been made (with keepFirstReference).
  const GomReference& firstReference() const { return first_; }

  // After a GOM of P meshes: the next GOM may continue it (gh_random_access 0); the vertices
  // of the connectivity it would continue.
  bool canContinue() const { return canContinue_; }
  size_t continuedVertices() const { return canContinue_ ? previous_.size() : 0; }
  // Forgets the last GOM: the next GOM cannot continue it (the stream decoder skips intra GOMs
  // before a frame range without decoding them).
  void clearContinuation() { canContinue_ = false; }

  // In a GOM of P meshes, only while a P or B mesh is asked for (GomUnits::pMesh): the
  // positions it is predicted from (the previous decoded keyframe, or a B mesh's interpolated
  // reference) and its parameters (a B mesh's quantiser is gh_bmesh_quant_step); and the GOM's
  // topology (d3dmc).
  // std::logic_error when no P or B mesh is being asked for.
  const std::vector<Vec3i>& reference() const;
  const PMeshParams& params() const;
  const GomTopology& topology() const { return *topology_; }

 private:
  void startPMeshes(GomUnits& units);
  // Decodes the P or B mesh of GOM frame `k` from `reference` into `out`.
  void decodeMesh(GomUnits& units, uint32_t k, const std::vector<Vec3i>& reference,
                  const PMeshParams& params, std::vector<Vec3i>& out);
  const std::vector<Vec3i>& nextWithBMeshes(GomUnits& units, uint32_t f, int a, int b);

  PMeshMode mode_ = PMeshMode::kIntra;
  bool randomAccess_ = true;
  uint32_t frameCount_ = 0;
  std::vector<uint16_t> keyframes_;
  PMeshParams params_;
  PMeshParams bParams_;  // a B mesh's: params_ with gh_bmesh_quant_step
  bool bMeshes_ = false;
  std::string where_;
  const GomReference* given_ = nullptr;  // start()'s `first`, until the first frame is made
  bool keepFirst_ = false;
  GomReference first_;
  bool canContinue_ = false;

  uint32_t produced_ = 0;
  size_t n_ = 0;  // the keyframe interval being made: keyframes n_ - 1 .. n_
  IntMesh mesh_;  // the connectivity; positions: the intra frame, or the interpolated frame
  std::shared_ptr<const GomTopology> topology_;
  std::vector<Vec3i> previous_, key_;  // the previous decoded keyframe, the next one
  // With B meshes: previous_ is the last frame handed out, and the decoded frames to the right
  // of it wait in a stack, the nearest on top: stackFrames_[0 .. stackSize_) are their GOM
  // offsets, stack_[i] their positions (buffers kept for reuse). At most about log2 of the
  // keyframe gap + 1 frames.
  std::vector<int> stackFrames_;
  std::vector<std::vector<Vec3i>> stack_;
  size_t stackSize_ = 0;
  std::vector<Vec3i> interpolated_;  // a B mesh's reference
  // What reference() and params() return: set by decodeMesh before it asks for the unit.
  const std::vector<Vec3i>* reference_ = nullptr;
  const PMeshParams* pendingParams_ = nullptr;
  PMeshWorkspace work_;
};

}  // namespace tdvo
