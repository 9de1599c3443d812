#include "decoder/stream_decoder.h"

#include "bitstream/units.h"
#include "common/error.h"
#include "decoder/imesh_decoder.h"

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

    for (uint32_t k = 0; k < gh.gh_frame_count; ++k, ++nextFrame) {
      const std::string frameWhen = "for frame " + std::to_string(nextFrame);
      expectUnit(UnitType::kIMesh, frameWhen);
      const IMeshUnit im = parseUnit<IMeshUnit>(unit, name_, trace_, "the I mesh");
      const std::string where = name_ + ": " + unit.describe();
      if (im.im_frame != nextFrame)
        throw Error(where + ": im_frame " + std::to_string(im.im_frame) + " but expected " +
                    std::to_string(nextFrame));
      const IntMesh mesh = decodeIMesh(im.im_draco_payload, sh_.sh_grid_bits, where);
      onFrame(static_cast<int>(nextFrame), mesh);
    }
  }
  if (units.next(unit))
    throw Error(name_ + ": " + unit.describe() + ": unit after the last frame (sh_frame_count " +
                std::to_string(sh_.sh_frame_count) + ")");
}

}  // namespace tdvo
