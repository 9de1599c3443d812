#include "encoder/sequence_encoder.h"

#include <algorithm>
#include <string>

#include "bitstream/units.h"
#include "common/error.h"
#include "encoder/imesh_encoder.h"

namespace tdvo {

namespace {

template <class T>
std::vector<uint8_t> serialise(T value) {
  ByteWriter writer;
  transfer(writer, value);
  return writer.take();
}

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
  auto frameName = [&](size_t frame) {
    return frame < frameNames.size() ? frameNames[frame] : "frame " + std::to_string(frame);
  };
  check(!frames.empty(), "no frames to encode");
  check(frames.size() <= kMaxFrames, "too many frames");
  EncodedSequence out;
  check(grid.bits == params.gridBits, "grid and GridBits disagree");

  UnitWriter units;
  SequenceHeader sh;
  sh.sh_frame_count = static_cast<uint32_t>(frames.size());
  sh.sh_frame_rate = params.frameRate;
  sh.sh_grid_bits = static_cast<uint8_t>(params.gridBits);
  for (int a = 0; a < 3; ++a)
    sh.sh_grid_origin[a] = grid.origin[a];
  sh.sh_grid_step = grid.step;
  units.write(UnitType::kSequenceHeader, serialise(sh));

  for (size_t first = 0; first < frames.size(); first += params.gomSize) {
    const size_t count = std::min<size_t>(params.gomSize, frames.size() - first);
    GomHeader gh;
    gh.gh_first_frame = static_cast<uint32_t>(first);
    gh.gh_frame_count = static_cast<uint16_t>(count);
    gh.gh_pmesh_mode = static_cast<uint8_t>(params.pmeshMode);
    units.write(UnitType::kGomHeader, serialise(gh));

    for (size_t k = 0; k < count; ++k) {
      const size_t frame = first + k;
      const IntMesh input = grid.quantise(frames[frame]);
      for (const Triangle& t : input.triangles)
        check(t[0] != t[1] && t[1] != t[2] && t[0] != t[2],
              frameName(frame) + ": triangle with a repeated vertex (degenerate face)");
      IMeshEncoding coded = encodeIMesh(input, params.gridBits, params.dracoSpeed);
      IMeshUnit im;
      im.im_frame = static_cast<uint32_t>(frame);
      im.im_draco_payload = std::move(coded.payload);
      units.write(UnitType::kIMesh, serialise(std::move(im)));
      out.frameInputIndex.push_back(std::move(coded.inputIndex));
      out.vertexFrames += coded.decoded.positions.size();
      onFrame(static_cast<int>(frame), coded.decoded);
    }
  }

  out.headerBytes =
      units.bytesOfType(UnitType::kSequenceHeader) + units.bytesOfType(UnitType::kGomHeader) + 4;
  out.iMeshBytes = units.bytesOfType(UnitType::kIMesh);
  out.pMeshBytes = units.bytesOfType(UnitType::kPMesh);
  out.stream = units.bytes();
  return out;
}

}  // namespace tdvo
