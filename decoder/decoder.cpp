#include "decoder/decoder.h"

#include <optional>
#include <utility>

#include "bitstream/byte_io.h"
#include "bitstream/header_hash.h"
#include "bitstream/syntax.h"
#include "bitstream/units.h"
#include "common/core/error.h"
#include "common/core/md5.h"

namespace tdvo {

std::string DecodedFrame::geometryHashLine() const {
  return tdvo::geometryHashLine(static_cast<int>(number), mesh);
}

// A Decoder's stream (a file, bytes in memory, or bytes arriving), the run decoding it (one
// StreamDecoder, made anew by a seek), and the settings every run gets.
struct Decoder::State {
  std::string name;
  std::string path;            // a file: read unit by unit, by two readers
  std::vector<uint8_t> owned;  // memory: the decoder's copy (when asked to copy)
  const uint8_t* data = nullptr;
  size_t size = 0;
  std::unique_ptr<ArrivingStream> arriving;  // bytes arriving (openArriving)
  bool headerRead = false;
  uint32_t nextIndex = 0;  // the stream frame next() makes next
  // The error next() threw, thrown again by every next() until seek(): decoding on from where
  // it failed would give frames of a broken state.
  std::optional<std::string> error;

  std::unique_ptr<UnitSource> units, textureUnits;  // geometry and texture units
  std::unique_ptr<StreamDecoder> decoder;
  StreamInfo info;
  // gomStarts(): the random access points found so far, all of them once `startsUnits` has
  // read the stream to its end. An arriving stream's are found as its units arrive, each unit
  // read once (`startsRead` of them so far). An error is kept, and given again.
  std::vector<int64_t> gomStarts;
  bool gomStartsComplete = false;
  std::unique_ptr<UnitSource> startsUnits;
  size_t startsRead = 0;
  std::optional<std::string> startsError;
  // canDecodeNext()'s place among an arriving stream's GOM headers (restart() resets it).
  struct GomCursor {
    size_t at = 0;  // those before arriving->gomHeaders()[at] end before frame nextIndex
    bool read = false, malformed = false;  // whether that one has been read, and how it was
    uint64_t first = 0, end = 0;           // its first frame and the one after its last
  } gom;

  PictureDecoderFactory pictures;
  bool keepAccessUnits = false;
  uint64_t maxVertexFramesPerByte = kDefaultMaxVertexFramesPerByte;
  uint64_t maxMeshMemoryPerByte = kDefaultMaxMeshMemoryPerByte;
  uint64_t maxTexturePixelsPerByte = kDefaultMaxTexturePixelsPerByte;

  // The file's version when first opened: every later reading (a seek, the texture units, the
  // GOM starts) must find the same file, or the frames would come from two streams.
  mutable std::optional<std::array<uint64_t, 5>> fileVersion;

  std::unique_ptr<UnitSource> source() const {
    if (!path.empty()) {
      auto file = std::make_unique<UnitFileReader>(path, name);
      if (!fileVersion) fileVersion = file->fileVersion();
      if (file->fileVersion() != *fileVersion)
        throw Error(name +
                    ": the stream file has changed since it was opened (replaced or "
                    "rewritten): open it again");
      return file;
    }
    if (arriving) return arriving->source();
    return std::make_unique<UnitReader>(data, size, name);
  }

  // A new run from frame number `first` (-1: the stream's first frame), its header read.
  void restart(int64_t first) {
    error.reset();
    units = source();
    textureUnits.reset();
    decoder = std::make_unique<StreamDecoder>(*units, name);
    decoder->setFrameRange(first, 0);
    decoder->setMaxVertexFramesPerByte(maxVertexFramesPerByte);
    decoder->setMaxMeshMemoryPerByte(maxMeshMemoryPerByte);
    decoder->setMaxTexturePixelsPerByte(maxTexturePixelsPerByte);
    decoder->setPictureDecoder(pictures);
    decoder->setKeepAccessUnits(keepAccessUnits);
    nextIndex = first < 0 ? 0 : static_cast<uint32_t>(first - info.firstFrame);
    gom = GomCursor();
    decoder->readHeader();
    headerRead = true;
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
  if (!s_->arriving) s_->restart(-1);
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

Decoder Decoder::openArriving(const std::string& name) {
  auto state = std::make_unique<State>();
  state->name = name;
  state->arriving = std::make_unique<ArrivingStream>(name);
  return Decoder(std::move(state));
}

namespace {

void checkArriving(const std::unique_ptr<ArrivingStream>& arriving, const char* what) {
  if (!arriving)
    throw Error(std::string("Decoder::") + what + ": only for a stream opened with openArriving");
}

}  // namespace

void Decoder::append(const uint8_t* data, size_t size) {
  checkArriving(s_->arriving, "append");
  s_->arriving->append(data, size);
}

void Decoder::finish() {
  checkArriving(s_->arriving, "finish");
  s_->arriving->finish();
}

uint64_t Decoder::bytesArrived() const {
  return s_->arriving ? s_->arriving->size() : s_->size;
}

bool Decoder::headerArrived() {
  State& s = *s_;
  if (s.headerRead) return true;
  const ArrivingStream& a = *s.arriving;
  if (!a.finished() && !a.scanBlocked() && (a.units().empty() || !a.arrived(a.units()[0].end())))
    return false;
  s.restart(-1);
  return true;
}

bool Decoder::canDecodeNext() {
  State& s = *s_;
  if (!s.arriving) return true;
  if (!headerArrived()) return false;
  const ArrivingStream& a = *s.arriving;
  if (a.finished()) return true;
  // After the last frame, next() checks that nothing follows it: that needs the end.
  if (s.nextIndex >= s.info.frameCount) return false;
  if (a.scanBlocked()) return true;  // a unit_size over the limit: next() reports it
  // From the GOM header the last call stopped at: next() only moves the next frame on (and
  // restart() starts again), so a GOM that ends before it is passed for good.
  const std::vector<ArrivingStream::UnitStart>& headers = a.gomHeaders();
  State::GomCursor& gom = s.gom;
  for (; gom.at < headers.size(); ++gom.at, gom.read = false) {
    const ArrivingStream::UnitStart& u = headers[gom.at];
    if (!a.arrived(u.end())) return false;
    if (!gom.read) {
      gom.read = true;
      try {
        GomHeader gh;
        ByteReader reader(a.payload(u), u.size, s.name, u.offset);
        transfer(reader, gh);
        gom.first = gh.gh_first_frame;
        gom.end = uint64_t{gh.gh_first_frame} + gh.gh_frame_count;
      } catch (const Error&) {
        gom.malformed = true;
      }
    }
    if (gom.malformed) return true;  // a malformed GOM header: next() reports it
    if (gom.end <= s.nextIndex) continue;
    if (gom.first > s.nextIndex) return true;  // not the expected GOM: next() says so
    // The GOM holding the next frame: its units all lie before the next GOM header (a decoder
    // that finds it out of place reads no further).
    return gom.at + 1 < headers.size() && a.arrived(headers[gom.at + 1].end());
  }
  return false;
}

const StreamInfo& Decoder::info() const {
  if (!s_->headerRead) throw Error(s_->name + ": the sequence header has not arrived yet");
  return s_->info;
}

std::string Decoder::headerHashLine() const {
  if (!s_->headerRead) throw Error(s_->name + ": the sequence header has not arrived yet");
  return sequenceHeaderHashLine(s_->decoder->sequenceHeader());
}

void Decoder::setPictureDecoder(PictureDecoderFactory factory) {
  s_->pictures = std::move(factory);
  if (s_->decoder) s_->decoder->setPictureDecoder(s_->pictures);
}

void Decoder::setTextureAccessUnits(bool keep) {
  s_->keepAccessUnits = keep;
  if (s_->decoder) s_->decoder->setKeepAccessUnits(keep);
}

void Decoder::setMaxVertexFramesPerByte(uint64_t limit) {
  s_->maxVertexFramesPerByte = limit;
  if (s_->decoder) s_->decoder->setMaxVertexFramesPerByte(limit);
}

void Decoder::setMaxMeshMemoryPerByte(uint64_t limit) {
  s_->maxMeshMemoryPerByte = limit;
  if (s_->decoder) s_->decoder->setMaxMeshMemoryPerByte(limit);
}

void Decoder::setMaxTexturePixelsPerByte(uint64_t limit) {
  s_->maxTexturePixelsPerByte = limit;
  if (s_->decoder) s_->decoder->setMaxTexturePixelsPerByte(limit);
}

bool Decoder::next(DecodedFrame& frame) {
  State& s = *s_;
  if (!canDecodeNext())
    throw Error(s.name + ": frame " + std::to_string(s.info.frameNumber(s.nextIndex)) +
                " has not arrived yet (" + std::to_string(bytesArrived()) +
                " bytes so far; wait for canDecodeNext())");
  // The texture units are read by a second reader of the same stream (StreamDecoder::pullFrame).
  if ((s.pictures || s.keepAccessUnits) && !s.info.cameras.empty() && !s.textureUnits)
    s.textureUnits = s.source();
  if (s.error) throw Error(*s.error);
  uint32_t index = 0;
  const IntMesh* mesh = nullptr;
  try {
    if (!s.decoder->pullFrame(index, mesh, s.textureUnits.get(), &frame.textures)) return false;
  } catch (const Error& e) {
    s.error = e.what();
    throw;
  }
  frame.index = index;
  frame.number = s.info.frameNumber(index);
  s.nextIndex = index + 1;
  frame.mesh = *mesh;  // positions, triangles, texture coordinates and normals
  frame.positions.resize(mesh->positions.size());
  for (size_t v = 0; v < mesh->positions.size(); ++v)
    frame.positions[v] = s.info.grid.dequantise(mesh->positions[v]);
  return true;
}

const std::vector<int64_t>& Decoder::gomStarts() {
  State& s = *s_;
  if (s.gomStartsComplete) return s.gomStarts;
  info();  // the header must have arrived
  if (s.startsError) throw Error(*s.startsError);
  // An arriving stream, before finish(): the units that have arrived.
  const bool partial = s.arriving && !s.arriving->finished();
  const auto more = [&] {
    if (!partial) return true;
    const auto& arrived = s.arriving->units();
    return s.startsRead < arrived.size() && s.arriving->arrived(arrived[s.startsRead].end());
  };
  try {
    if (!s.startsUnits) s.startsUnits = s.source();
    UnitView unit;
    while (more() && s.startsUnits->next(unit)) {
      ++s.startsRead;
      if (unit.type != static_cast<uint8_t>(UnitType::kGomHeader)) continue;
      GomHeader gh;
      ByteReader reader(unit.payload, unit.size, s.name + ": " + unit.describe(),
                        unit.payloadOffset);
      transfer(reader, gh);
      reader.expectEnd("the GOM header");
      if (gh.gh_random_access) s.gomStarts.push_back(s.info.frameNumber(gh.gh_first_frame));
    }
  } catch (const Error& e) {
    // The units before the bad one do not change: a new reading would stop here again.
    s.startsError = e.what();
    s.startsUnits.reset();
    throw;
  }
  if (!partial) {
    s.gomStartsComplete = true;
    s.startsUnits.reset();
  }
  return s.gomStarts;
}

void Decoder::seek(int64_t frameNumber) {
  const StreamInfo& info = this->info();
  const int64_t last = info.firstFrame + info.frameCount - 1;
  if (frameNumber < info.firstFrame || frameNumber > last)
    throw Error(s_->name + ": cannot seek to frame " + std::to_string(frameNumber) +
                ": the stream's frames are " + std::to_string(info.firstFrame) + " .. " +
                std::to_string(last));
  s_->restart(frameNumber);
}

}  // namespace tdvo
