#include "decoder/stream_decoder.h"

#include "bitstream/units.h"
#include "common/error.h"
#include "common/keyframes.h"
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

Grid StreamDecoder::grid() const {
  return gridFromHeader(sh_);
}

namespace {

// Parses one unit's payload as structure T, requiring that the whole payload is consumed.
template <class T>
T parseUnit(const UnitView& unit, const std::string& name, std::FILE* trace,
            const char* structure) {
  if (trace) std::fprintf(trace, "%s\n", unit.describe().c_str());
  ByteReader reader(unit.payload, unit.size, name + ": " + unit.describe(), unit.payloadOffset,
                    trace);
  T value;
  transfer(reader, value);
  reader.expectEnd(structure);
  return value;
}

}  // namespace

void StreamDecoder::decode(const FrameCallback& onFrame) {
  UnitReader units(data_, size_, name_);
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

  uint32_t nextFrame = 0;
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
        onFrame(static_cast<int>(nextFrame), readIMesh(nextFrame));
      continue;
    }

    IntMesh mesh = readIMesh(nextFrame);
    const GomTopology topology =
        mode == PMeshMode::kD3dmc ? GomTopology::build(mesh) : GomTopology();
    onFrame(static_cast<int>(nextFrame), mesh);
    std::vector<Vec3i> previous = mesh.positions;
    for (size_t n = 1; n < gh.keyframes.size(); ++n) {
      const int a = gh.keyframes[n - 1], b = gh.keyframes[n];
      const uint32_t frame = gh.gh_first_frame + b;
      expectUnit(UnitType::kPMesh, "for frame " + std::to_string(frame));
      const PMeshUnit pm = parseUnit<PMeshUnit>(unit, name_, trace_, "the P mesh");
      const std::string where = name_ + ": " + unit.describe();
      if (pm.pm_frame != frame)
        throw Error(where + ": pm_frame " + std::to_string(pm.pm_frame) + " but expected " +
                    std::to_string(frame));
      std::vector<Vec3i> key =
          mode == PMeshMode::kD3dmc
              ? decodePMesh(pm.pm_cabac_payload, topology, previous, pmParams, where, trace_)
              : decodeTemporalDpcm(pm.pm_cabac_payload, previous, pmParams, where, trace_);
      for (int f = a + 1; f < b; ++f) {
        mesh.positions = interpolateFrame(previous, key, a, b, f);
        onFrame(static_cast<int>(gh.gh_first_frame + f), mesh);
      }
      mesh.positions = key;
      onFrame(static_cast<int>(frame), mesh);
      previous = std::move(key);
    }
    nextFrame += gh.gh_frame_count;
  }
  if (units.next(unit))
    throw Error(name_ + ": " + unit.describe() + ": unit after the last frame (sh_frame_count " +
                std::to_string(sh_.sh_frame_count) + ")");
}

}  // namespace tdvo
