#include "encoder/sequence_encoder.h"

#include "common/core/warnings.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>

#include "bitstream/units.h"
#include "common/core/error.h"
#include "common/core/ordered_parallel.h"
#include "decoder/stream_decoder.h"
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
      warn(warning);
    // How normals are carried, said when it changes (the first time, and from the GOM on that
    // changes it), through the warning handler: a program using the library receives it, and
    // Quality's trial codings (SilenceWarningsScope) do not repeat it.
    if (attributesPresent_ && gom.normals != normals_) {
      warn("normals from frame " + std::to_string(static_cast<long long>(first) + firstFrame_) +
           " on: " + gom.normals);
      normals_ = gom.normals;
    }
    for (const GomGeometry::Unit& unit : gom.units)
      units_.write(unit.type, unit.payload);
    out_.gomKeyframes.push_back(gom.keyframes);
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
    if (keepInputIndex_) {
      // Output index -> input vertex.
      std::vector<uint32_t> index(i.order.numVertices);
      for (size_t j = 0; j < index.size(); ++j)
        index[i.order.vertexOutput[j]] = i.inputIndex[j];
      out_.frameInputIndex.push_back(std::move(index));
    }
    out_.vertexFrames += f.positions.size();
    // The frame as the decoder outputs it: in the input's order.
    IntMesh output;
    applyVertexOrder(i.order, f.positions, output.positions);
    output.triangles = i.order.triangles;
    applyAttributes(i.attributes, output);
    gomDecoded_.push_back(std::move(output));
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

 public:
  bool attributesPresent_ = false;
  int firstFrame_ = 0;  // the input's frame number of stream frame 0 (for messages)

 private:
  std::string normals_;  // the last normals line printed
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

// boundsOfSequence's fold: the frames added in frame order.
class BoundsFold {
 public:
  void add(const Mesh& mesh) {
    Vec3d frameLo{0, 0, 0}, frameHi{0, 0, 0};
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
      const Vec3d& p = mesh.positions[i];
      for (int a = 0; a < 3; ++a) {
        b_.lo[a] = any_ ? std::min(b_.lo[a], p[a]) : p[a];
        b_.hi[a] = any_ ? std::max(b_.hi[a], p[a]) : p[a];
        frameLo[a] = i > 0 ? std::min(frameLo[a], p[a]) : p[a];
        frameHi[a] = i > 0 ? std::max(frameHi[a], p[a]) : p[a];
      }
      any_ = true;
    }
    b_.objectExtent = std::max(b_.objectExtent, Grid::largestExtent(frameLo, frameHi));
  }
  // The bounds of the `count` frames added; `name(k)` names frame k.
  SequenceBounds finish(size_t count, const std::function<std::string(size_t)>& name) {
    check(any_, "no vertex positions to bound");
    b_.frames = count;
    b_.firstName = name(0);
    b_.lastName = name(count - 1);
    return b_;
  }

 private:
  SequenceBounds b_;
  bool any_ = false;
};

}  // namespace

Grid gridForSequence(const std::vector<Mesh>& frames, int bits, GridFit fit) {
  return gridFor(boundsOfSequence(frames), bits, fit);
}

SequenceBounds boundsOfSequence(const std::vector<Mesh>& frames) {
  BoundsFold fold;
  for (const Mesh& mesh : frames)
    fold.add(mesh);
  return fold.finish(frames.size(), [](size_t k) { return "frame " + std::to_string(k); });
}

SequenceBounds boundsOfSequence(
    const FrameSource& source, int threads, const std::function<void(size_t frame)>& onFrameRead,
    const std::function<void(size_t frame, const Mesh& mesh)>& inspect) {
  // One fold, frame after frame in order, so the result is the same bit for bit for any
  // `threads`.
  // The readers' warnings are held and said in frame order too (the first file that has a
  // kind of warning is the one named, common/core/warnings.h).
  struct Read {
    Mesh mesh;
    std::vector<HeldWarning> warnings;
  };
  BoundsFold fold;
  orderedParallelFor<Read>(
      source.count, threads, 2 * static_cast<size_t>(threads),
      [&](size_t k) {
        WarningHold hold;
        Read read{source.read(k), {}};
        if (inspect) inspect(k, read.mesh);
        read.warnings = hold.release();
        return read;
      },
      [&](size_t k, Read& read) {
        say(read.warnings);
        fold.add(read.mesh);
        if (onFrameRead) onFrameRead(k);
      });
  return fold.finish(source.count, [&source](size_t k) {
    return source.name ? source.name(k) : "frame " + std::to_string(k);
  });
}

Grid gridFor(const SequenceBounds& bounds, int bits, GridFit fit) {
  try {
    return fit == GridFit::kObject
               ? Grid::fitObject(bounds.lo, bounds.hi, bounds.objectExtent, bits)
               : Grid::fromBounds(bounds.lo, bounds.hi, bits);
  } catch (const Error& e) {
    // Bad input: say which frames it is about.
    throw Error(bounds.firstName + (bounds.frames > 1 ? " .. " + bounds.lastName : "") + ": " +
                e.what());
  }
}

Grid gridForSequence(const FrameSource& source, int bits, GridFit fit, int threads,
                     const std::function<void(size_t frame)>& onFrameRead,
                     const std::function<void(size_t frame, const Mesh& mesh)>& inspect) {
  return gridFor(boundsOfSequence(source, threads, onFrameRead, inspect), bits, fit);
}

EncodedSequence encodeSequence(const EncoderParams& params, const Grid& grid,
                               const std::vector<Mesh>& frames,
                               const std::vector<std::string>& frameNames,
                               const FrameCallback& onFrame, TextureEncoder* textures,
                               const TextureCallback& onTexture) {
  return encodeSequence(params, grid, sourceOf(frames, frameNames), onFrame, textures, onTexture,
                        true);
}

EncodedSequence encodeSequence(const EncoderParams& inParams, const Grid& grid,
                               const FrameSource& source, const FrameCallback& onFrame,
                               TextureEncoder* textures, const TextureCallback& onTexture,
                               bool keepInputIndex) {
  check(source.count > 0, "no frames to encode");
  check(source.count <= kMaxFrames, "too many frames");
  // The stream's coordinates have the grid's bits: GridBits, or more with GridFit object.
  check(grid.bits >= inParams.gridBits, "the grid has fewer bits than GridBits");
  EncoderParams params = inParams;
  params.gridBits = grid.bits;
  // The stream has ATTRIBUTES units when the first frame has attributes the cfg keeps.
  {
    WarningHold again;  // frame 0 was read before (below: the GOMs' frames)
    const MeshAttributes first = source.read(0).attributes;
    params.attributesPresent = (params.textureCoordinates && first.hasUvs()) ||
                               (params.normals != NormalsChoice::kNone && first.hasNormals());
  }
  EncodedSequence out;
  UnitWriter units;
  SequenceHeader sh;
  check(params.firstFrame >= 0 && static_cast<uint32_t>(params.firstFrame) <= kMaxFirstFrame,
        "FirstFrame out of range");
  sh.sh_first_frame = static_cast<uint32_t>(params.firstFrame);
  sh.sh_frame_count = static_cast<uint32_t>(source.count);
  sh.sh_frame_rate = params.frameRate;
  sh.sh_grid_bits = static_cast<uint8_t>(params.gridBits);
  for (int a = 0; a < 3; ++a)
    sh.sh_grid_origin[a] = grid.origin[a];
  sh.sh_grid_step = grid.step;
  sh.sh_attributes_present = params.attributesPresent ? 1 : 0;
  if (textures) {
    // The dataset's fields the cameras do not code travel with them (docs/bitstream.md).
    sh.cameras = textures->cameras();
    sh.sh_description = textures->dataset().description;
    sh.sh_up_present = textures->dataset().up ? 1 : 0;
    if (textures->dataset().up)
      for (int a = 0; a < 3; ++a)
        sh.sh_up[a] = (*textures->dataset().up)[a];
  }
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
  writer.attributesPresent_ = params.attributesPresent;
  writer.firstFrame_ = params.firstFrame;
  // Runs of GOMs from one random access point to the next (RandomAccessPeriod; P-mesh modes
  // only) are coded one after the other in a task, as each GOM of a run may continue the
  // previous one's connectivity; runs are independent.
  const std::vector<std::pair<size_t, size_t>> runs = params.randomAccessRuns(goms.size());
  orderedParallelFor<std::vector<GomGeometry>>(
      runs.size(), threads, 2 * static_cast<size_t>(threads),
      [&](size_t r) {
        std::vector<GomGeometry> coded;
        GomContinuation continuation;
        for (size_t g = runs[r].first; g < runs[r].first + runs[r].second; ++g) {
          const size_t first = static_cast<size_t>(goms[g].first);
          const size_t count = static_cast<size_t>(goms[g].second);
          std::vector<Mesh> frames;
          frames.reserve(count);
          {
            // The bounds pass read these frames and said their readers' warnings, in frame
            // order; reading them again says nothing new (and is not counted twice).
            WarningHold again;
            for (size_t k = 0; k < count; ++k)
              frames.push_back(source.read(first + k));
          }
          const bool last = g + 1 == runs[r].first + runs[r].second;
          coded.push_back(encodeGomGeometry(params, grid, first, std::move(frames), frameName,
                                            g == runs[r].first ? nullptr : &continuation,
                                            last ? nullptr : &continuation));
        }
        return coded;
      },
      [&](size_t r, std::vector<GomGeometry>& coded) {
        for (size_t i = 0; i < coded.size(); ++i)
          writer.write(static_cast<size_t>(goms[runs[r].first + i].first), coded[i]);
      });

  out.headerBytes = units.bytesOfType(UnitType::kSequenceHeader) +
                    units.bytesOfType(UnitType::kGomHeader) + sizeof kStreamMagic;
  out.iMeshBytes = units.bytesOfType(UnitType::kIMesh);
  out.pMeshBytes = units.bytesOfType(UnitType::kPMesh);
  out.orderBytes = units.bytesOfType(UnitType::kVertexOrder);
  out.attributeBytes = units.bytesOfType(UnitType::kAttributes);
  out.textureBytes = units.bytesOfType(UnitType::kTexture);
  out.stream = units.bytes();
  return out;
}

void warnIfDecodersRefuse(const std::vector<uint8_t>& stream) {
  // A geometry decode (texture units are read and their work counted, pictures not decoded)
  // with every decoder limit at its default: the limits are the decoder's, so this is what
  // 3dvo-dec, tdvo::Decoder and the browser player do with the stream.
  try {
    UnitReader units(stream.data(), stream.size(), "the stream");
    StreamDecoder decoder(units, "the stream");
    decoder.decode([](int, const IntMesh&) {});
  } catch (const Error& e) {
    warn(std::string("decoders with their default limits refuse this stream: ") + e.what() +
         " (3dvo-dec decodes it with the limit named there raised, or 0 for none)");
  }
}

}  // namespace tdvo
