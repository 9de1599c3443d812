#include "decoder/stream_decoder.h"

#include <algorithm>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <optional>

#include "bitstream/camera_parameters.h"
#include "bitstream/order_syntax.h"
#include "bitstream/units.h"
#include "common/core/error.h"
#include "common/core/ordered_parallel.h"
#include "common/geometry/keyframes.h"
#include "decoder/h264_decoder.h"
#include "decoder/imesh_decoder.h"
#include "decoder/pmesh_decoder.h"

namespace tdvo {

Grid gridFromHeader(const SequenceHeader& sh) {
  Grid grid;
  grid.bits = sh.sh_grid_bits;
  grid.step = sh.sh_grid_step;
  for (int a = 0; a < 3; ++a)
    grid.origin[a] = sh.sh_grid_origin[a];
  return grid;
}

StreamDecoder::StreamDecoder(const uint8_t* data, size_t size, std::string name, std::FILE* trace)
    : data_(data), size_(size), name_(std::move(name)), trace_(trace) {}

StreamDecoder::StreamDecoder(UnitSource& units, std::string name, std::FILE* trace)
    : source_(&units), name_(std::move(name)), trace_(trace) {}

Grid StreamDecoder::grid() const {
  return gridFromHeader(sh_);
}

namespace {

// Parses one unit's payload into structure `value`, requiring that the whole payload is
// consumed. Reusing `value` reuses its buffers (P-mesh payloads, frame after frame).
template <class T>
void parseUnitInto(const UnitView& unit, const std::string& name, std::FILE* trace,
                   const char* structure, T& value) {
  if (trace) std::fprintf(trace, "%s\n", unit.describe().c_str());
  ByteReader reader(unit.payload, unit.size, name + ": " + unit.describe(), unit.payloadOffset,
                    trace);
  transfer(reader, value);
  reader.expectEnd(structure);
}

template <class T>
T parseUnit(const UnitView& unit, const std::string& name, std::FILE* trace,
            const char* structure) {
  T value;
  parseUnitInto(unit, name, trace, structure, value);
  return value;
}

// Makes a GOM's frames again, in frame order, for the texture pass, from what the geometry
// pass kept: the I mesh and the P-mesh payloads (intra GOMs: the Draco payloads). What is kept
// is bounded by the stream's bytes, and only the frame being made is held, so a textured GOM
// takes memory for a few frames, not for all of them (docs/robustness.md, "Memory").
// The payloads decoded without error in the geometry pass, so they decode the same here.
struct GomReplay {
  PMeshMode mode = PMeshMode::kIntra;
  int gridBits = 0;
  std::string where;  // the GOM header (for messages; none is expected)
  PMeshParams params;
  std::vector<uint16_t> keyframes;
  IntMesh first;           // the GOM's I mesh, or the previous GOM's last frame (P-mesh GOMs)
  bool continued = false;  // no I mesh: frame 0 is a P mesh predicted from `first`
  GomTopology topology;
  std::vector<std::vector<uint8_t>> payloads;  // per P mesh; per frame in intra GOMs
  uint32_t produced = 0;                       // frames made so far

  void start(PMeshMode m, int bits, const std::string& gomWhere, const PMeshParams& p,
             const std::vector<uint16_t>& keys) {
    mode = m;
    gridBits = bits;
    where = gomWhere;
    params = p;
    keyframes = keys;
    first = IntMesh();
    continued = false;
    topology = GomTopology();
    payloads.clear();
    produced = 0;
    n_ = 0;
  }

  void setFirst(IntMesh mesh, bool continuing) {
    first = std::move(mesh);
    continued = continuing;
  }

  // The GOM's next frame (frame `produced` before the call).
  const IntMesh& next() {
    const int f = static_cast<int>(produced++);
    if (mode == PMeshMode::kIntra) {
      // Its counts passed the mesh-memory limit when the geometry pass read it.
      current_ = decodeIMesh(payloads[f], gridBits, where, 0, 0);
      payloads[f] = std::vector<uint8_t>();  // each is decoded once
      return current_;
    }
    if (f == 0) {
      current_ = first;
      previous_ = first.positions;
      n_ = 1;
      if (!continued) return current_;  // the I mesh
      n_ = 0;  // the first P mesh, predicted from the previous GOM's last frame
    }
    const int a = n_ > 0 ? keyframes[n_ - 1] : -1, b = keyframes[n_];
    if (f == a + 1) {
      const std::vector<uint8_t>& payload = payloads[continued ? n_ : n_ - 1];
      if (mode == PMeshMode::kD3dmc)
        decodePMesh(payload.data(), payload.size(), topology, previous_, params, where, work_,
                    key_);
      else
        decodeTemporalDpcm(payload.data(), payload.size(), previous_, params, where, key_);
    }
    if (f < b) {
      interpolateFrame(previous_, key_, a, b, f, current_.positions);
    } else {
      current_.positions = key_;
      previous_.swap(key_);
      ++n_;
    }
    return current_;
  }

 private:
  size_t n_ = 0;  // the keyframe interval being made: keyframes n_ - 1 .. n_
  std::vector<Vec3i> previous_, key_;
  PMeshWorkspace work_;
  IntMesh current_;
};

}  // namespace

void StreamDecoder::decode(const FrameCallback& onFrame, const TextureCallback& onTexture,
                           const TextureCallback& prepareTexture) {
  std::optional<UnitReader> inMemory;
  if (!source_) inMemory.emplace(data_, size_, name_);
  UnitSource& units = source_ ? *source_ : *inMemory;
  gomStarts_.clear();
  UnitView unit;
  auto expectUnit = [&](UnitType type, const std::string& when) {
    if (!units.next(unit))
      throw Error(name_ + ": stream ends " + when + " (expected a " +
                  unitTypeName(static_cast<uint8_t>(type)) + " unit; truncated stream)");
    if (unit.type != static_cast<uint8_t>(type))
      throw Error(name_ + ": " + unit.describe() + ": expected a " +
                  unitTypeName(static_cast<uint8_t>(type)) + " unit " + when);
  };

  expectUnit(UnitType::kSequenceHeader, "at the start");
  sh_ = parseUnit<SequenceHeader>(unit, name_, trace_, "the sequence header");

  // The frame range (setFrameRange) as stream frames [outFirst, outEnd).
  const int64_t firstNumber = sh_.sh_first_frame;
  const int64_t lastNumber = firstNumber + sh_.sh_frame_count - 1;
  const std::string streamFrames = "the stream's frames are " + std::to_string(firstNumber) +
                                   " .. " + std::to_string(lastNumber);
  uint32_t outFirst = 0, outEnd = sh_.sh_frame_count;
  if (rangeFirst_ >= 0) {
    if (rangeFirst_ < firstNumber || rangeFirst_ > lastNumber)
      throw Error(name_ + ": FirstFrame " + std::to_string(rangeFirst_) +
                  " is not in the stream (" + streamFrames + ")");
    outFirst = static_cast<uint32_t>(rangeFirst_ - firstNumber);
  }
  if (rangeCount_ > 0) {
    const int64_t last = firstNumber + outFirst + rangeCount_ - 1;
    if (last > lastNumber)
      throw Error(name_ + ": FirstFrame + FrameCount - 1 = " + std::to_string(last) +
                  " is past the stream's last frame (" + streamFrames + ")");
    outEnd = static_cast<uint32_t>(outFirst + rangeCount_);
  }
  auto inRange = [&](uint64_t frame) { return frame >= outFirst && frame < outEnd; };

  IntMesh mesh;
  std::vector<Vec3i> previous, key;
  PMeshWorkspace work;
  PMeshUnit pm;
  uint32_t nextFrame = 0;
  // The decoding-work limit (kDefaultMaxVertexFramesPerByte): `frames` more frames of a
  // `vertices`-vertex I mesh, declared by the GOM at `gomWhere`; `unit` is that I mesh.
  uint64_t declaredOutput = 0;  // vertex-frames, summed over the I meshes so far
  auto limitDecodingWork = [&](const std::string& gomWhere, uint32_t frames, size_t vertices) {
    declaredOutput += uint64_t{frames} * vertices;  // < 2^20 frames x 2^24 vertices: no overflow
    const uint64_t bytesRead = unit.payloadOffset + unit.size + 4;  // through the unit's CRC
    const uint64_t limit = maxVertexFramesPerByte_;
    // declared > limit x bytes, without overflowing the product.
    if (limit == 0 || declaredOutput == 0 || (declaredOutput - 1) / bytesRead < limit) return;
    throw Error(gomWhere + ": " + std::to_string(frames) + " frames x " + std::to_string(vertices) +
                " vertices take the decoded output to " + std::to_string(declaredOutput) +
                " vertex-frames from " + std::to_string(bytesRead) +
                " stream bytes, more than the limit of " + std::to_string(limit) +
                " vertex-frames per stream byte (MaxVertexFramesPerByte)");
  };
  // Textures: one H.264 decoder per camera, made with the camera's first texture unit (so
  // that their memory follows the units read, not the cameras declared); the GOM's decoded
  // meshes (dequantised once per frame, for all cameras) give the shapes, through each
  // camera's rasteriser set up once.
  std::vector<MaskRenderer> cameras;
  std::vector<std::unique_ptr<H264Decoder>> textureDecoders(sh_.cameras.size());
  for (size_t c = 0; c < sh_.cameras.size(); ++c)
    cameras.emplace_back(toCamera(sh_.cameras[c], static_cast<int>(c)));
  // The texture-work limit (kDefaultMaxTexturePixelsPerByte): each camera's pixels, and the
  // camera pixels of the texture units read so far.
  std::vector<uint64_t> cameraPixels;
  for (const CameraParameters& c : sh_.cameras) {
    const TextureBox box = textureBox(c);
    cameraPixels.push_back(
        std::max(uint64_t{c.cam_width} * c.cam_height,
                 uint64_t{static_cast<uint32_t>(box.width)} * static_cast<uint32_t>(box.height)));
  }
  uint64_t texturePixels = 0;
  auto limitTextureWork = [&](const std::string& where, size_t c) {
    const uint64_t limit = maxTexturePixelsPerByte_;
    if (limit == 0) return;
    const uint64_t bytesRead = unit.payloadOffset + unit.size + 4;  // through the unit's CRC
    const uint64_t pixels = cameraPixels[c];
    const CameraParameters& cp = sh_.cameras[c];
    if (pixels > kTexturePixelsFree + kTexturePixelsPerByte * bytesRead)
      throw Error(where + ": camera " + std::to_string(c) + "'s " + std::to_string(cp.cam_width) +
                  "x" + std::to_string(cp.cam_height) + " frames need more memory than " +
                  std::to_string(bytesRead) + " stream bytes allow (" +
                  std::to_string(kTexturePixelsFree) + " + " +
                  std::to_string(kTexturePixelsPerByte) +
                  " pixels per stream byte; MaxTexturePixelsPerByte)");
    texturePixels += pixels;  // < 2^20 frames x 64 cameras x 2^28 pixels: no overflow
    if ((texturePixels - 1) / bytesRead < limit) return;
    throw Error(where + ": texture units take the decoded camera pixels to " +
                std::to_string(texturePixels) + " from " + std::to_string(bytesRead) +
                " stream bytes, more than the limit of " + std::to_string(limit) +
                " pixels per stream byte (MaxTexturePixelsPerByte)");
  };
  const Grid textureGrid = grid();
  const bool textured = !cameras.empty();
  GomReplay replay;
  // Frames are decoded in coding order and output in the order of the last VERTEX_ORDER unit.
  MeshOrder order;
  IntMesh output;
  bool canContinue = false;  // the last GOM was of P meshes: the next may continue it
  auto emit = [&](int frame, const IntMesh& m) {
    if (!inRange(static_cast<uint64_t>(frame))) return;
    applyVertexOrder(order, m.positions, output.positions);
    onFrame(frame, output);
  };
  // Item i = k * cameras + c is camera c's texture of the GOM's frame k. Whichever worker
  // needs a unit reads the units up to it, in item order, under a lock; the pictures are
  // decoded and the shapes rasterised on threads_ threads, at most `cameras` items started and
  // not yet consumed: item i starts only once item i - cameras (the same camera's previous
  // picture, through the same H.264 decoder) has been consumed. Callbacks and errors come in
  // item order on the calling thread, as in a sequential run, for any thread count.
  auto decodeTextures = [&](uint32_t first, uint32_t frames) {
    const size_t count = size_t{frames} * cameras.size();
    // The GOM's frames, made again in order as the items ask for them: each is kept until
    // every camera's item has taken it (at most a few frames at a time).
    struct Made {
      std::shared_ptr<const Mesh> mesh;
      size_t taken = 0;
    };
    std::mutex frameMutex;
    std::map<size_t, Made> made;
    auto frameMesh = [&](size_t k) {
      std::lock_guard<std::mutex> lock(frameMutex);
      while (replay.produced <= k) {
        const size_t f = replay.produced;
        made[f].mesh = std::make_shared<const Mesh>(textureGrid.dequantise(replay.next()));
      }
      auto it = made.find(k);
      std::shared_ptr<const Mesh> mesh = it->second.mesh;
      if (++it->second.taken == cameras.size()) made.erase(it);
      return mesh;
    };
    struct Parsed {
      TextureUnit tx;
      std::string where;
    };
    std::map<size_t, Parsed> parsed;  // units read and not yet taken (a few: not the GOM's)
    std::mutex readMutex;
    size_t unitsRead = 0;          // units read so far
    std::exception_ptr readError;  // what reading unit `unitsRead` threw
    auto readUnit = [&](size_t i) {
      std::lock_guard<std::mutex> lock(readMutex);
      while (unitsRead <= i && !readError) {
        try {
          const size_t c = unitsRead % cameras.size();
          const uint32_t frame = first + static_cast<uint32_t>(unitsRead / cameras.size());
          expectUnit(UnitType::kTexture, "for the texture of camera " + std::to_string(c) +
                                             ", frame " + std::to_string(frame));
          Parsed& p = parsed[unitsRead];
          p.tx = parseUnit<TextureUnit>(unit, name_, trace_, "the texture");
          textureBytes_ += kUnitOverhead + unit.size;
          p.where = name_ + ": " + unit.describe();
          if (p.tx.tx_frame != frame || p.tx.tx_camera != c)
            throw Error(p.where + ": texture of camera " + std::to_string(p.tx.tx_camera) +
                        ", frame " + std::to_string(p.tx.tx_frame) + " but expected camera " +
                        std::to_string(c) + ", frame " + std::to_string(frame));
          limitTextureWork(p.where, c);
          ++unitsRead;
        } catch (...) {
          readError = std::current_exception();
        }
      }
      if (unitsRead <= i) std::rethrow_exception(readError);  // item i's own error comes first
      const auto it = parsed.find(i);
      Parsed p = std::move(it->second);
      parsed.erase(it);
      return p;
    };
    struct Decoded {
      YuvPicture picture;
      Image shape;
    };
    orderedParallelFor<Decoded>(
        count, threads_, cameras.size(),
        [&](size_t i) {
          const Parsed p = readUnit(i);
          const size_t k = i / cameras.size(), c = i % cameras.size();
          const TextureBox box = textureBox(sh_.cameras[c]);
          Decoded d;
          // Only this item uses camera c's decoder now: the camera's next item starts once this
          // one has been consumed.
          if (!textureDecoders[c])
            textureDecoders[c] =
                std::make_unique<H264Decoder>(name_ + ": camera " + std::to_string(c));
          try {
            d.picture = textureDecoders[c]->decode(p.tx.tx_access_unit, box.width, box.height);
          } catch (const Error& e) {
            throw Error(p.where + ": " + e.what());
          }
          d.shape = textureShape(*frameMesh(k), cameras[c]);
          if (prepareTexture && inRange(first + k))
            prepareTexture(static_cast<int>(first + k), static_cast<int>(c), d.picture, d.shape);
          return d;
        },
        [&](size_t i, Decoded& d) {
          if (onTexture && inRange(first + i / cameras.size()))
            onTexture(static_cast<int>(first + i / cameras.size()),
                      static_cast<int>(i % cameras.size()), d.picture, d.shape);
        });
  };

  while (nextFrame < sh_.sh_frame_count) {
    if (nextFrame >= outEnd) return;  // the range is decoded: the rest is not read
    const std::string when =
        "before frame " + std::to_string(nextFrame) + " of " + std::to_string(sh_.sh_frame_count);
    expectUnit(UnitType::kGomHeader, when);
    const GomHeader gh = parseUnit<GomHeader>(unit, name_, trace_, "the GOM header");
    const std::string gomWhere = name_ + ": " + unit.describe();
    if (gh.gh_first_frame != nextFrame)
      throw Error(gomWhere + ": gh_first_frame " + std::to_string(gh.gh_first_frame) +
                  " but the next frame is " + std::to_string(nextFrame));
    if (uint64_t{gh.gh_first_frame} + gh.gh_frame_count > sh_.sh_frame_count)
      throw Error(gomWhere + ": GOM of " + std::to_string(gh.gh_frame_count) +
                  " frames runs past sh_frame_count " + std::to_string(sh_.sh_frame_count));
    if (gh.gh_random_access) gomStarts_.push_back(gh.gh_first_frame);

    // Before the range: the GOM's texture units are read (their types checked), not decoded.
    // Its geometry is skipped the same way in an intra GOM; a GOM of P meshes is decoded
    // without output, since the next GOM may continue it (no I mesh: not a random access
    // point).
    const bool beforeRange = uint64_t{gh.gh_first_frame} + gh.gh_frame_count <= outFirst;
    auto skipTextures = [&]() {
      for (size_t k = 0; k < size_t{gh.gh_frame_count} * sh_.cameras.size(); ++k) {
        expectUnit(UnitType::kTexture, "in the GOM at frame " + std::to_string(gh.gh_first_frame));
        textureBytes_ += kUnitOverhead + unit.size;
      }
    };
    if (beforeRange && gh.gh_pmesh_mode == static_cast<uint8_t>(PMeshMode::kIntra)) {
      for (size_t k = 0; k < gh.gh_frame_count; ++k)
        for (UnitType type : {UnitType::kIMesh, UnitType::kVertexOrder})
          expectUnit(type, "in the GOM at frame " + std::to_string(gh.gh_first_frame));
      skipTextures();
      nextFrame += gh.gh_frame_count;
      canContinue = false;
      continue;
    }

    const PMeshMode mode = static_cast<PMeshMode>(gh.gh_pmesh_mode);
    PMeshParams pmParams;
    pmParams.gridBits = sh_.sh_grid_bits;
    pmParams.quantStep = gh.gh_motion_quant_step;
    pmParams.maxDepth = gh.gh_max_octree_depth;
    if (mode == PMeshMode::kD3dmc && gh.gh_max_octree_depth > sh_.sh_grid_bits)
      throw Error(gomWhere + ": gh_max_octree_depth " + std::to_string(gh.gh_max_octree_depth) +
                  " exceeds sh_grid_bits " + std::to_string(sh_.sh_grid_bits));

    if (textured) replay.start(mode, sh_.sh_grid_bits, gomWhere, pmParams, gh.keyframes);

    // `frames`: the frames made from this I mesh's vertices (the GOM's; 1 in an intra GOM).
    auto readIMesh = [&](uint32_t frame, uint32_t frames) {
      expectUnit(UnitType::kIMesh, "for frame " + std::to_string(frame));
      const IMeshUnit im = parseUnit<IMeshUnit>(unit, name_, trace_, "the I mesh");
      const std::string where = name_ + ": " + unit.describe();
      if (im.im_frame != frame)
        throw Error(where + ": im_frame " + std::to_string(im.im_frame) + " but expected " +
                    std::to_string(frame));
      // The mesh-memory limit (kDefaultMaxMeshMemoryPerByte), with the bytes through its CRC.
      IntMesh decoded = decodeIMesh(im.im_draco_payload, sh_.sh_grid_bits, where,
                                    unit.payloadOffset + unit.size + 4, maxMeshMemoryPerByte_);
      limitDecodingWork(gomWhere, frames, decoded.positions.size());
      if (textured && mode == PMeshMode::kIntra) replay.payloads.push_back(im.im_draco_payload);
      expectUnit(UnitType::kVertexOrder, "after the I mesh of frame " + std::to_string(frame));
      const VertexOrderUnit vo =
          parseUnit<VertexOrderUnit>(unit, name_, trace_, "the vertex order");
      const std::string orderWhere = name_ + ": " + unit.describe();
      if (vo.vo_frame != frame)
        throw Error(orderWhere + ": vo_frame " + std::to_string(vo.vo_frame) + " but expected " +
                    std::to_string(frame));
      CabacReaderIo reader(vo.vo_cabac_payload.data(), vo.vo_cabac_payload.size(), orderWhere,
                           trace_);
      order.numVertices = vo.vo_num_vertices;
      codeMeshOrder(reader, decoded, order, vo.vo_triangle_order != 0);
      reader.finish();
      output.triangles = order.triangles;
      return decoded;
    };

    if (mode == PMeshMode::kIntra) {
      for (uint32_t k = 0; k < gh.gh_frame_count; ++k, ++nextFrame)
        emit(static_cast<int>(nextFrame), readIMesh(nextFrame, 1));
      if (textured) decodeTextures(gh.gh_first_frame, gh.gh_frame_count);
      canContinue = false;
      continue;
    }

    // Buffers reused through the GOM and the next ones (no allocation per frame): the
    // previous keyframe, the keyframe being decoded, and the frame handed to onFrame.
    // A GOM that is no random access point continues the previous GOM's connectivity, order
    // and last frame (`mesh`, `order`, `previous`): its first frame is a P mesh.
    if (!gh.gh_random_access && !canContinue)
      throw Error(gomWhere + ": gh_random_access 0, but no previous GOM of P meshes to continue");
    if (gh.gh_random_access) {
      mesh = readIMesh(nextFrame, gh.gh_frame_count);
    } else {
      limitDecodingWork(gomWhere, gh.gh_frame_count, mesh.positions.size());
    }
    GomTopology topology;
    if (mode == PMeshMode::kD3dmc) try {
        topology = GomTopology::build(mesh);
      } catch (const Error& e) {  // the I mesh's connectivity: name its unit
        throw Error(name_ + ": " + unit.describe() + ": " + e.what());
      }
    if (gh.gh_random_access) {
      emit(static_cast<int>(nextFrame), mesh);
      previous.assign(mesh.positions.begin(), mesh.positions.end());
    }
    // The texture pass makes the GOM's frames again from its first reference: the I mesh, or
    // the previous GOM's last frame that a continuing GOM's first P mesh is predicted from.
    if (textured) replay.setFirst(IntMesh{previous, mesh.triangles}, !gh.gh_random_access);
    for (size_t n = gh.gh_random_access ? 1 : 0; n < gh.keyframes.size(); ++n) {
      const int a = n > 0 ? gh.keyframes[n - 1] : -1, b = gh.keyframes[n];
      const uint32_t frame = gh.gh_first_frame + b;
      expectUnit(UnitType::kPMesh, "for frame " + std::to_string(frame));
      parseUnitInto(unit, name_, trace_, "the P mesh", pm);
      const std::string where = name_ + ": " + unit.describe();
      if (pm.pm_frame != frame)
        throw Error(where + ": pm_frame " + std::to_string(pm.pm_frame) + " but expected " +
                    std::to_string(frame));
      const std::vector<uint8_t>& payload = pm.pm_cabac_payload;
      if (textured) replay.payloads.push_back(payload);
      if (mode == PMeshMode::kD3dmc)
        decodePMesh(payload.data(), payload.size(), topology, previous, pmParams, where, work, key,
                    trace_);
      else
        decodeTemporalDpcm(payload.data(), payload.size(), previous, pmParams, where, key, trace_);
      for (int f = a + 1; f < b; ++f) {
        interpolateFrame(previous, key, a, b, f, mesh.positions);
        emit(static_cast<int>(gh.gh_first_frame + f), mesh);
      }
      mesh.positions.swap(key);  // the keyframe is handed out ...
      emit(static_cast<int>(frame), mesh);
      previous.swap(mesh.positions);  // ... and becomes the reference of the next one
    }
    nextFrame += gh.gh_frame_count;
    if (beforeRange) {
      skipTextures();
    } else if (textured) {
      replay.topology = std::move(topology);
      decodeTextures(gh.gh_first_frame, gh.gh_frame_count);
    }
    canContinue = true;
  }
  if (units.next(unit))
    throw Error(name_ + ": " + unit.describe() + ": unit after the last frame (sh_frame_count " +
                std::to_string(sh_.sh_frame_count) + ")");
}

}  // namespace tdvo
