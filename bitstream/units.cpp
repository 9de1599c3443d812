#include "bitstream/units.h"

#include <sys/stat.h>

#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>

#include "common/core/error.h"
#include "common/core/file_io.h"

namespace tdvo {

namespace {

const char kNotA3dvoStream[] = ": not a 3DVO stream (the first four bytes are not \"3DVO\")";

uint32_t unitCrc(const uint8_t* header, const uint8_t* payload, uint32_t size) {
  uLong crc = crc32(0L, Z_NULL, 0);
  crc = crc32(crc, header, kUnitHeaderSize);
  // zlib's length type is uInt; payloads are bounded by kMaxUnitSize, which fits. An empty
  // payload is skipped: crc32() with a null buffer (an empty vector's data()) returns 0 instead
  // of the running CRC, so writer and reader would disagree.
  if (size > 0) crc = crc32(crc, payload, static_cast<uInt>(size));
  return static_cast<uint32_t>(crc);
}

uint32_t readU32(const uint8_t* p) {
  return uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24;
}

void appendU32(std::vector<uint8_t>& out, uint32_t v) {
  for (int i = 0; i < 4; ++i)
    out.push_back(static_cast<uint8_t>(v >> (8 * i)));
}

}  // namespace

const char* unitTypeName(uint8_t type) {
  switch (static_cast<UnitType>(type)) {
    case UnitType::kSequenceHeader:
      return "SEQUENCE_HEADER";
    case UnitType::kGomHeader:
      return "GOM_HEADER";
    case UnitType::kIMesh:
      return "I_MESH";
    case UnitType::kPMesh:
      return "P_MESH";
    case UnitType::kTexture:
      return "TEXTURE";
    case UnitType::kVertexOrder:
      return "VERTEX_ORDER";
    case UnitType::kAttributes:
      return "ATTRIBUTES";
  }
  return "unknown type";
}

UnitWriter::UnitWriter() {
  stream_.assign(kStreamMagic, kStreamMagic + 4);
}

void UnitWriter::write(UnitType type, const std::vector<uint8_t>& payload) {
  if (payload.size() > kMaxUnitSize) throw Error("unit payload larger than 1 GiB");
  const size_t start = stream_.size();
  stream_.push_back(static_cast<uint8_t>(type));
  appendU32(stream_, static_cast<uint32_t>(payload.size()));
  stream_.insert(stream_.end(), payload.begin(), payload.end());
  appendU32(stream_,
            unitCrc(&stream_[start], payload.data(), static_cast<uint32_t>(payload.size())));
  typeBytes_[static_cast<uint8_t>(type)] += stream_.size() - start;
}

uint64_t UnitWriter::bytesOfType(UnitType type) const {
  return typeBytes_[static_cast<uint8_t>(type)];
}

std::string UnitView::describe() const {
  return "unit " + std::to_string(index) + " (" + unitTypeName(type) + ") at byte " +
         std::to_string(offset);
}

UnitReader::UnitReader(const uint8_t* data, size_t size, std::string name)
    : data_(data), size_(size), pos_(4), name_(std::move(name)) {
  if (size < 4 || std::memcmp(data, kStreamMagic, 4) != 0) throw Error(name_ + kNotA3dvoStream);
}

namespace {

// How much of a unit a reader takes, when `available` bytes lie from the unit's start to the end
// of the stream (or of what has arrived of it) and `header` holds the first
// min(available, kUnitHeaderSize) of them.
struct UnitBytes {
  uint64_t present = 0;   // the whole unit, or as much of its header as there is
  bool complete = false;  // enough for parseUnit to judge: the whole unit, or a header whose
                          // unit_size exceeds the limit
};

UnitBytes unitBytesPresent(const uint8_t* header, uint64_t available) {
  if (available < kUnitHeaderSize) return {available, false};
  const uint32_t size = readU32(header + 1);
  if (size > kMaxUnitSize) return {kUnitHeaderSize, true};
  if (available - kUnitHeaderSize < uint64_t{size} + 4) return {kUnitHeaderSize, false};
  return {kUnitOverhead + size, true};
}

// Checks the unit at `at` (stream offset `offset`, `available` bytes from there to the end of
// the stream, of which at least the unit itself, or at least its header when the header is
// invalid, are at `at`) and describes it in `unit`.
void parseUnit(const uint8_t* at, uint64_t available, uint64_t offset, size_t index,
               const std::string& name, UnitView& unit) {
  unit = UnitView();
  unit.index = index;
  unit.offset = offset;
  const std::string where =
      name + ": unit " + std::to_string(unit.index) + " at byte " + std::to_string(offset);
  if (available < kUnitHeaderSize)
    throw Error(where + ": stream ends inside the unit header (truncated stream)");
  unit.type = at[0];
  unit.size = readU32(at + 1);
  const std::string typed = name + ": unit " + std::to_string(unit.index) + " (" +
                            unitTypeName(unit.type) + ") at byte " + std::to_string(offset);
  if (unit.size > kMaxUnitSize)
    throw Error(typed + ": unit_size " + std::to_string(unit.size) + " exceeds the 1 GiB limit");
  if (available - kUnitHeaderSize < uint64_t{unit.size} + 4)
    throw Error(typed + ": unit_size " + std::to_string(unit.size) +
                " runs past the end of the stream (truncated or corrupted stream)");
  unit.payload = at + kUnitHeaderSize;
  unit.payloadOffset = offset + kUnitHeaderSize;
  const uint32_t stored = readU32(unit.payload + unit.size);
  if (stored != unitCrc(at, unit.payload, unit.size))
    throw Error(typed + ": CRC mismatch (corrupted stream)");
}

}  // namespace

std::array<uint64_t, 5> UnitFileReader::fileVersion() const {
  struct stat st;
  if (::fstat(::fileno(file_), &st) != 0) return {0, 0, 0, 0, 0};
  return {uint64_t(st.st_dev), uint64_t(st.st_ino), uint64_t(st.st_size),
          uint64_t(st.st_mtim.tv_sec), uint64_t(st.st_mtim.tv_nsec)};
}

void UnitSource::seek(uint64_t, size_t) {
  throw Error("this unit source cannot seek (decode from a file or from memory)");
}

void UnitReader::seek(uint64_t offset, size_t index) {
  if (offset < 4 || offset > size_)
    throw Error(name_ + ": seek to byte " + std::to_string(offset) + " outside the stream");
  pos_ = static_cast<size_t>(offset);
  index_ = index;
}

bool UnitReader::next(UnitView& unit) {
  if (pos_ == size_) return false;
  parseUnit(data_ + pos_, size_ - pos_, pos_, index_++, name_, unit);
  pos_ += kUnitOverhead + unit.size;
  return true;
}

UnitFileReader::UnitFileReader(const std::string& path, std::string name) : name_(std::move(name)) {
  file_ = std::fopen(path.c_str(), "rb");
  if (!file_) throw Error(name_ + ": cannot open: " + std::strerror(errno));
  noteFileRead(file_);
  long end = -1;
  if (std::fseek(file_, 0, SEEK_END) == 0) end = std::ftell(file_);
  if (end < 0 || std::fseek(file_, 0, SEEK_SET) != 0) {
    const int error = errno;
    std::fclose(file_);
    // A stream is read unit by unit, with seeks (the texture units by a second reader).
    throw Error(name_ + ": cannot read: " + std::strerror(error) +
                (error == ESPIPE ? " (a pipe or terminal; decode from a regular file)" : ""));
  }
  size_ = static_cast<uint64_t>(end);
  uint8_t magic[4] = {0, 0, 0, 0};
  if (size_ >= 4) read(magic, 4);
  if (size_ < 4 || std::memcmp(magic, kStreamMagic, 4) != 0) {
    std::fclose(file_);
    throw Error(name_ + kNotA3dvoStream);
  }
}

UnitFileReader::~UnitFileReader() {
  std::fclose(file_);
}

void UnitFileReader::read(uint8_t* to, size_t bytes) {
  if (bytes > 0 && std::fread(to, 1, bytes, file_) != bytes)
    throw Error(name_ + ": read error at byte " + std::to_string(std::ftell(file_)) + ": " +
                (std::ferror(file_) ? std::strerror(errno) : "file shorter than it was"));
}

void UnitFileReader::seek(uint64_t offset, size_t index) {
  if (offset < 4 || offset > size_ || std::fseek(file_, static_cast<long>(offset), SEEK_SET) != 0)
    throw Error(name_ + ": cannot seek to byte " + std::to_string(offset));
  pos_ = offset;
  index_ = index;
}

bool UnitFileReader::next(UnitView& unit) {
  if (pos_ == size_) return false;
  const uint64_t available = size_ - pos_;
  // The header first: the payload is read only once its size has been found plausible.
  const size_t header = static_cast<size_t>(std::min<uint64_t>(available, kUnitHeaderSize));
  unit_.resize(header);
  read(unit_.data(), header);
  const uint64_t present = unitBytesPresent(unit_.data(), available).present;
  if (present > header) {
    unit_.resize(static_cast<size_t>(present));
    read(unit_.data() + header, static_cast<size_t>(present) - header);
  }
  parseUnit(unit_.data(), available, pos_, index_++, name_, unit);
  pos_ += kUnitOverhead + unit.size;
  return true;
}

// ---- ArrivingStream ----

namespace {

std::atomic<uint64_t> unitsRead{0};  // arrivingUnitsRead()

// Reads the units of an ArrivingStream, each copied into a buffer of its own.
class ArrivingUnitReader : public UnitSource {
 public:
  explicit ArrivingUnitReader(const ArrivingStream& stream) : stream_(stream) {}

  bool next(UnitView& unit) override {
    const uint64_t size = stream_.size();
    if (pos_ >= size && stream_.finished()) return false;
    const uint64_t available = size - pos_;
    const uint8_t* at = stream_.data() + pos_;
    const UnitBytes bytes = unitBytesPresent(at, available);
    // Before the end, a unit parseUnit cannot judge yet has not arrived yet; after it, it is a
    // short one, which parseUnit reports.
    if (!bytes.complete && !stream_.finished())
      throw Error(stream_.name() + ": unit " + std::to_string(index_) + " at byte " +
                  std::to_string(pos_) + " has not arrived yet (" + std::to_string(size) +
                  " bytes so far)");
    unit_.assign(at, at + bytes.present);
    unitsRead.fetch_add(1, std::memory_order_relaxed);
    parseUnit(unit_.data(), available, pos_, index_++, stream_.name(), unit);
    pos_ += kUnitOverhead + unit.size;
    return true;
  }

  void seek(uint64_t offset, size_t index) override {
    if (offset < 4 || offset > stream_.size())
      throw Error(stream_.name() + ": seek to byte " + std::to_string(offset) +
                  " outside the stream");
    pos_ = offset;
    index_ = index;
  }

 private:
  const ArrivingStream& stream_;
  uint64_t pos_ = 4;
  size_t index_ = 0;
  std::vector<uint8_t> unit_;
};

}  // namespace

ArrivingStream::ArrivingStream(std::string name) : name_(std::move(name)) {}

void ArrivingStream::append(const uint8_t* data, size_t size) {
  if (finished_) throw Error(name_ + ": bytes appended after the end of the stream");
  const size_t before = bytes_.size();
  bytes_.insert(bytes_.end(), data, data + size);
  if (before < 4 && bytes_.size() >= 4 && std::memcmp(bytes_.data(), kStreamMagic, 4) != 0) {
    bytes_.resize(before);
    throw Error(name_ + kNotA3dvoStream);
  }
  scan();
}

void ArrivingStream::finish() {
  finished_ = true;
  if (bytes_.size() < 4) throw Error(name_ + kNotA3dvoStream);
}

void ArrivingStream::scan() {
  while (!blocked_ && bytes_.size() >= 4 && scanned_ + kUnitHeaderSize <= bytes_.size()) {
    UnitStart u;
    u.type = bytes_[scanned_];
    u.size = readU32(&bytes_[scanned_ + 1]);
    u.offset = scanned_;
    if (u.size > kMaxUnitSize) {
      blocked_ = true;
      break;
    }
    units_.push_back(u);
    if (u.type == static_cast<uint8_t>(UnitType::kGomHeader)) gomHeaders_.push_back(u);
    scanned_ = u.end();  // may lie past what has arrived: the payload is still arriving
  }
}

const uint8_t* ArrivingStream::payload(const UnitStart& u) const {
  unitsRead.fetch_add(1, std::memory_order_relaxed);
  return bytes_.data() + u.offset + kUnitHeaderSize;
}

std::unique_ptr<UnitSource> ArrivingStream::source() const {
  if (finished_ && bytes_.size() < 4) throw Error(name_ + kNotA3dvoStream);
  return std::make_unique<ArrivingUnitReader>(*this);
}

uint64_t arrivingUnitsRead() {
  return unitsRead.load(std::memory_order_relaxed);
}

}  // namespace tdvo
