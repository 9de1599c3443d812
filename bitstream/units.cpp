#include "bitstream/units.h"

#include <zlib.h>

#include <cstring>

#include "common/error.h"

namespace tdvo {

namespace {

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
  if (size < 4 || std::memcmp(data, kStreamMagic, 4) != 0)
    throw Error(name_ + ": not a 3DVO stream (the first four bytes are not \"3DVO\")");
}

bool UnitReader::next(UnitView& unit) {
  if (pos_ == size_) return false;
  unit = UnitView();
  unit.index = index_++;
  unit.offset = pos_;
  const std::string where =
      name_ + ": unit " + std::to_string(unit.index) + " at byte " + std::to_string(pos_);
  if (size_ - pos_ < kUnitHeaderSize)
    throw Error(where + ": stream ends inside the unit header (truncated stream)");
  unit.type = data_[pos_];
  unit.size = readU32(data_ + pos_ + 1);
  const std::string typed = where + " (" + unitTypeName(unit.type) + ")";
  if (unit.size > kMaxUnitSize)
    throw Error(typed + ": unit_size " + std::to_string(unit.size) + " exceeds the 1 GiB limit");
  if (size_ - pos_ - kUnitHeaderSize < uint64_t{unit.size} + 4)
    throw Error(typed + ": unit_size " + std::to_string(unit.size) +
                " runs past the end of the stream (truncated or corrupted stream)");
  unit.payload = data_ + pos_ + kUnitHeaderSize;
  unit.payloadOffset = pos_ + kUnitHeaderSize;
  const uint32_t stored = readU32(unit.payload + unit.size);
  if (stored != unitCrc(data_ + pos_, unit.payload, unit.size))
    throw Error(typed + ": CRC mismatch (corrupted stream)");
  pos_ += kUnitOverhead + unit.size;
  return true;
}

}  // namespace tdvo
