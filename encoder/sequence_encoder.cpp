#include "encoder/sequence_encoder.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "bitstream/units.h"
#include "common/error.h"
#include "common/keyframes.h"
#include "decoder/pmesh_decoder.h"
#include "encoder/imesh_encoder.h"
#include "encoder/keyframe_selection.h"
#include "encoder/pmesh_encoder.h"

namespace tdvo {

namespace {

template <class T>
std::vector<uint8_t> serialise(T value) {
  ByteWriter writer;
  transfer(writer, value);
  return writer.take();
}

// Encodes GOM by GOM into `units`, reporting every reconstructed frame in order.
class GomEncoder {
 public:
  GomEncoder(const EncoderParams& params, const Grid& grid, const std::vector<Mesh>& frames,
             const std::vector<std::string>& frameNames, const FrameCallback& onFrame,
             UnitWriter& units, EncodedSequence& out)
      : params_(params),
        grid_(grid),
        frames_(frames),
        frameNames_(frameNames),
        onFrame_(onFrame),
        units_(units),
        out_(out) {
    pmParams_.gridBits = params.gridBits;
    pmParams_.quantStep = params.motionQuantStep;
    pmParams_.maxDepth = std::min(params.maxOctreeDepth, params.gridBits);
  }

  void encodeGom(size_t first, size_t count) {
    const bool pMeshes = params_.pmeshMode != PMeshMode::kIntra;
    std::vector<IntMesh> inputs;
    for (size_t k = 0; k < count; ++k)
      inputs.push_back(grid_.quantise(frames_[first + k]));
    if (pMeshes) checkConstantConnectivity(first, count);

    GomHeader gh;
    gh.gh_first_frame = static_cast<uint32_t>(first);
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
    units_.write(UnitType::kGomHeader, serialise(gh));

    if (!pMeshes) {
      for (size_t k = 0; k < count; ++k) {
        const IMeshEncoding i = codeIMesh(first + k, inputs[k]);
        emit(first + k, i.decoded.positions, i, inputs[k]);
      }
      return;
    }

    const IMeshEncoding i = codeIMesh(first, inputs[0]);
    const GomTopology topology =
        params_.pmeshMode == PMeshMode::kD3dmc ? GomTopology::build(i.decoded) : GomTopology();
    emit(first, i.decoded.positions, i, inputs[0]);
    std::vector<Vec3i> previous = i.decoded.positions;
    for (size_t n = 1; n < gh.keyframes.size(); ++n) {
      const int a = gh.keyframes[n - 1], b = gh.keyframes[n];
      // The keyframe's target in the GOM's vertex order (Draco's decoded order).
      std::vector<Vec3i> target(i.inputIndex.size());
      for (size_t j = 0; j < target.size(); ++j)
        target[j] = inputs[b].positions[i.inputIndex[j]];
      std::vector<Vec3i> key = codePMesh(first + b, topology, previous, target);
      for (int f = a + 1; f < b; ++f)
        emit(first + f, interpolateFrame(previous, key, a, b, f), i, inputs[f]);
      emit(first + b, key, i, inputs[b]);
      previous = std::move(key);
    }
  }

 private:
  std::string frameName(size_t frame) const {
    return frame < frameNames_.size() ? frameNames_[frame] : "frame " + std::to_string(frame);
  }

  // P meshes carry positions only: the GOM's frames must share the first frame's connectivity.
  void checkConstantConnectivity(size_t first, size_t count) const {
    const Mesh& a = frames_[first];
    for (size_t k = 1; k < count; ++k) {
      const Mesh& b = frames_[first + k];
      check(a.positions.size() == b.positions.size(),
            frameName(first + k) + ": " + std::to_string(b.positions.size()) +
                " vertices, but the GOM's first frame (" + frameName(first) + ") has " +
                std::to_string(a.positions.size()) +
                " (P meshes need constant connectivity; use GOMSize or PMeshMode intra)");
      check(a.triangles == b.triangles,
            frameName(first + k) + ": connectivity differs from the GOM's first frame (" +
                frameName(first) + "); P meshes need constant connectivity");
    }
  }

  IMeshEncoding codeIMesh(size_t frame, const IntMesh& input) {
    for (const Triangle& t : input.triangles)
      check(t[0] != t[1] && t[1] != t[2] && t[0] != t[2],
            frameName(frame) + ": triangle with a repeated vertex (degenerate face)");
    IMeshEncoding i = encodeIMesh(input, params_.gridBits, params_.dracoSpeed);
    // Draco does not keep vertices that no triangle uses; say so rather than drop them quietly.
    if (i.decoded.positions.size() != input.positions.size())
      std::fprintf(stderr, "3dvo-enc: warning: %s: %zu vertices in, %zu coded (Draco drops "
                   "vertices no triangle uses and splits non-manifold ones)\n",
                   frameName(frame).c_str(), input.positions.size(), i.decoded.positions.size());
    if (i.unmatchedTriangles > 0)
      std::fprintf(stderr, "3dvo-enc: warning: %s: %zu decoded triangles have no input twin; "
                   "P meshes of this GOM may predict poorly\n",
                   frameName(frame).c_str(), i.unmatchedTriangles);
    IMeshUnit im;
    im.im_frame = static_cast<uint32_t>(frame);
    im.im_draco_payload = i.payload;
    units_.write(UnitType::kIMesh, serialise(std::move(im)));
    return i;
  }

  std::vector<Vec3i> codePMesh(size_t frame, const GomTopology& topology,
                               const std::vector<Vec3i>& previous,
                               const std::vector<Vec3i>& target) {
    const bool d3dmc = params_.pmeshMode == PMeshMode::kD3dmc;
    PMeshEncoding p =
        d3dmc ? encodePMesh(topology, previous, target, pmParams_, params_.effectiveLambda())
              : encodeTemporalDpcm(previous, target, pmParams_);
    // Closed loop: what the decoder makes of the payload must be the encoder's
    // reconstruction, bit for bit.
    const std::string context = "encoder's own P mesh";
    const std::vector<Vec3i> decoded =
        d3dmc ? decodePMesh(p.payload, topology, previous, pmParams_, context)
              : decodeTemporalDpcm(p.payload, previous, pmParams_, context);
    if (decoded != p.reconstruction)
      throw std::logic_error("P-mesh reconstruction differs from the decoder's (frame " +
                             std::to_string(frame) + ")");
    PMeshUnit pm;
    pm.pm_frame = static_cast<uint32_t>(frame);
    pm.pm_cabac_payload = std::move(p.payload);
    units_.write(UnitType::kPMesh, serialise(std::move(pm)));
    return std::move(p.reconstruction);
  }

  // Reports a reconstructed frame and accounts its error against the quantised input.
  void emit(size_t frame, const std::vector<Vec3i>& positions, const IMeshEncoding& i,
            const IntMesh& input) {
    for (size_t j = 0; j < positions.size(); ++j)
      for (int c = 0; c < 3; ++c) {
        const int64_t e = int64_t{positions[j][c]} - input.positions[i.inputIndex[j]][c];
        out_.sumSquaredError += double(e) * double(e);
        out_.maxAbsError = std::max(out_.maxAbsError, e < 0 ? -e : e);
      }
    out_.frameInputIndex.push_back(i.inputIndex);
    out_.vertexFrames += positions.size();
    onFrame_(static_cast<int>(frame), IntMesh{positions, i.decoded.triangles});
  }

  const EncoderParams& params_;
  const Grid& grid_;
  const std::vector<Mesh>& frames_;
  const std::vector<std::string>& frameNames_;
  const FrameCallback& onFrame_;
  UnitWriter& units_;
  EncodedSequence& out_;
  PMeshParams pmParams_;
};

}  // namespace

Grid gridForSequence(const std::vector<Mesh>& frames, int bits) {
  Vec3d lo, hi;
  boundingBox(frames, lo, hi);
  return Grid::fromBounds(lo, hi, bits);
}

EncodedSequence encodeSequence(const EncoderParams& params, const Grid& grid,
                               const std::vector<Mesh>& frames,
                               const std::vector<std::string>& frameNames,
                               const FrameCallback& onFrame) {
  check(!frames.empty(), "no frames to encode");
  check(frames.size() <= kMaxFrames, "too many frames");
  check(grid.bits == params.gridBits, "grid and GridBits disagree");
  EncodedSequence out;
  UnitWriter units;
  SequenceHeader sh;
  sh.sh_frame_count = static_cast<uint32_t>(frames.size());
  sh.sh_frame_rate = params.frameRate;
  sh.sh_grid_bits = static_cast<uint8_t>(params.gridBits);
  for (int a = 0; a < 3; ++a)
    sh.sh_grid_origin[a] = grid.origin[a];
  sh.sh_grid_step = grid.step;
  units.write(UnitType::kSequenceHeader, serialise(sh));

  GomEncoder gomEncoder(params, grid, frames, frameNames, onFrame, units, out);
  for (size_t first = 0; first < frames.size(); first += params.gomSize)
    gomEncoder.encodeGom(first, std::min<size_t>(params.gomSize, frames.size() - first));

  out.headerBytes = units.bytesOfType(UnitType::kSequenceHeader) +
                    units.bytesOfType(UnitType::kGomHeader) + sizeof kStreamMagic;
  out.iMeshBytes = units.bytesOfType(UnitType::kIMesh);
  out.pMeshBytes = units.bytesOfType(UnitType::kPMesh);
  out.stream = units.bytes();
  return out;
}

}  // namespace tdvo
