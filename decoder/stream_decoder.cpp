#include "decoder/stream_decoder.h"

#include <algorithm>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <optional>

#include "bitstream/attributes_syntax.h"
#include "bitstream/camera_parameters.h"
#include "bitstream/order_syntax.h"
#include "bitstream/units.h"
#include "common/core/error.h"
#include "common/core/ordered_parallel.h"
#include "decoder/gom_decoder.h"
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

// "a TEXTURE unit", "an I_MESH unit": a unit type in messages.
std::string aUnit(UnitType type) {
  const std::string name = unitTypeName(static_cast<uint8_t>(type));
  return (std::string("AEIOU").find(name[0]) == std::string::npos ? "a " : "an ") + name + " unit";
}

template <class T>
T parseUnit(const UnitView& unit, const std::string& name, std::FILE* trace,
            const char* structure) {
  T value;
  parseUnitInto(unit, name, trace, structure, value);
  return value;
}

// The units a GOM's texture pass makes its frames again from: what the geometry pass kept of
// the GOM's geometry, the P-mesh payloads (intra GOMs: the Draco payloads). They are bounded by
// the stream's bytes, and decoded without error in the geometry pass, so they decode the same
// here. P-mesh GOMs start from the geometry pass's first reference (GomDecoder::firstReference).
struct KeptUnits : GomUnits {
  int gridBits = 0;
  std::string where;  // the GOM header (for messages; none is expected)
  std::vector<std::vector<uint8_t>> payloads;
  std::vector<uint16_t> iMeshQuantSteps;  // of each I mesh among the payloads, in order
  size_t taken = 0;

  void iMesh(uint32_t, IntMesh& mesh, std::string& meshWhere) override {
    // Its counts passed the mesh-memory limit when the geometry pass read it.
    mesh = decodeIMesh(payloads[taken], gridBits, where, 0, 0, iMeshQuantSteps.at(taken));
    payloads[taken++] = std::vector<uint8_t>();  // each is decoded once
    meshWhere = where;
  }
  PMeshPayload pMesh(uint32_t) override {
    const std::vector<uint8_t>& p = payloads[taken++];
    return {p.data(), p.size(), where, nullptr};
  }
};

}  // namespace

// One run of StreamDecoder::decode: the stream's units in order, GOM by GOM. Each GOM's
// geometry is made by a GomDecoder, which asks this class (its GomUnits) for the I and P meshes
// as it needs them; with cameras, a second GomDecoder makes the GOM's frames again, a few at a
// time, for its texture units (docs/robustness.md, "Memory").
class StreamDecoder::Decoding : public GomUnits {
 public:
  // `pull`: driven by pull() (StreamDecoder::pullFrame), else by run().
  Decoding(StreamDecoder& decoder, const FrameCallback& onFrame, const TextureCallback& onTexture,
           const TextureCallback& prepareTexture, bool pull = false)
      : d_(decoder),
        sh_(decoder.sh_),
        name_(decoder.name_),
        trace_(decoder.trace_),
        onFrame_(onFrame),
        onTexture_(onTexture),
        prepareTexture_(prepareTexture),
        pull_(pull) {
    if (!d_.source_) inMemory_.emplace(d_.data_, d_.size_, name_);
    units_ = d_.source_ ? d_.source_ : &*inMemory_;
  }

  void run() {
    d_.gomStarts_.clear();
    readSequenceHeader();
    while (nextFrame_ < sh_.sh_frame_count) {
      if (nextFrame_ >= outEnd_) return;  // the range is decoded: the rest is not read
      decodeGom();
    }
    expectEnd();
  }

  // Pull-style: reads the sequence header (once), then each call makes one frame.
  void begin() {
    if (begun_) return;
    d_.gomStarts_.clear();
    readSequenceHeader();
    begun_ = true;
  }
  bool pull(uint32_t& frame, const IntMesh*& mesh, UnitSource* textureUnits,
            std::vector<DecodedTexture>* textures);

 private:
  // ---- The steps ----
  void readSequenceHeader();
  void setFrameRange();
  void setUpCameras();
  void decodeGom();
  GomHeader readGomHeader();
  void skipGom(const GomHeader& gh);
  void startGeometry(const GomHeader& gh);
  void decodeGeometry(const GomHeader& gh);
  void decodeTextures(const GomHeader& gh);
  YuvPicture decodePicture(size_t c, const TextureUnit& tx, const std::string& where);
  void startPulledTextures(UnitSource& textureUnits);
  void pullTextures(uint32_t frame, const std::vector<Vec3i>& positions,
                    std::vector<DecodedTexture>& textures, bool output);
  void expectEnd();
  void emit(uint32_t frame, const std::vector<Vec3i>& positions);
  void makeOutput(const std::vector<Vec3i>& positions);

  // ---- Units and limits ----
  void expectUnit(UnitType type, const std::string& when) {
    expectUnit(*units_, unit_, type, when);
  }
  void expectUnit(UnitSource& from, UnitView& unit, UnitType type, const std::string& when);
  std::string frameName(uint64_t k, const std::string& of = "") const;
  std::string gomName(const GomHeader& gh) const {
    return "the GOM at " + frameName(gh.gh_first_frame);
  }
  void skipTextures(const GomHeader& gh);
  IntMesh readIMesh(uint32_t frame, uint32_t frames);
  void readAttributes(uint32_t frame);
  void limitDecodingWork(uint32_t frames, size_t vertices);
  void limitTextureWork(const std::string& where, size_t c, uint64_t bytesRead);
  bool inRange(uint64_t frame) const { return frame >= outFirst_ && frame < outEnd_; }

  class TexturePass;

  // ---- GomUnits: the geometry pass reads the GOM's units from the stream ----
  void iMesh(uint32_t k, IntMesh& mesh, std::string& where) override {
    mesh = readIMesh(gomFirst_ + k, mode_ == PMeshMode::kIntra ? 1 : gomFrames_);
    where = name_ + ": " + unit_.describe();
  }
  PMeshPayload pMesh(uint32_t k) override;

  StreamDecoder& d_;
  SequenceHeader& sh_;
  const std::string& name_;
  std::FILE* const trace_;
  const FrameCallback& onFrame_;
  const TextureCallback& onTexture_;
  const TextureCallback& prepareTexture_;
  const bool pull_;
  std::optional<UnitReader> inMemory_;
  UnitSource* units_ = nullptr;
  UnitView unit_;  // the unit read last

  uint32_t outFirst_ = 0, outEnd_ = 0;  // the frame range (setFrameRange) as stream frames
  uint32_t nextFrame_ = 0;
  uint64_t declaredOutput_ = 0;  // vertex-frames, summed over the I meshes so far

  // The GOM being decoded.
  std::string gomWhere_;
  PMeshMode mode_ = PMeshMode::kIntra;
  uint32_t gomFirst_ = 0, gomFrames_ = 0;
  GomDecoder gom_;
  PMeshUnit pm_;       // the last P mesh read (its buffers reused GOM after GOM)
  KeptUnits kept_;     // the GOM's geometry payloads, for the texture pass
  GomDecoder replay_;  // the texture pass's frames

  // Frames are decoded in coding order and output in the order of the last VERTEX_ORDER unit.
  MeshOrder order_;
  DecodedAttributes attributes_;  // of the last ATTRIBUTES unit (none before one)
  IntMesh output_;

  // Pull-style decoding: the GOM whose frames pull() is making.
  bool begun_ = false, gomOpen_ = false, ended_ = false;
  GomHeader gh_;
  UnitSource* textureUnits_ = nullptr;  // the GOM's texture units, when pulled with its frames
  UnitView textureUnit_;
  // With setKeepAccessUnits: per camera, the access units of the frames decoded so far without
  // output in the GOM (after a seek into it), for its first output frame.
  std::vector<std::vector<std::vector<uint8_t>>> pendingAccessUnits_;

  // Textures.
  std::vector<MaskRenderer> cameras_;
  std::vector<std::unique_ptr<PictureDecoder>> textureDecoders_;  // made with a camera's first unit
  std::vector<uint64_t> cameraPixels_;  // the larger of a camera's frame and texture box
  uint64_t texturePixels_ = 0;          // the camera pixels of the texture units so far
  Grid textureGrid_;
};

void StreamDecoder::Decoding::expectUnit(UnitSource& from, UnitView& unit, UnitType type,
                                         const std::string& when) {
  if (!from.next(unit))
    throw Error(name_ + ": stream ends " + when + " (expected " + aUnit(type) +
                "; truncated stream)");
  if (unit.type != static_cast<uint8_t>(type))
    throw Error(name_ + ": " + unit.describe() + ": expected " + aUnit(type) + " " + when);
}

// Stream frame k as the user knows it, in the messages that name a frame: its input frame
// number (sh_first_frame + k, as in the MD5 lines and the output files), with the stream's own
// index beside it when they differ: "frame 5 (stream frame 4)"; `of` follows the index
// (" of 20"). The syntax elements' values (im_frame, gh_first_frame, ...) stay stream indices.
std::string StreamDecoder::Decoding::frameName(uint64_t k, const std::string& of) const {
  const uint64_t number = uint64_t{sh_.sh_first_frame} + k;
  if (number == k) return "frame " + std::to_string(k) + of;
  return "frame " + std::to_string(number) + " (stream frame " + std::to_string(k) + of + ")";
}

void StreamDecoder::Decoding::expectEnd() {
  if (units_->next(unit_))
    throw Error(name_ + ": " + unit_.describe() + ": unit after the last frame (sh_frame_count " +
                std::to_string(sh_.sh_frame_count) + ")");
}

void StreamDecoder::Decoding::readSequenceHeader() {
  expectUnit(UnitType::kSequenceHeader, "at the start");
  sh_ = parseUnit<SequenceHeader>(unit_, name_, trace_, "the sequence header");
  setFrameRange();
  setUpCameras();
}

// The frame range (setFrameRange) as stream frames [outFirst_, outEnd_).
void StreamDecoder::Decoding::setFrameRange() {
  const int64_t firstNumber = sh_.sh_first_frame;
  const int64_t lastNumber = firstNumber + sh_.sh_frame_count - 1;
  const std::string streamFrames = "the stream's frames are " + std::to_string(firstNumber) +
                                   " .. " + std::to_string(lastNumber);
  outFirst_ = 0;
  outEnd_ = sh_.sh_frame_count;
  if (d_.rangeFirst_ >= 0) {
    if (d_.rangeFirst_ < firstNumber || d_.rangeFirst_ > lastNumber)
      throw Error(name_ + ": FirstFrame " + std::to_string(d_.rangeFirst_) +
                  " is not in the stream (" + streamFrames + ")");
    outFirst_ = static_cast<uint32_t>(d_.rangeFirst_ - firstNumber);
  }
  if (d_.rangeCount_ > 0) {
    const int64_t last = firstNumber + outFirst_ + d_.rangeCount_ - 1;
    if (last > lastNumber)
      throw Error(name_ + ": FirstFrame + FrameCount - 1 = " + std::to_string(last) +
                  " is past the stream's last frame (" + streamFrames + ")");
    outEnd_ = static_cast<uint32_t>(outFirst_ + d_.rangeCount_);
  }
}

void StreamDecoder::Decoding::setUpCameras() {
  textureDecoders_.resize(sh_.cameras.size());
  for (size_t c = 0; c < sh_.cameras.size(); ++c)
    cameras_.emplace_back(toCamera(sh_.cameras[c], static_cast<int>(c)));
  for (const CameraParameters& c : sh_.cameras) {
    const TextureBox box = textureBox(c);
    cameraPixels_.push_back(
        std::max(uint64_t{c.cam_width} * c.cam_height,
                 uint64_t{static_cast<uint32_t>(box.width)} * static_cast<uint32_t>(box.height)));
  }
  textureGrid_ = d_.grid();
  gom_.keepFirstReference(!cameras_.empty() && !pull_);
}

// The decoding-work limit (kDefaultMaxVertexFramesPerByte): `frames` more frames of a
// `vertices`-vertex I mesh, declared by the GOM being decoded; unit_ is that I mesh (or, in a
// GOM that continues the previous one, its header).
void StreamDecoder::Decoding::limitDecodingWork(uint32_t frames, size_t vertices) {
  declaredOutput_ += uint64_t{frames} * vertices;  // < 2^20 frames x 2^24 vertices: no overflow
  const uint64_t bytesRead = unit_.payloadOffset + unit_.size + 4;  // through the unit's CRC
  const uint64_t limit = d_.maxVertexFramesPerByte_;
  // declared > limit x bytes, without overflowing the product.
  if (limit == 0 || declaredOutput_ == 0 || (declaredOutput_ - 1) / bytesRead < limit) return;
  throw Error(gomWhere_ + ": " + std::to_string(frames) + " frames x " + std::to_string(vertices) +
              " vertices take the decoded output to " + std::to_string(declaredOutput_) +
              " vertex-frames from " + std::to_string(bytesRead) +
              " stream bytes, more than the limit of " + std::to_string(limit) +
              " vertex-frames per stream byte (MaxVertexFramesPerByte)");
}

// The texture-work limit (kDefaultMaxTexturePixelsPerByte): camera c's pixels, and the camera
// pixels of the texture units read so far; `bytesRead`: the stream through camera c's texture
// unit.
void StreamDecoder::Decoding::limitTextureWork(const std::string& where, size_t c,
                                               uint64_t bytesRead) {
  const uint64_t limit = d_.maxTexturePixelsPerByte_;
  if (limit == 0) return;
  const uint64_t pixels = cameraPixels_[c];
  const CameraParameters& cp = sh_.cameras[c];
  if (pixels > kTexturePixelsFree + kTexturePixelsPerByte * bytesRead)
    throw Error(where + ": camera " + std::to_string(c) + "'s " + std::to_string(cp.cam_width) +
                "x" + std::to_string(cp.cam_height) + " frames need more memory than " +
                std::to_string(bytesRead) + " stream bytes allow (" +
                std::to_string(kTexturePixelsFree) + " + " + std::to_string(kTexturePixelsPerByte) +
                " pixels per stream byte; MaxTexturePixelsPerByte)");
  texturePixels_ += pixels;  // < 2^20 frames x 64 cameras x 2^28 pixels: no overflow
  if ((texturePixels_ - 1) / bytesRead < limit) return;
  throw Error(where + ": texture units take the decoded camera pixels to " +
              std::to_string(texturePixels_) + " from " + std::to_string(bytesRead) +
              " stream bytes, more than the limit of " + std::to_string(limit) +
              " pixels per stream byte (MaxTexturePixelsPerByte)");
}

void StreamDecoder::Decoding::decodeGom() {
  const GomHeader gh = readGomHeader();
  // Before the range: the GOM's texture units are read (their types checked), not decoded.
  // Its geometry is skipped the same way in an intra GOM; a GOM of P meshes is decoded
  // without output, since the next GOM may continue it (no I mesh: not a random access
  // point).
  const bool beforeRange = uint64_t{gh.gh_first_frame} + gh.gh_frame_count <= outFirst_;
  if (beforeRange && gh.gh_pmesh_mode == static_cast<uint8_t>(PMeshMode::kIntra))
    return skipGom(gh);
  decodeGeometry(gh);
  if (beforeRange || cameras_.empty()) return skipTextures(gh);
  // Without a picture decoder (a geometry-only program) textures are read, not decoded, unless
  // the caller asked for them.
  if (d_.pictureDecoders_) return decodeTextures(gh);
  if (onTexture_ || prepareTexture_)
    throw Error(gomWhere_ +
                ": the stream has textures and this decoder has no picture decoder (give "
                "StreamDecoder::setPictureDecoder the texture component's makeH264Decoder)");
  skipTextures(gh);
}

GomHeader StreamDecoder::Decoding::readGomHeader() {
  const std::string when =
      "before " + frameName(nextFrame_, " of " + std::to_string(sh_.sh_frame_count));
  expectUnit(UnitType::kGomHeader, when);
  const GomHeader gh = parseUnit<GomHeader>(unit_, name_, trace_, "the GOM header");
  gomWhere_ = name_ + ": " + unit_.describe();
  if (gh.gh_first_frame != nextFrame_)
    throw Error(gomWhere_ + ": gh_first_frame " + std::to_string(gh.gh_first_frame) +
                " but the next frame is " + std::to_string(nextFrame_));
  if (uint64_t{gh.gh_first_frame} + gh.gh_frame_count > sh_.sh_frame_count)
    throw Error(gomWhere_ + ": GOM of " + std::to_string(gh.gh_frame_count) +
                " frames runs past sh_frame_count " + std::to_string(sh_.sh_frame_count));
  if (hasBMeshes(gh) && sh_.sh_syntax_version < kMinBMeshSyntaxVersion)
    throw Error(gomWhere_ + ": gh_pmesh_mode " + std::to_string(gh.gh_pmesh_mode) +
                " (B meshes) needs sh_syntax_version " + std::to_string(kMinBMeshSyntaxVersion) +
                ", the stream has " + std::to_string(sh_.sh_syntax_version));
  if (gh.gh_random_access) d_.gomStarts_.push_back(gh.gh_first_frame);
  return gh;
}

// An intra GOM before the frame range: its units are read, their types checked.
void StreamDecoder::Decoding::skipGom(const GomHeader& gh) {
  for (size_t k = 0; k < gh.gh_frame_count; ++k)
    for (UnitType type : {UnitType::kIMesh, UnitType::kVertexOrder, UnitType::kAttributes})
      if (type != UnitType::kAttributes || sh_.sh_attributes_present)
        expectUnit(type, "in " + gomName(gh));
  skipTextures(gh);
  nextFrame_ += gh.gh_frame_count;
  gom_.clearContinuation();
}

void StreamDecoder::Decoding::skipTextures(const GomHeader& gh) {
  for (size_t k = 0; k < size_t{gh.gh_frame_count} * sh_.cameras.size(); ++k) {
    expectUnit(UnitType::kTexture, "in " + gomName(gh));
    d_.textureBytes_ += kUnitOverhead + unit_.size;
  }
}

// The GOM's frames, in order, each handed out (emit) as it is made.
void StreamDecoder::Decoding::decodeGeometry(const GomHeader& gh) {
  startGeometry(gh);
  while (!gom_.done()) {
    const uint32_t frame = gomFirst_ + gom_.produced();
    emit(frame, gom_.next(*this));
  }
  nextFrame_ += gh.gh_frame_count;
}

// Starts the GOM's geometry: its frames are then made by gom_.next(*this).
void StreamDecoder::Decoding::startGeometry(const GomHeader& gh) {
  mode_ = codingMode(gh);
  gomFirst_ = gh.gh_first_frame;
  gomFrames_ = gh.gh_frame_count;
  gom_.start(gh, sh_.sh_grid_bits, gomWhere_);
  kept_ = KeptUnits();
  kept_.gridBits = sh_.sh_grid_bits;
  kept_.where = gomWhere_;
  // A GOM that continues the previous one declares its frames at its header.
  if (mode_ != PMeshMode::kIntra && !gh.gh_random_access)
    limitDecodingWork(gh.gh_frame_count, gom_.continuedVertices());
}

// `frames`: the frames made from this I mesh's vertices (the GOM's; 1 in an intra GOM).
IntMesh StreamDecoder::Decoding::readIMesh(uint32_t frame, uint32_t frames) {
  expectUnit(UnitType::kIMesh, "for " + frameName(frame));
  IMeshUnit im;
  im.syntaxVersion = sh_.sh_syntax_version;
  parseUnitInto(unit_, name_, trace_, "the I mesh", im);
  const std::string where = name_ + ": " + unit_.describe();
  if (im.im_frame != frame)
    throw Error(where + ": im_frame " + std::to_string(im.im_frame) + " but expected " +
                std::to_string(frame));
  // The mesh-memory limit (kDefaultMaxMeshMemoryPerByte), with the bytes through its CRC.
  IntMesh decoded =
      decodeIMesh(im.im_draco_payload, sh_.sh_grid_bits, where,
                  unit_.payloadOffset + unit_.size + 4, d_.maxMeshMemoryPerByte_, im.im_quant_step);
  limitDecodingWork(frames, decoded.positions.size());
  if (!cameras_.empty() && !pull_ && mode_ == PMeshMode::kIntra) {
    kept_.payloads.push_back(im.im_draco_payload);
    kept_.iMeshQuantSteps.resize(kept_.payloads.size(), 1);
    kept_.iMeshQuantSteps.back() = im.im_quant_step;
  }
  expectUnit(UnitType::kVertexOrder, "after the I mesh of " + frameName(frame));
  const VertexOrderUnit vo = parseUnit<VertexOrderUnit>(unit_, name_, trace_, "the vertex order");
  const std::string orderWhere = name_ + ": " + unit_.describe();
  if (vo.vo_frame != frame)
    throw Error(orderWhere + ": vo_frame " + std::to_string(vo.vo_frame) + " but expected " +
                std::to_string(frame));
  CabacReaderIo reader(vo.vo_cabac_payload.data(), vo.vo_cabac_payload.size(), orderWhere, trace_);
  order_.numVertices = vo.vo_num_vertices;
  codeMeshOrder(reader, decoded, order_, vo.vo_triangle_order != 0);
  reader.finish();
  output_.triangles = order_.triangles;
  if (sh_.sh_attributes_present) readAttributes(frame);
  return decoded;
}

// The ATTRIBUTES unit after the vertex order of frame `frame`'s I mesh (syntax version 3 with
// sh_attributes_present): the texture coordinates and normals of every frame made from it.
void StreamDecoder::Decoding::readAttributes(uint32_t frame) {
  expectUnit(UnitType::kAttributes, "after the vertex order of " + frameName(frame));
  AttributesUnit at;
  at.syntaxVersion = sh_.sh_syntax_version;
  // Values beyond the output's corners would be values no corner uses: their bound.
  at.maxValues = static_cast<uint32_t>(std::min<size_t>(3 * order_.triangles.size(), UINT32_MAX));
  parseUnitInto(unit_, name_, trace_, "the attributes", at);
  const std::string where = name_ + ": " + unit_.describe();
  if (at.at_frame != frame)
    throw Error(where + ": at_frame " + std::to_string(at.at_frame) + " but expected " +
                std::to_string(frame));
  CabacReaderIo reader(at.at_cabac_payload.data(), at.at_cabac_payload.size(), where, trace_);
  codeAttributes(reader, at, order_.numVertices, order_.triangles, attributes_);
  reader.finish();
}

PMeshPayload StreamDecoder::Decoding::pMesh(uint32_t k) {
  const uint32_t frame = gomFirst_ + k;
  expectUnit(UnitType::kPMesh, "for " + frameName(frame));
  parseUnitInto(unit_, name_, trace_, "the P mesh", pm_);
  const std::string where = name_ + ": " + unit_.describe();
  if (pm_.pm_frame != frame)
    throw Error(where + ": pm_frame " + std::to_string(pm_.pm_frame) + " but expected " +
                std::to_string(frame));
  if (!cameras_.empty() && !pull_) kept_.payloads.push_back(pm_.pm_cabac_payload);
  return {pm_.pm_cabac_payload.data(), pm_.pm_cabac_payload.size(), where, trace_};
}

// Output: a frame in the range, in the output order, to onFrame.
void StreamDecoder::Decoding::emit(uint32_t frame, const std::vector<Vec3i>& positions) {
  if (!inRange(frame)) return;
  makeOutput(positions);
  onFrame_(static_cast<int>(frame), output_);
}

// output_: a frame's positions (in the GOM's vertex order) in the output order, with the
// triangles and attributes of the I mesh it was made from.
void StreamDecoder::Decoding::makeOutput(const std::vector<Vec3i>& positions) {
  applyVertexOrder(order_, positions, output_.positions);
  applyAttributes(attributes_, output_);
}

// A GOM's texture pass. Item i = k * cameras + c is camera c's texture of the GOM's frame k.
// Whichever worker needs a unit reads the units up to it, in item order, under a lock; the
// pictures are decoded and the shapes rasterised on threads_ threads, at most `cameras` items
// started and not yet consumed: item i starts only once item i - cameras (the same camera's
// previous picture, through the same H.264 decoder) has been consumed. Callbacks and errors
// come in item order on the calling thread, as in a sequential run, for any thread count.
class StreamDecoder::Decoding::TexturePass {
 public:
  TexturePass(Decoding& run, uint32_t first, uint32_t frames)
      : run_(run), cameras_(run.cameras_.size()), first_(first), frames_(frames) {}

  void decode() {
    orderedParallelFor<Decoded>(
        size_t{frames_} * cameras_, run_.d_.threads_, cameras_,
        [&](size_t i) { return decodeItem(i); },
        [&](size_t i, Decoded& d) {
          const uint32_t frame = first_ + static_cast<uint32_t>(i / cameras_);
          if (run_.onTexture_ && run_.inRange(frame))
            run_.onTexture_(static_cast<int>(frame), static_cast<int>(i % cameras_), d.picture,
                            d.shape);
        });
  }

 private:
  struct Parsed {
    TextureUnit tx;
    std::string where;
  };
  struct Decoded {
    YuvPicture picture;
    Image shape;
  };
  // The GOM's frames, made again in order as the items ask for them: each is kept until every
  // camera's item has taken it (at most a few frames at a time).
  struct Made {
    std::shared_ptr<const Mesh> mesh;
    size_t taken = 0;
  };

  Decoded decodeItem(size_t i) {
    const Parsed p = readUnit(i);
    const size_t k = i / cameras_, c = i % cameras_;
    Decoded d;
    // Only this item uses camera c's decoder now: the camera's next item starts once this one
    // has been consumed.
    d.picture = run_.decodePicture(c, p.tx, p.where);
    d.shape = textureShape(*frameMesh(k), run_.cameras_[c]);
    const uint32_t frame = first_ + static_cast<uint32_t>(k);
    if (run_.prepareTexture_ && run_.inRange(frame))
      run_.prepareTexture_(static_cast<int>(frame), static_cast<int>(c), d.picture, d.shape);
    return d;
  }

  std::shared_ptr<const Mesh> frameMesh(size_t k) {
    std::lock_guard<std::mutex> lock(frameMutex_);
    GomDecoder& replay = run_.replay_;
    while (replay.produced() <= k) {
      const size_t f = replay.produced();
      const std::vector<Vec3i>& positions = replay.next(run_.kept_);
      auto mesh = std::make_shared<Mesh>();
      mesh->positions.reserve(positions.size());
      for (const Vec3i& q : positions)
        mesh->positions.push_back(run_.textureGrid_.dequantise(q));
      mesh->triangles = replay.triangles();
      made_[f].mesh = std::move(mesh);
    }
    auto it = made_.find(k);
    std::shared_ptr<const Mesh> mesh = it->second.mesh;
    if (++it->second.taken == cameras_) made_.erase(it);
    return mesh;
  }

  // Item i's texture unit, read (with the units before it) and checked.
  Parsed readUnit(size_t i) {
    std::lock_guard<std::mutex> lock(readMutex_);
    while (unitsRead_ <= i && !readError_) {
      try {
        readNextUnit();
      } catch (...) {
        readError_ = std::current_exception();
      }
    }
    if (unitsRead_ <= i) std::rethrow_exception(readError_);  // item i's own error comes first
    const auto it = parsed_.find(i);
    Parsed p = std::move(it->second);
    parsed_.erase(it);
    return p;
  }

  void readNextUnit() {
    const size_t c = unitsRead_ % cameras_;
    const uint32_t frame = first_ + static_cast<uint32_t>(unitsRead_ / cameras_);
    run_.expectUnit(UnitType::kTexture, "for the texture of camera " + std::to_string(c) + ", " +
                                            run_.frameName(frame));
    const UnitView& unit = run_.unit_;
    Parsed& p = parsed_[unitsRead_];
    p.tx = parseUnit<TextureUnit>(unit, run_.name_, run_.trace_, "the texture");
    run_.d_.textureBytes_ += kUnitOverhead + unit.size;
    p.where = run_.name_ + ": " + unit.describe();
    if (p.tx.tx_frame != frame || p.tx.tx_camera != c)
      throw Error(p.where + ": texture of camera " + std::to_string(p.tx.tx_camera) + ", frame " +
                  std::to_string(p.tx.tx_frame) + " but expected camera " + std::to_string(c) +
                  ", frame " + std::to_string(frame));
    run_.limitTextureWork(p.where, c, unit.end());
    ++unitsRead_;
  }

  Decoding& run_;
  const size_t cameras_;
  const uint32_t first_, frames_;
  std::mutex frameMutex_;
  std::map<size_t, Made> made_;
  std::mutex readMutex_;
  std::map<size_t, Parsed> parsed_;  // units read and not yet taken (a few: not the GOM's)
  size_t unitsRead_ = 0;             // units read so far
  std::exception_ptr readError_;     // what reading unit `unitsRead_` threw
};

// The texture pass makes the GOM's frames again: from the geometry pass's first reference (the
// I mesh, or the previous GOM's last frame that a continuing GOM's first P mesh is predicted
// from) and the kept P-mesh payloads, or in an intra GOM from the kept Draco payloads.
void StreamDecoder::Decoding::decodeTextures(const GomHeader& gh) {
  replay_.start(gh, sh_.sh_grid_bits, gomWhere_,
                mode_ == PMeshMode::kIntra ? nullptr : &gom_.firstReference());
  TexturePass(*this, gh.gh_first_frame, gh.gh_frame_count).decode();
}

// Camera c's picture of texture unit `tx` (`where` names it), through the camera's decoder.
YuvPicture StreamDecoder::Decoding::decodePicture(size_t c, const TextureUnit& tx,
                                                  const std::string& where) {
  const TextureBox box = textureBox(sh_.cameras[c]);
  std::unique_ptr<PictureDecoder>& decoder = textureDecoders_[c];
  if (!decoder) decoder = d_.pictureDecoders_(name_ + ": camera " + std::to_string(c));
  try {
    return decoder->decode(tx.tx_access_unit, box.width, box.height);
  } catch (const Error& e) {
    throw Error(where + ": " + e.what());
  }
}

// ---- Pull-style decoding (StreamDecoder::pullFrame) ----
// The GOM's frames are made one at a time, as they are asked for, by the same GomDecoder the
// push-style decode() uses. A GOM's texture units follow all its geometry units in the stream;
// to hand out each frame with its pictures without making the GOM's frames twice or keeping
// them, a second source over the same stream reads the texture units while units_ reads the
// geometry, and units_ passes over them (skipTextures) once the GOM is done.
bool StreamDecoder::Decoding::pull(uint32_t& frame, const IntMesh*& mesh, UnitSource* textureUnits,
                                   std::vector<DecodedTexture>* textures) {
  begin();
  if (textures) textures->clear();
  for (;;) {
    if (gomOpen_) {
      while (!gom_.done()) {
        const uint32_t f = gomFirst_ + gom_.produced();
        const std::vector<Vec3i>& positions = gom_.next(*this);
        // Frames before the range (in a GOM of P meshes before it, or in the range's first
        // GOM): decoded, not output; their pictures too, which later ones are predicted from.
        if (textureUnits_) pullTextures(f, positions, *textures, inRange(f));
        if (!inRange(f)) continue;
        makeOutput(positions);
        frame = f;
        mesh = &output_;
        return true;
      }
      gomOpen_ = false;
      nextFrame_ += gh_.gh_frame_count;
      skipTextures(gh_);
    }
    if (nextFrame_ >= sh_.sh_frame_count) {
      if (!ended_) expectEnd();
      ended_ = true;
      return false;
    }
    if (nextFrame_ >= outEnd_) return false;  // the range is decoded: the rest is not read
    gh_ = readGomHeader();
    const bool beforeRange = uint64_t{gh_.gh_first_frame} + gh_.gh_frame_count <= outFirst_;
    if (beforeRange && gh_.gh_pmesh_mode == static_cast<uint8_t>(PMeshMode::kIntra)) {
      skipGom(gh_);
      continue;
    }
    startGeometry(gh_);
    textureUnits_ = nullptr;
    if (!beforeRange && !cameras_.empty() && textureUnits && textures &&
        (d_.pictureDecoders_ || d_.keepAccessUnits_))
      startPulledTextures(*textureUnits);
    gomOpen_ = true;
  }
}

// Moves `textureUnits` to the GOM's first texture unit: past the geometry units that follow
// the GOM header just read (units_ checks them as it decodes them).
void StreamDecoder::Decoding::startPulledTextures(UnitSource& textureUnits) {
  textureUnits.seek(unit_.end(), unit_.index + 1);
  const std::string when = "in " + gomName(gh_);
  for (;;) {
    if (!textureUnits.next(textureUnit_))
      throw Error(name_ + ": stream ends " + when + " (expected " + aUnit(UnitType::kTexture) +
                  "; truncated stream)");
    const auto type = static_cast<UnitType>(textureUnit_.type);
    if (type == UnitType::kTexture) break;
    if (type != UnitType::kIMesh && type != UnitType::kVertexOrder &&
        type != UnitType::kAttributes && type != UnitType::kPMesh)
      throw Error(name_ + ": " + textureUnit_.describe() + ": expected " +
                  aUnit(UnitType::kTexture) + " " + when);
  }
  textureUnits.seek(textureUnit_.offset, textureUnit_.index);
  textureUnits_ = &textureUnits;
  pendingAccessUnits_.assign(cameras_.size(), {});
}

// Frame `frame`'s pictures, one per camera, from the GOM's texture units in order; `positions`
// (in the GOM's vertex order, with gom_.triangles()) make the shapes. Without `output` (a frame
// before the range) the pictures are decoded for the ones predicted from them, and no shape is
// made.
void StreamDecoder::Decoding::pullTextures(uint32_t frame, const std::vector<Vec3i>& positions,
                                           std::vector<DecodedTexture>& textures, bool output) {
  Mesh mesh;  // for the shapes
  if (output && d_.pictureDecoders_) {
    mesh.positions.reserve(positions.size());
    for (const Vec3i& q : positions)
      mesh.positions.push_back(textureGrid_.dequantise(q));
    mesh.triangles = gom_.triangles();
  }
  textures.resize(cameras_.size());
  for (size_t c = 0; c < cameras_.size(); ++c) {
    expectUnit(*textureUnits_, textureUnit_, UnitType::kTexture,
               "for the texture of camera " + std::to_string(c) + ", " + frameName(frame));
    TextureUnit tx = parseUnit<TextureUnit>(textureUnit_, name_, trace_, "the texture");
    const std::string where = name_ + ": " + textureUnit_.describe();
    if (tx.tx_frame != frame || tx.tx_camera != c)
      throw Error(where + ": texture of camera " + std::to_string(tx.tx_camera) + ", frame " +
                  std::to_string(tx.tx_frame) + " but expected camera " + std::to_string(c) +
                  ", frame " + std::to_string(frame));
    limitTextureWork(where, c, textureUnit_.end());
    DecodedTexture& t = textures[c];
    t.camera = static_cast<int>(c);
    t.box = textureBox(sh_.cameras[c]);
    t.picture = d_.pictureDecoders_ ? decodePicture(c, tx, where) : YuvPicture();
    t.shape = output && d_.pictureDecoders_ ? textureShape(mesh, cameras_[c]) : Image();
    t.accessUnits.clear();
    if (d_.keepAccessUnits_) {
      // Frames before the range keep theirs for the first output frame, which depends on them.
      std::vector<std::vector<uint8_t>>& pending = pendingAccessUnits_[c];
      pending.push_back(std::move(tx.tx_access_unit));
      if (output) t.accessUnits.swap(pending);
    }
  }
}

StreamDecoder::~StreamDecoder() = default;

void StreamDecoder::decode(const FrameCallback& onFrame, const TextureCallback& onTexture,
                           const TextureCallback& prepareTexture) {
  Decoding(*this, onFrame, onTexture, prepareTexture).run();
}

StreamDecoder::Decoding& StreamDecoder::pullRun() {
  static const FrameCallback noFrames;
  static const TextureCallback noTextures;
  if (!pull_) pull_ = std::make_unique<Decoding>(*this, noFrames, noTextures, noTextures, true);
  return *pull_;
}

void StreamDecoder::readHeader() {
  pullRun().begin();
}

bool StreamDecoder::pullFrame(uint32_t& frame, const IntMesh*& mesh, UnitSource* textureUnits,
                              std::vector<DecodedTexture>* textures) {
  return pullRun().pull(frame, mesh, textureUnits, textures);
}

}  // namespace tdvo
