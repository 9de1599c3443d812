#include "encoder/gom_coder.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include "bitstream/syntax.h"
#include "common/core/error.h"
#include "common/geometry/keyframes.h"
#include "decoder/pmesh_decoder.h"
#include "encoder/keyframe_selection.h"
#include "encoder/pmesh_encoder.h"

namespace tdvo {

namespace {

class GomCoder {
 public:
  GomCoder(const EncoderParams& params, const Grid& grid, size_t first, std::vector<Mesh> frames,
           const std::function<std::string(size_t)>& frameName, const GomContinuation* continuation,
           GomContinuation* next)
      : params_(params),
        grid_(grid),
        first_(first),
        frames_(std::move(frames)),
        frameName_(frameName),
        continuation_(continuation),
        next_(next) {
    pmParams_.gridBits = params.gridBits;
    pmParams_.quantStep = params.motionQuantStep;
    pmParams_.maxDepth = std::min(params.maxOctreeDepth, params.gridBits);
  }

  GomGeometry code() {
    const size_t count = frames_.size();
    const bool pMeshes = params_.pmeshMode != PMeshMode::kIntra;
    // Only the quantised frames are kept: each input mesh is released once on the grid, and in a
    // GOM of P meshes only the first frame keeps its triangles (memory is what bounds the
    // largest meshes a GOM can hold).
    std::vector<IntMesh> inputs;
    for (Mesh& mesh : frames_) {
      inputs.push_back(grid_.quantise(mesh));
      mesh = Mesh();
      // In a GOM of P meshes the first frame speaks for all (the others must have its triangles).
      countDegenerateTriangles(inputs.size() - 1, inputs.back());
    }
    if (pMeshes) {
      checkConstantConnectivity(inputs);
      for (size_t k = 1; k < count; ++k)
        std::vector<Triangle>().swap(inputs[k].triangles);
    }

    const size_t inputVertices = inputs[0].positions.size();
    // Continue the previous GOM's connectivity (no I mesh) when it is the same.
    const bool continues = pMeshes && continuation_ && continuation_->iMesh &&
                           continuation_->inputVertices == inputVertices &&
                           continuation_->inputTriangles == inputs[0].triangles;

    GomHeader gh;
    gh.gh_random_access = continues ? 0 : 1;
    gh.gh_first_frame = static_cast<uint32_t>(first_);
    gh.gh_frame_count = static_cast<uint16_t>(count);
    gh.gh_pmesh_mode = static_cast<uint8_t>(params_.pmeshMode);
    gh.gh_motion_quant_step = static_cast<uint16_t>(pmParams_.quantStep);
    gh.gh_max_octree_depth = static_cast<uint8_t>(pmParams_.maxDepth);
    if (pMeshes) {
      std::vector<std::vector<Vec3i>> positions;
      for (const IntMesh& m : inputs)
        positions.push_back(m.positions);
      const std::vector<int> keys =
          selectKeyframes(positions, params_.keyframeCount, params_.keyframeMaxError);
      gh.keyframes.assign(keys.begin(), keys.end());
    }
    out_.units.push_back({UnitType::kGomHeader, serialise(gh)});

    if (!pMeshes) {
      if (next_) *next_ = GomContinuation();
      for (size_t k = 0; k < count; ++k) {
        codeIMesh(k, inputs[k]);
        emit(out_.iMeshes.back().decoded.positions, std::move(inputs[k].positions));
      }
      return std::move(out_);
    }

    if (continues)
      out_.iMeshes.push_back(*continuation_->iMesh);
    else
      codeIMesh(0, inputs[0]);
    const IMeshEncoding& i = out_.iMeshes.back();
    const GomTopology topology =
        params_.pmeshMode == PMeshMode::kD3dmc ? GomTopology::build(i.decoded) : GomTopology();
    std::vector<Vec3i> previous, target(i.inputIndex.size());
    if (continues) {
      // The first frame: a P mesh from the previous GOM's last frame.
      for (size_t j = 0; j < target.size(); ++j)
        target[j] = inputs[0].positions[i.inputIndex[j]];
      previous = codePMesh(0, topology, continuation_->last, target);
    } else {
      previous = i.decoded.positions;
    }
    emit(previous, std::move(inputs[0].positions));
    for (size_t n = 1; n < gh.keyframes.size(); ++n) {
      const int a = gh.keyframes[n - 1], b = gh.keyframes[n];
      // The keyframe's target in the GOM's vertex order (Draco's decoded order).
      for (size_t j = 0; j < target.size(); ++j)
        target[j] = inputs[b].positions[i.inputIndex[j]];
      std::vector<Vec3i> key = codePMesh(b, topology, previous, target);
      for (int f = a + 1; f < b; ++f)
        emit(interpolateFrame(previous, key, a, b, f), std::move(inputs[f].positions));
      emit(key, std::move(inputs[b].positions));
      previous = std::move(key);
    }
    if (next_) {
      next_->iMesh = continues ? continuation_->iMesh
                               : std::make_shared<const IMeshEncoding>(out_.iMeshes.back());
      next_->inputTriangles = std::move(inputs[0].triangles);
      next_->inputVertices = inputVertices;
      next_->last = std::move(previous);
    }
    return std::move(out_);
  }

 private:
  std::string name(size_t k) const { return frameName_(first_ + k); }

  // Triangles with a repeated vertex have no area and no orientation; Draco's Edgebreaker cannot
  // code them (draco_encoder drops them). They are kept, in every mode: the VERTEX_ORDER unit
  // carries them (encodeIMesh); codeIMesh counts them in a warning. A mesh of nothing else has
  // no surface to code.
  void countDegenerateTriangles(size_t k, const IntMesh& mesh) const {
    const bool any =
        std::any_of(mesh.triangles.begin(), mesh.triangles.end(),
                    [](const Triangle& t) { return t[0] != t[1] && t[1] != t[2] && t[0] != t[2]; });
    check(any, name(k) + ": every triangle has a repeated vertex: no triangle is left to code");
  }

  // P meshes carry positions only: the GOM's frames must share the first frame's connectivity.
  void checkConstantConnectivity(const std::vector<IntMesh>& inputs) const {
    const IntMesh& a = inputs[0];
    for (size_t k = 1; k < inputs.size(); ++k) {
      const IntMesh& b = inputs[k];
      check(a.positions.size() == b.positions.size(),
            name(k) + ": " + std::to_string(b.positions.size()) +
                " vertices, but the GOM's first frame (" + name(0) + ") has " +
                std::to_string(a.positions.size()) +
                " (P meshes need constant connectivity; use GOMSize or PMeshMode intra)");
      check(a.triangles == b.triangles, name(k) +
                                            ": connectivity differs from the GOM's first frame (" +
                                            name(0) + "); P meshes need constant connectivity");
    }
  }

  void codeIMesh(size_t k, const IntMesh& input) {
    IMeshEncoding i =
        encodeIMesh(input, params_.gridBits, params_.dracoSpeed, params_.inputTriangleOrder);
    // Draco does not keep vertices that no triangle uses; say so rather than drop them quietly.
    if (i.decoded.positions.size() != input.positions.size())
      out_.warnings.push_back(name(k) + ": " + std::to_string(input.positions.size()) +
                              " vertices in, " + std::to_string(i.decoded.positions.size()) +
                              " coded (Draco drops vertices no triangle uses and splits "
                              "non-manifold ones)");
    if (i.keptDegenerate + i.droppedDegenerate > 0)
      out_.warnings.push_back(
          name(k) + ": " + std::to_string(i.keptDegenerate + i.droppedDegenerate) + " of " +
          std::to_string(input.triangles.size()) +
          " triangles have a repeated vertex (degenerate); kept (carried outside Draco)" +
          (i.droppedDegenerate > 0 ? ", except " + std::to_string(i.droppedDegenerate) +
                                         " using a vertex no other triangle uses: dropped"
                                   : std::string()));
    if (i.unmatchedTriangles > 0)
      out_.warnings.push_back(name(k) + ": " + std::to_string(i.unmatchedTriangles) +
                              " decoded triangles have no input twin; P meshes of this GOM "
                              "may predict poorly");
    IMeshUnit im;
    im.im_frame = static_cast<uint32_t>(first_ + k);
    im.im_draco_payload = i.payload;
    out_.units.push_back({UnitType::kIMesh, serialise(std::move(im))});
    VertexOrderUnit vo;
    vo.vo_frame = static_cast<uint32_t>(first_ + k);
    vo.vo_num_vertices = i.order.numVertices;
    vo.vo_triangle_order = i.triangleOrder ? 1 : 0;
    vo.vo_cabac_payload = i.orderPayload;
    out_.units.push_back({UnitType::kVertexOrder, serialise(std::move(vo))});
    out_.iMeshes.push_back(std::move(i));
  }

  std::vector<Vec3i> codePMesh(size_t k, const GomTopology& topology,
                               const std::vector<Vec3i>& previous,
                               const std::vector<Vec3i>& target) {
    const bool d3dmc = params_.pmeshMode == PMeshMode::kD3dmc;
    PMeshEncoding p =
        d3dmc ? encodePMesh(topology, previous, target, pmParams_, params_.effectiveLambda())
              : encodeTemporalDpcm(previous, target, pmParams_);
    // Closed loop: what the decoder makes of the payload must be the encoder's
    // reconstruction, bit for bit.
    const std::string context = "encoder's own P mesh";
    if (d3dmc)
      decodePMesh(p.payload.data(), p.payload.size(), topology, previous, pmParams_, context, work_,
                  decoded_);
    else
      decodeTemporalDpcm(p.payload.data(), p.payload.size(), previous, pmParams_, context,
                         decoded_);
    if (decoded_ != p.reconstruction)
      throw std::logic_error("P-mesh reconstruction differs from the decoder's (frame " +
                             std::to_string(first_ + k) + ")");
    PMeshUnit pm;
    pm.pm_frame = static_cast<uint32_t>(first_ + k);
    pm.pm_cabac_payload = std::move(p.payload);
    out_.units.push_back({UnitType::kPMesh, serialise(std::move(pm))});
    return std::move(p.reconstruction);
  }

  // The next frame of the GOM is final; `input` (its quantised input positions) is not needed
  // here any more.
  void emit(std::vector<Vec3i> positions, std::vector<Vec3i>&& input) {
    out_.frames.push_back({std::move(positions), out_.iMeshes.size() - 1, std::move(input)});
  }

  const EncoderParams& params_;
  const Grid& grid_;
  size_t first_;
  std::vector<Mesh> frames_;  // released frame by frame as they are quantised
  const std::function<std::string(size_t)>& frameName_;
  const GomContinuation* continuation_;
  GomContinuation* next_;
  PMeshParams pmParams_;
  PMeshWorkspace work_;         // the closed-loop decoder's buffers, reused frame to frame
  std::vector<Vec3i> decoded_;  // its output
  GomGeometry out_;
};

}  // namespace

GomGeometry encodeGomGeometry(const EncoderParams& params, const Grid& grid, size_t first,
                              std::vector<Mesh> frames,
                              const std::function<std::string(size_t)>& frameName,
                              const GomContinuation* continuation, GomContinuation* next) {
  check(!frames.empty(), "a GOM needs at least one frame");
  return GomCoder(params, grid, first, std::move(frames), frameName, continuation, next).code();
}

}  // namespace tdvo
