#include "decoder/gom_decoder.h"

#include <stdexcept>
#include <utility>

#include "common/core/error.h"
#include "common/geometry/keyframes.h"
#include "decoder/pmesh_decoder.h"

namespace tdvo {

void GomDecoder::start(const GomHeader& gh, int gridBits, const std::string& where,
                       const GomReference* first) {
  mode_ = codingMode(gh);
  bMeshes_ = hasBMeshes(gh);
  params_.gridBits = gridBits;
  params_.quantStep = gh.gh_motion_quant_step;
  params_.maxDepth = gh.gh_max_octree_depth;
  bParams_ = params_;
  bParams_.quantStep = gh.gh_bmesh_quant_step;
  stackSize_ = 0;
  if (mode_ == PMeshMode::kD3dmc && gh.gh_max_octree_depth > gridBits)
    throw Error(where + ": gh_max_octree_depth " + std::to_string(gh.gh_max_octree_depth) +
                " exceeds sh_grid_bits " + std::to_string(gridBits));
  randomAccess_ = gh.gh_random_access != 0;
  if (mode_ != PMeshMode::kIntra && !randomAccess_ && !first && !canContinue_)
    throw Error(where + ": gh_random_access 0, but no previous GOM of P meshes to continue");
  frameCount_ = gh.gh_frame_count;
  keyframes_ = gh.keyframes;
  where_ = where;
  given_ = first;
  produced_ = 0;
  n_ = 0;
  first_ = GomReference();
  canContinue_ = mode_ != PMeshMode::kIntra;
}

// Frame 0 of a GOM of P meshes: its first reference, and the topology d3dmc predicts with.
void GomDecoder::startPMeshes(GomUnits& units) {
  std::string where = where_;
  if (given_) {
    mesh_ = given_->mesh;
    topology_ = given_->topology;
    previous_ = mesh_.positions;
  } else if (randomAccess_) {
    units.iMesh(0, mesh_, where);
    topology_.reset();
    previous_ = mesh_.positions;
  }
  // else: a continuing GOM keeps the connectivity, topology and last keyframe it continues.
  given_ = nullptr;
  if (mode_ == PMeshMode::kD3dmc && !topology_) try {
      mesh_.positions.swap(previous_);  // the reference's positions (the topology needs the count)
      topology_ = std::make_shared<const GomTopology>(GomTopology::build(mesh_));
      mesh_.positions.swap(previous_);
    } catch (const Error& e) {  // the connectivity: name the unit that gave it
      throw Error(where + ": " + e.what());
    }
  if (keepFirst_) first_ = {IntMesh{previous_, mesh_.triangles, {}}, topology_};
  n_ = randomAccess_ ? 1 : 0;  // a random access point's keyframe 0 is its I mesh
}

const std::vector<Vec3i>& GomDecoder::next(GomUnits& units) {
  const uint32_t f = produced_++;
  if (mode_ == PMeshMode::kIntra) {
    std::string where;
    units.iMesh(f, mesh_, where);
    return mesh_.positions;
  }
  if (f == 0) {
    startPMeshes(units);
    if (randomAccess_) return previous_;  // the I mesh
  }
  // Frames a + 1 .. b come from keyframes a and b (a = -1: the first P mesh of a continuing
  // GOM, predicted from the previous GOM's last frame).
  const int a = n_ > 0 ? keyframes_[n_ - 1] : -1, b = keyframes_[n_];
  if (bMeshes_) return nextWithBMeshes(units, f, a, b);
  if (static_cast<int>(f) == a + 1)
    decodeMesh(units, static_cast<uint32_t>(b), previous_, params_, key_);
  if (static_cast<int>(f) < b) {
    interpolateFrame(previous_, key_, a, b, static_cast<int>(f), mesh_.positions);
    return mesh_.positions;
  }
  previous_.swap(key_);  // the keyframe is handed out and is the next one's reference
  ++n_;
  return previous_;
}

const std::vector<Vec3i>& GomDecoder::reference() const {
  if (!reference_) throw std::logic_error("GomDecoder::reference(): no P or B mesh is asked for");
  return *reference_;
}

const PMeshParams& GomDecoder::params() const {
  if (!pendingParams_) throw std::logic_error("GomDecoder::params(): no P or B mesh is asked for");
  return *pendingParams_;
}

void GomDecoder::decodeMesh(GomUnits& units, uint32_t k, const std::vector<Vec3i>& reference,
                            const PMeshParams& params, std::vector<Vec3i>& out) {
  reference_ = &reference;
  pendingParams_ = &params;
  const PMeshPayload p = units.pMesh(k);
  reference_ = nullptr;
  pendingParams_ = nullptr;
  if (mode_ == PMeshMode::kD3dmc)
    decodePMesh(p.data, p.size, *topology_, reference, params, p.where, work_, out, p.trace);
  else
    decodeTemporalDpcm(p.data, p.size, reference, params, p.where, out, p.trace);
}

// Frame f of keyframe interval a .. b in a GOM of B meshes. previous_ is frame f - 1 (the last
// one handed out; keyframe a when f = a + 1). The frames right of it that are decoded already
// wait on the stack, nearest on top; the first is keyframe b, decoded from previous_. While the
// nearest one, r, is not f, the frame m = bMeshMiddle(f - 1, r) half way between is decoded as
// a B mesh from interpolateFrame(f - 1, r) and pushed. The B meshes thus come in the preorder of
// the halving of a .. b (the middle frame, then the left half's, then the right half's), as the
// encoder asked for them, and the frames go out in order.
const std::vector<Vec3i>& GomDecoder::nextWithBMeshes(GomUnits& units, uint32_t f, int a, int b) {
  const auto push = [&](int frame) -> std::vector<Vec3i>& {
    if (stack_.size() == stackSize_) stack_.emplace_back();
    if (stackFrames_.size() == stackSize_) stackFrames_.push_back(0);
    stackFrames_[stackSize_] = frame;
    return stack_[stackSize_++];
  };
  const int left = static_cast<int>(f) - 1;
  if (left == a) decodeMesh(units, static_cast<uint32_t>(b), previous_, params_, push(b));
  while (stackFrames_[stackSize_ - 1] != static_cast<int>(f)) {
    const int r = stackFrames_[stackSize_ - 1];
    const int m = bMeshMiddle(left, r);
    interpolateFrame(previous_, stack_[stackSize_ - 1], left, r, m, interpolated_);
    decodeMesh(units, static_cast<uint32_t>(m), interpolated_, bParams_, push(m));
  }
  previous_.swap(stack_[--stackSize_]);
  if (static_cast<int>(f) == b) ++n_;
  return previous_;
}

}  // namespace tdvo
