// The 3DVO unit container.
//
//   stream := "3DVO" unit*
//   unit   := unit_type (u8) unit_size (u32 LE) payload[unit_size] unit_crc (u32 LE)
//
// unit_crc is the CRC-32 (zlib's crc32, ISO-HDLC polynomial) of unit_type, unit_size and the
// payload. Units are read whole and their CRC is checked before any payload byte is parsed.
#pragma once

#include <array>

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace tdvo {

enum class UnitType : uint8_t {
  kSequenceHeader = 1,
  kGomHeader = 2,
  kIMesh = 3,
  kPMesh = 4,
  kTexture = 5,
  kVertexOrder = 6,
  kAttributes = 7,  // syntax version 3 on
};

const char* unitTypeName(uint8_t type);

constexpr char kStreamMagic[4] = {'3', 'D', 'V', 'O'};
constexpr size_t kUnitHeaderSize = 5;  // unit_type + unit_size
constexpr size_t kUnitOverhead = kUnitHeaderSize + 4;
// No unit may be larger than this (a corrupt size field must not cause a huge allocation).
constexpr uint32_t kMaxUnitSize = 1u << 30;

// Appends units to a stream held in memory.
class UnitWriter {
 public:
  UnitWriter();
  void write(UnitType type, const std::vector<uint8_t>& payload);
  const std::vector<uint8_t>& bytes() const { return stream_; }
  // Bytes written so far per unit type (for the encoder's summary), indexed by the type value.
  uint64_t bytesOfType(UnitType type) const;

 private:
  std::vector<uint8_t> stream_;
  uint64_t typeBytes_[256] = {};
};

// One unit as found in a stream; `payload` points into the stream buffer.
struct UnitView {
  uint8_t type = 0;
  const uint8_t* payload = nullptr;
  uint32_t size = 0;
  uint64_t offset = 0;         // stream offset of the unit's first byte
  uint64_t payloadOffset = 0;  // stream offset of payload[0]
  size_t index = 0;            // 0-based unit number
  // "unit 3 (I_MESH) at byte 1234" — the prefix of every error about this unit.
  std::string describe() const;
  // The stream offset just past the unit (its CRC included): where the next unit starts.
  uint64_t end() const { return payloadOffset + size + 4; }
};

// Where a decoder gets its units from: a stream in memory (UnitReader) or a file read unit by
// unit (UnitFileReader). Both check and report alike.
class UnitSource {
 public:
  virtual ~UnitSource() = default;
  // Returns false at the end of the stream; throws Error on a truncated or corrupted unit. The
  // unit's payload stays valid until the next call.
  virtual bool next(UnitView& unit) = 0;
  // Makes the next unit the one at stream offset `offset`, numbered `index` in messages: a unit
  // start this source or another over the same stream returned (UnitView::end(), index + 1).
  // Sources that cannot go back throw Error.
  virtual void seek(uint64_t offset, size_t index);
};

// Walks the units of a stream held in memory. `name` (the file name) prefixes error messages.
class UnitReader : public UnitSource {
 public:
  UnitReader(const uint8_t* data, size_t size, std::string name);
  bool next(UnitView& unit) override;
  void seek(uint64_t offset, size_t index) override;
  const std::string& name() const { return name_; }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_;
  size_t index_ = 0;
  std::string name_;
};

// Reads the units of a stream file one at a time into a buffer it reuses, so that decoding
// needs memory for one unit, not for the whole stream: a decoder's memory does not grow with
// the length of the sequence. Same checks and messages as UnitReader; `name` prefixes them.
class UnitFileReader : public UnitSource {
 public:
  // Throws Error when the file cannot be opened or does not start with "3DVO".
  UnitFileReader(const std::string& path, std::string name);
  ~UnitFileReader() override;
  UnitFileReader(const UnitFileReader&) = delete;
  UnitFileReader& operator=(const UnitFileReader&) = delete;
  bool next(UnitView& unit) override;
  void seek(uint64_t offset, size_t index) override;
  uint64_t fileSize() const { return size_; }
  // The open file's identity and version: device, inode, size and modification time, which
  // change when the file is replaced or rewritten.
  std::array<uint64_t, 5> fileVersion() const;

 private:
  void read(uint8_t* to, size_t bytes);
  std::FILE* file_ = nullptr;
  uint64_t size_ = 0;
  uint64_t pos_ = 4;
  size_t index_ = 0;
  std::string name_;
  std::vector<uint8_t> unit_;  // the current unit: header, payload, CRC
};

// A stream whose bytes arrive in pieces, in order (a download): append() them as they come,
// finish() after the last. It keeps the bytes (the stream's size, no more) and the start of
// every unit whose header has arrived. Sources over it (source()) read units as UnitReader
// does; before finish(), a unit that has not wholly arrived is an error saying so (callers ask
// arrived() first), after it, a short stream is truncated exactly as UnitReader reports. A
// source copies each unit it returns, so that later appends do not move what it handed out.
class ArrivingStream {
 public:
  // A unit whose 5-byte header has arrived.
  struct UnitStart {
    uint8_t type = 0;
    uint32_t size = 0;
    uint64_t offset = 0;
    uint64_t end() const { return offset + kUnitOverhead + size; }
  };

  explicit ArrivingStream(std::string name);
  // Throws Error when the first four bytes are not "3DVO", or after finish().
  void append(const uint8_t* data, size_t size);
  void finish();
  bool finished() const { return finished_; }
  uint64_t size() const { return bytes_.size(); }
  const uint8_t* data() const { return bytes_.data(); }
  const std::string& name() const { return name_; }
  // Every unit whose header has arrived, in stream order. The scan stops at a unit_size over
  // the 1 GiB limit (scanBlocked(): the stream is bad there; a decoder reports it).
  const std::vector<UnitStart>& units() const { return units_; }
  // The GOM_HEADER units among them.
  const std::vector<UnitStart>& gomHeaders() const { return gomHeaders_; }
  bool scanBlocked() const { return blocked_; }
  // Whether the bytes before stream offset `end` have arrived (or the stream is finished).
  bool arrived(uint64_t end) const { return finished_ || end <= bytes_.size(); }
  // The payload of unit `u` (read in place: call arrived(u.end()) first); counted as a read.
  const uint8_t* payload(const UnitStart& u) const;
  std::unique_ptr<UnitSource> source() const;

 private:
  void scan();
  std::string name_;
  std::vector<uint8_t> bytes_;
  std::vector<UnitStart> units_, gomHeaders_;
  uint64_t scanned_ = 4;  // the next unit's offset
  bool blocked_ = false, finished_ = false;
};

// How many times units of arriving streams have been read, process-wide: one for each unit a
// source over one returns, and one for each ArrivingStream::payload(). A statistic for tests
// that bound the reading work by the stream's size (each unit read a bounded number of times).
uint64_t arrivingUnitsRead();

}  // namespace tdvo
