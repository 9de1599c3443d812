#include "decoder/decoder.h"

#include <optional>
#include <utility>

#include "bitstream/byte_io.h"
#include "bitstream/syntax.h"
#include "bitstream/units.h"
#include "common/core/error.h"
#include "common/core/md5.h"

namespace tdvo {

std::string DecodedFrame::geometryHashLine() const {
  return tdvo::geometryHashLine(static_cast<int>(number), mesh);
}

// A Decoder's stream (a file, or bytes in memory), the run decoding it (one StreamDecoder, made
// anew by a seek), and the settings every run gets.
struct Decoder::State {
  std::string name;
  std::string path;            // a file: read unit by unit, by two readers
  std::vector<uint8_t> owned;  // memory: the decoder's copy (when asked to copy)
  const uint8_t* data = nullptr;
  size_t size = 0;

  std::unique_ptr<UnitSource> units, textureUnits;  // geometry and texture units
  std::unique_ptr<StreamDecoder> decoder;
  StreamInfo info;
  std::optional<std::vector<int64_t>> gomStarts;

  PictureDecoderFactory pictures;
  uint64_t maxVertexFramesPerByte = kDefaultMaxVertexFramesPerByte;
  uint64_t maxMeshMemoryPerByte = kDefaultMaxMeshMemoryPerByte;
  uint64_t maxTexturePixelsPerByte = kDefaultMaxTexturePixelsPerByte;

  std::unique_ptr<UnitSource> source() const {
    if (!path.empty()) return std::make_unique<UnitFileReader>(path, name);
    return std::make_unique<UnitReader>(data, size, name);
  }

  // A new run from frame number `first` (-1: the stream's first frame), its header read.
  void restart(int64_t first) {
    units = source();
    textureUnits.reset();
    decoder = std::make_unique<StreamDecoder>(*units, name);
    decoder->setFrameRange(first, 0);
    decoder->setMaxVertexFramesPerByte(maxVertexFramesPerByte);
    decoder->setMaxMeshMemoryPerByte(maxMeshMemoryPerByte);
    decoder->setMaxTexturePixelsPerByte(maxTexturePixelsPerByte);
    decoder->setPictureDecoder(pictures);
    decoder->readHeader();
    const SequenceHeader& sh = decoder->sequenceHeader();
    info.syntaxVersion = sh.sh_syntax_version;
    info.firstFrame = sh.sh_first_frame;
    info.frameCount = sh.sh_frame_count;
    info.frameRate = sh.sh_frame_rate;
    info.grid = gridFromHeader(sh);
    info.cameras = sh.cameras;
    info.description = sh.sh_description;
    info.upPresent = sh.sh_up_present != 0;
    for (int a = 0; a < 3; ++a)
      info.up[a] = sh.sh_up[a];
  }
};

Decoder::Decoder(std::unique_ptr<State> state) : s_(std::move(state)) {
  s_->restart(-1);
}

Decoder::Decoder(Decoder&&) noexcept = default;
Decoder& Decoder::operator=(Decoder&&) noexcept = default;
Decoder::~Decoder() = default;

Decoder Decoder::openFile(const std::string& path, const std::string& name) {
  auto state = std::make_unique<State>();
  state->path = path;
  state->name = name.empty() ? path : name;
  return Decoder(std::move(state));
}

Decoder Decoder::openMemory(const uint8_t* data, size_t size, const std::string& name, bool copy) {
  auto state = std::make_unique<State>();
  state->name = name;
  if (copy) {
    state->owned.assign(data, data + size);
    data = state->owned.data();
  }
  state->data = data;
  state->size = size;
  return Decoder(std::move(state));
}

const StreamInfo& Decoder::info() const {
  return s_->info;
}

void Decoder::setPictureDecoder(PictureDecoderFactory factory) {
  s_->pictures = std::move(factory);
  s_->decoder->setPictureDecoder(s_->pictures);
}

void Decoder::setMaxVertexFramesPerByte(uint64_t limit) {
  s_->maxVertexFramesPerByte = limit;
  s_->decoder->setMaxVertexFramesPerByte(limit);
}

void Decoder::setMaxMeshMemoryPerByte(uint64_t limit) {
  s_->maxMeshMemoryPerByte = limit;
  s_->decoder->setMaxMeshMemoryPerByte(limit);
}

void Decoder::setMaxTexturePixelsPerByte(uint64_t limit) {
  s_->maxTexturePixelsPerByte = limit;
  s_->decoder->setMaxTexturePixelsPerByte(limit);
}

bool Decoder::next(DecodedFrame& frame) {
  State& s = *s_;
  // The texture units are read by a second reader of the same stream (StreamDecoder::pullFrame).
  if (s.pictures && !s.info.cameras.empty() && !s.textureUnits) s.textureUnits = s.source();
  uint32_t index = 0;
  const IntMesh* mesh = nullptr;
  if (!s.decoder->pullFrame(index, mesh, s.textureUnits.get(), &frame.textures)) return false;
  frame.index = index;
  frame.number = s.info.frameNumber(index);
  frame.mesh = *mesh;  // positions, triangles, texture coordinates and normals
  frame.positions.resize(mesh->positions.size());
  for (size_t v = 0; v < mesh->positions.size(); ++v) {
    const Vec3d p = s.info.grid.dequantise(mesh->positions[v]);
    frame.positions[v] = {static_cast<float>(p[0]), static_cast<float>(p[1]),
                          static_cast<float>(p[2])};
  }
  return true;
}

const std::vector<int64_t>& Decoder::gomStarts() {
  State& s = *s_;
  if (s.gomStarts) return *s.gomStarts;
  std::vector<int64_t> starts;
  std::unique_ptr<UnitSource> units = s.source();
  UnitView unit;
  while (units->next(unit)) {
    if (unit.type != static_cast<uint8_t>(UnitType::kGomHeader)) continue;
    GomHeader gh;
    ByteReader reader(unit.payload, unit.size, s.name + ": " + unit.describe(), unit.payloadOffset);
    transfer(reader, gh);
    reader.expectEnd("the GOM header");
    if (gh.gh_random_access) starts.push_back(s.info.frameNumber(gh.gh_first_frame));
  }
  s.gomStarts = std::move(starts);
  return *s.gomStarts;
}

void Decoder::seek(int64_t frameNumber) {
  const StreamInfo& info = s_->info;
  const int64_t last = info.firstFrame + info.frameCount - 1;
  if (frameNumber < info.firstFrame || frameNumber > last)
    throw Error(s_->name + ": cannot seek to frame " + std::to_string(frameNumber) +
                ": the stream's frames are " + std::to_string(info.firstFrame) + " .. " +
                std::to_string(last));
  s_->restart(frameNumber);
}

}  // namespace tdvo
