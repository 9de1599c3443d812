#include "encoder/sequence_encoder.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>

#include "bitstream/units.h"
#include "common/error.h"
#include "common/ordered_parallel.h"
#include "encoder/gom_coder.h"

namespace tdvo {

namespace {

// Appends coded GOMs to the stream in GOM order and reports every reconstructed frame in frame
// order (then the GOM's textures), exactly as if the GOMs had been coded one after the other.
class GomWriter {
 public:
  GomWriter(const Grid& grid, const FrameCallback& onFrame, TextureEncoder* textures,
            const TextureCallback& onTexture, UnitWriter& units, EncodedSequence& out,
            bool keepInputIndex)
      : grid_(grid),
        onFrame_(onFrame),
        textures_(textures),
        onTexture_(onTexture),
        units_(units),
        out_(out),
        keepInputIndex_(keepInputIndex) {}

  void write(size_t first, const GomGeometry& gom) {
    gomDecoded_.clear();
    for (const std::string& warning : gom.warnings)
      std::fprintf(stderr, "3dvo-enc: warning: %s\n", warning.c_str());
    for (const GomGeometry::Unit& unit : gom.units)
      units_.write(unit.type, unit.payload);
    for (size_t k = 0; k < gom.frames.size(); ++k)
      emit(first + k, gom.frames[k], gom.iMeshes[gom.frames[k].iMesh]);
    // Textures (if any) are coded here, GOM after GOM, the GOM's cameras in parallel
    // (TextureEncoder::encodeGom; each camera's H.264 state runs on from GOM to GOM).
    if (textures_) textures_->encodeGom(first, gomDecoded_, grid_, units_, onTexture_);
  }

 private:
  // Reports a reconstructed frame and accounts its error against the quantised input.
  void emit(size_t frame, const GomGeometry::Frame& f, const IMeshEncoding& i) {
    for (size_t j = 0; j < f.positions.size(); ++j)
      for (int c = 0; c < 3; ++c) {
        const int64_t e = int64_t{f.positions[j][c]} - f.input[i.inputIndex[j]][c];
        out_.sumSquaredError += double(e) * double(e);
        out_.maxAbsError = std::max(out_.maxAbsError, e < 0 ? -e : e);
      }
    if (keepInputIndex_) out_.frameInputIndex.push_back(i.inputIndex);
    out_.vertexFrames += f.positions.size();
    gomDecoded_.push_back(IntMesh{f.positions, i.decoded.triangles});
    onFrame_(static_cast<int>(frame), gomDecoded_.back());
    if (!textures_) gomDecoded_.clear();  // kept only for the GOM's textures
  }

  const Grid& grid_;
  const FrameCallback& onFrame_;
  TextureEncoder* textures_;
  const TextureCallback& onTexture_;
  std::vector<IntMesh> gomDecoded_;  // the current GOM's reconstruction, for its textures
  UnitWriter& units_;
  EncodedSequence& out_;
  bool keepInputIndex_;
};

FrameSource sourceOf(const std::vector<Mesh>& frames, const std::vector<std::string>& names) {
  FrameSource source;
  source.count = frames.size();
  source.read = [&frames](size_t k) { return frames[k]; };
  source.name = [&names](size_t k) {
    return k < names.size() ? names[k] : "frame " + std::to_string(k);
  };
  return source;
}

}  // namespace

Grid gridForSequence(const std::vector<Mesh>& frames, int bits) {
  Vec3d lo, hi;
  boundingBox(frames, lo, hi);
  return Grid::fromBounds(lo, hi, bits);
}

Grid gridForSequence(const FrameSource& source, int bits, int threads,
                     const std::function<void(size_t frame)>& onFrameRead,
                     const std::function<void(size_t frame, const Mesh& mesh)>& inspect) {
  // boundingBox()'s fold, frame after frame in order, so the result is the same bit for bit.
  Vec3d lo{0, 0, 0}, hi{0, 0, 0};
  bool any = false;
  orderedParallelFor<Mesh>(
      source.count, threads, 2 * static_cast<size_t>(threads),
      [&](size_t k) {
        Mesh mesh = source.read(k);
        if (inspect) inspect(k, mesh);
        return mesh;
      },
      [&](size_t k, Mesh& mesh) {
        for (const Vec3d& p : mesh.positions) {
          for (int a = 0; a < 3; ++a) {
            lo[a] = any ? std::min(lo[a], p[a]) : p[a];
            hi[a] = any ? std::max(hi[a], p[a]) : p[a];
          }
          any = true;
        }
        if (onFrameRead) onFrameRead(k);
      });
  check(any, "no vertex positions to bound");
  try {
    return Grid::fromBounds(lo, hi, bits);
  } catch (const Error& e) {
    // Bad input: say which frames it is about.
    throw Error(source.name(0) + (source.count > 1 ? " .. " + source.name(source.count - 1) : "") +
                ": " + e.what());
  }
}

EncodedSequence encodeSequence(const EncoderParams& params, const Grid& grid,
                               const std::vector<Mesh>& frames,
                               const std::vector<std::string>& frameNames,
                               const FrameCallback& onFrame, TextureEncoder* textures,
                               const TextureCallback& onTexture) {
  return encodeSequence(params, grid, sourceOf(frames, frameNames), onFrame, textures, onTexture,
                        true);
}

EncodedSequence encodeSequence(const EncoderParams& params, const Grid& grid,
                               const FrameSource& source, const FrameCallback& onFrame,
                               TextureEncoder* textures, const TextureCallback& onTexture,
                               bool keepInputIndex) {
  check(source.count > 0, "no frames to encode");
  check(source.count <= kMaxFrames, "too many frames");
  check(grid.bits == params.gridBits, "grid and GridBits disagree");
  EncodedSequence out;
  UnitWriter units;
  SequenceHeader sh;
  sh.sh_frame_count = static_cast<uint32_t>(source.count);
  sh.sh_frame_rate = params.frameRate;
  sh.sh_grid_bits = static_cast<uint8_t>(params.gridBits);
  for (int a = 0; a < 3; ++a)
    sh.sh_grid_origin[a] = grid.origin[a];
  sh.sh_grid_step = grid.step;
  if (textures) sh.cameras = textures->cameras();
  units.write(UnitType::kSequenceHeader, serialise(sh));

  // GOMs are coded in parallel (Threads) and written in order. Each task reads its own frames,
  // so at most 2 * Threads GOMs of frames are in memory at once, however long the sequence.
  // The GOM boundaries (GOMSize, or GOMListFile's list) are decided here alone.
  const GomList goms = params.goms(source.count);
  const int threads = params.threadCount();
  auto frameName = [&source](size_t k) {
    return source.name ? source.name(k) : "frame " + std::to_string(k);
  };
  GomWriter writer(grid, onFrame, textures, onTexture, units, out, keepInputIndex);
  orderedParallelFor<GomGeometry>(
      goms.size(), threads, 2 * static_cast<size_t>(threads),
      [&](size_t g) {
        const size_t first = static_cast<size_t>(goms[g].first);
        const size_t count = static_cast<size_t>(goms[g].second);
        std::vector<Mesh> frames;
        frames.reserve(count);
        for (size_t k = 0; k < count; ++k)
          frames.push_back(source.read(first + k));
        return encodeGomGeometry(params, grid, first, std::move(frames), frameName);
      },
      [&](size_t g, GomGeometry& gom) { writer.write(static_cast<size_t>(goms[g].first), gom); });

  out.headerBytes = units.bytesOfType(UnitType::kSequenceHeader) +
                    units.bytesOfType(UnitType::kGomHeader) + sizeof kStreamMagic;
  out.iMeshBytes = units.bytesOfType(UnitType::kIMesh);
  out.pMeshBytes = units.bytesOfType(UnitType::kPMesh);
  out.textureBytes = units.bytesOfType(UnitType::kTexture);
  out.stream = units.bytes();
  return out;
}

}  // namespace tdvo
