#include "decoder/stream_decoder.h"

#include <memory>
#include <optional>

#include "bitstream/camera_parameters.h"
#include "bitstream/units.h"
#include "common/error.h"
#include "common/keyframes.h"
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

}  // namespace

void StreamDecoder::decode(const FrameCallback& onFrame, const TextureCallback& onTexture) {
  std::optional<UnitReader> inMemory;
  if (!source_) inMemory.emplace(data_, size_, name_);
  UnitSource& units = source_ ? *source_ : *inMemory;
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

  IntMesh mesh;
  std::vector<Vec3i> previous, key;
  PMeshWorkspace work;
  PMeshUnit pm;
  uint32_t nextFrame = 0;
  // Textures: one H.264 decoder per camera; the GOM's decoded meshes give the shapes.
  std::vector<Camera> cameras;
  std::vector<std::unique_ptr<H264Decoder>> textureDecoders;
  for (size_t c = 0; c < sh_.cameras.size(); ++c) {
    cameras.push_back(toCamera(sh_.cameras[c], static_cast<int>(c)));
    textureDecoders.push_back(std::make_unique<H264Decoder>(name_ + ": camera " + std::to_string(c)));
  }
  std::vector<IntMesh> gomMeshes;
  auto emit = [&](int frame, const IntMesh& m) {
    onFrame(frame, m);
    if (!cameras.empty()) gomMeshes.push_back(m);
  };
  auto decodeTextures = [&](uint32_t first) {
    for (size_t k = 0; k < gomMeshes.size(); ++k)
      for (size_t c = 0; c < cameras.size(); ++c) {
        const uint32_t frame = first + static_cast<uint32_t>(k);
        expectUnit(UnitType::kTexture,
                   "for the texture of camera " + std::to_string(c) + ", frame " +
                       std::to_string(frame));
        const TextureUnit tx = parseUnit<TextureUnit>(unit, name_, trace_, "the texture");
        textureBytes_ += kUnitOverhead + unit.size;
        const std::string where = name_ + ": " + unit.describe();
        if (tx.tx_frame != frame || tx.tx_camera != c)
          throw Error(where + ": texture of camera " + std::to_string(tx.tx_camera) +
                      ", frame " + std::to_string(tx.tx_frame) + " but expected camera " +
                      std::to_string(c) + ", frame " + std::to_string(frame));
        const TextureBox box = textureBox(sh_.cameras[c]);
        YuvPicture picture;
        try {
          picture = textureDecoders[c]->decode(tx.tx_access_unit, box.width, box.height);
        } catch (const Error& e) {
          throw Error(where + ": " + e.what());
        }
        const Image shape = textureShape(gomMeshes[k], grid(), cameras[c]);
        if (onTexture) onTexture(static_cast<int>(frame), static_cast<int>(c), picture, shape);
      }
    gomMeshes.clear();
  };

  while (nextFrame < sh_.sh_frame_count) {
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

    const PMeshMode mode = static_cast<PMeshMode>(gh.gh_pmesh_mode);
    PMeshParams pmParams;
    pmParams.gridBits = sh_.sh_grid_bits;
    pmParams.quantStep = gh.gh_motion_quant_step;
    pmParams.maxDepth = gh.gh_max_octree_depth;
    if (mode == PMeshMode::kD3dmc && gh.gh_max_octree_depth > sh_.sh_grid_bits)
      throw Error(gomWhere + ": gh_max_octree_depth " + std::to_string(gh.gh_max_octree_depth) +
                  " exceeds sh_grid_bits " + std::to_string(sh_.sh_grid_bits));

    auto readIMesh = [&](uint32_t frame) {
      expectUnit(UnitType::kIMesh, "for frame " + std::to_string(frame));
      const IMeshUnit im = parseUnit<IMeshUnit>(unit, name_, trace_, "the I mesh");
      const std::string where = name_ + ": " + unit.describe();
      if (im.im_frame != frame)
        throw Error(where + ": im_frame " + std::to_string(im.im_frame) + " but expected " +
                    std::to_string(frame));
      return decodeIMesh(im.im_draco_payload, sh_.sh_grid_bits, where);
    };

    if (mode == PMeshMode::kIntra) {
      for (uint32_t k = 0; k < gh.gh_frame_count; ++k, ++nextFrame)
        emit(static_cast<int>(nextFrame), readIMesh(nextFrame));
      decodeTextures(gh.gh_first_frame);
      continue;
    }

    // Buffers reused through the GOM and the next ones (no allocation per frame): the
    // previous keyframe, the keyframe being decoded, and the frame handed to onFrame.
    mesh = readIMesh(nextFrame);
    GomTopology topology;
    if (mode == PMeshMode::kD3dmc) try {
        topology = GomTopology::build(mesh);
      } catch (const Error& e) {  // the I mesh's connectivity: name its unit
        throw Error(name_ + ": " + unit.describe() + ": " + e.what());
      }
    emit(static_cast<int>(nextFrame), mesh);
    previous.assign(mesh.positions.begin(), mesh.positions.end());
    for (size_t n = 1; n < gh.keyframes.size(); ++n) {
      const int a = gh.keyframes[n - 1], b = gh.keyframes[n];
      const uint32_t frame = gh.gh_first_frame + b;
      expectUnit(UnitType::kPMesh, "for frame " + std::to_string(frame));
      parseUnitInto(unit, name_, trace_, "the P mesh", pm);
      const std::string where = name_ + ": " + unit.describe();
      if (pm.pm_frame != frame)
        throw Error(where + ": pm_frame " + std::to_string(pm.pm_frame) + " but expected " +
                    std::to_string(frame));
      const std::vector<uint8_t>& payload = pm.pm_cabac_payload;
      if (mode == PMeshMode::kD3dmc)
        decodePMesh(payload.data(), payload.size(), topology, previous, pmParams, where, work,
                    key, trace_);
      else
        decodeTemporalDpcm(payload.data(), payload.size(), previous, pmParams, where, key,
                           trace_);
      for (int f = a + 1; f < b; ++f) {
        interpolateFrame(previous, key, a, b, f, mesh.positions);
        emit(static_cast<int>(gh.gh_first_frame + f), mesh);
      }
      mesh.positions.swap(key);  // the keyframe is handed out ...
      emit(static_cast<int>(frame), mesh);
      previous.swap(mesh.positions);  // ... and becomes the reference of the next one
    }
    nextFrame += gh.gh_frame_count;
    decodeTextures(gh.gh_first_frame);
  }
  if (units.next(unit))
    throw Error(name_ + ": " + unit.describe() + ": unit after the last frame (sh_frame_count " +
                std::to_string(sh_.sh_frame_count) + ")");
}

}  // namespace tdvo
